// `granflow study closures CASE.yaml` (docs/calibration.md, "Closure study"): which closures of
// the steady forward model do the DEM data prefer? CASE is a `kind: calibrate` case plus a
// top-level section
//
//     closures:
//       collisional.radial_distribution: [chialvo_sundaresan, torquato, carnahan_starling]
//       force_chains.enabled: [true, false]
//
// mapping choice or boolean keys of the model sections to lists of values. Every combination of
// the Cartesian product (first key varying slowest) is calibrated on the same DEM data with the
// case's fit.parameters, minus those that do not act in it (reported as dropped), and ranked by
// Akaike's information criterion. Under `mpirun -np N` the combinations are shared over the
// ranks (core/sweep_scheduler.hpp); rank 0 writes the study directory, identical to a serial run.
#pragma once

#include <spdlog/logger.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "analysis/calibration/calibration.hpp"
#include "core/case.hpp"

namespace granflow::calibration {

// Written into a study directory when it is created; --force deletes only directories holding it.
inline constexpr const char* closure_study_marker = ".granflow-study";

struct ClosureCombination {
  std::vector<std::string> values;             // one per ClosureStudy::keys ("torquato", "true")
  std::string label;                           // "radial_distribution=torquato, force_chains=true"
  std::vector<std::string> parameters;         // the case's fit.parameters that act here (fitted)
  std::vector<std::string> dropped;            // those that do not act here (not fitted)
  std::shared_ptr<const core::Case> run_case;  // the calibrate case with these options applied
};

struct ClosureStudy {
  std::filesystem::path file;
  std::string name;                            // `name:` of the case, else the file stem
  std::shared_ptr<const core::Schema> schema;  // the calibrate schema the cases refer to
  std::shared_ptr<const core::Case> base;      // the case without `closures:` (case.yaml)
  std::vector<std::string> keys;               // closures key paths, in file order
  std::vector<std::string> short_keys;         // for tables: radial_distribution, force_chains, ...
  std::vector<std::vector<std::string>> options;  // values listed for each key
  std::vector<std::string> parameters;            // fit.parameters as written in the case
  std::vector<Observable> observables;            // data.observables
  std::vector<ClosureCombination> combinations;   // Cartesian product, first key slowest
};

// Reads CASE, validates `closures:` (key paths, value names) and builds every combination with
// core::Case::parse and the overrides, running the calibrate kind's checks on each. Throws
// core::CaseError "file:line: key.path: expected ..." before anything runs.
ClosureStudy load_closure_study(const std::filesystem::path& file,
                                const std::vector<std::string>& overrides);

// The starting model of a calibrate case, as kind: calibrate builds it.
CalibratedModel start_model(const core::Case& c);

// Why a parameter does not act in a case ("" if it acts).
std::string dropped_because(const std::string& parameter, const core::Case& c);

// The DEM points of the case (data section) and the training / held-out split (holdout section),
// as kind: calibrate makes them. Throws core::CaseError.
using StudyData = CaseData;
StudyData read_study_data(const core::Case& c);

// Calibration of one combination.
struct ClosureFit {
  bool ok = false;
  std::string error;                             // why the fit failed (ok = false)
  std::vector<double> estimate, standard_error;  // ClosureCombination::parameters order
  std::vector<double> at_bound;                  // 1: the estimate is on a wall of its interval
  double chi2 = NAN, chi2_red = NAN, aic = NAN, aicc = NAN;
  int k = 0, dof = 0, residuals = 0, evaluations = 0, status = 0;
  bool identifiable = false, inside_domain = false;
  int no_steady_state =
      0;  // used points (fitted or held out) the model cannot carry at the estimate
  std::vector<double> holdout_rel_err, train_rel_err;  // per ClosureStudy::observables
};
ClosureFit fit_combination(const ClosureStudy& study, std::size_t index, const StudyData& data);

// The items joined by `separator` (table cells, key lists).
std::string join(const std::vector<std::string>& items, const std::string& separator);

// AIC = χ² + 2k (Akaike 1974; -2 ln L up to a constant for Gaussian errors of known σ).
double akaike(double chi2, int k);
// AICc = AIC + 2k(k+1)/(n-k-1), n residuals (Hurvich & Tsai 1989); NaN for n ≤ k + 1.
double akaike_corrected(double chi2, int k, int n);
// Indices of `fits` ordered by AIC, then χ²_red, then index; failed fits last.
std::vector<std::size_t> rank_fits(const std::vector<ClosureFit>& fits);

// ---- outputs (closure_study_output.cpp)
struct ClosureStudyResults {
  const ClosureStudy& study;
  const StudyData& data;
  const std::vector<ClosureFit>& fits;  // per combination
  std::vector<std::size_t> order;       // rank_fits(fits)
};
// closures.h5 (DEM points, smooth curves of the best three distinct combinations over I at the
// mean DEM σ_yy), closures.png (analysis/plots/plot_closures.py, started without a shell, when
// `plot`), then closures.csv, study.json and report.md, into `dir`. `started`: for study.wall_s.
void write_closure_study(const ClosureStudyResults& results, const std::filesystem::path& dir,
                         bool plot, spdlog::logger& log,
                         std::chrono::steady_clock::time_point started);

struct ClosureStudyCommand {
  std::filesystem::path case_file, out_dir;  // out_dir empty: runs/<case name>_closures
  std::vector<std::string> overrides;        // --set key.path=value
  bool force = false, quiet = false;
  bool plot = true;  // run analysis/plots/plot_closures.py for closures.png
};
// The whole subcommand on one rank of an mpirun (rank 0 without one): validation, the fits shared
// over the ranks, then on rank 0 closures.csv, report.md, study.json, closures.h5, closures.png
// and log.txt in the study directory. Returns the CLI exit code (2: bad input, printed as one
// line on rank 0). The caller ends an mpirun with MpiRanks::leave_run() on every rank.
int run_closure_study_command(const ClosureStudyCommand& command, int rank);

}  // namespace granflow::calibration
