// Weighted least-squares calibration of closure parameters of the continuum model against steady
// DEM simple-shear data (docs/calibration.md). The forward model is the steady REV simple shear at
// each DEM condition (steady_shear_model.hpp), the misfit
//
//     χ²(θ) = Σ_i Σ_k [(y_ik - f_k(θ; γ̇_i, p_i)) / σ_ik]²
//
// over the conditions i and the chosen observables k (μ, φ, T/(dγ̇)²) with the DEM standard
// errors σ_ik (batch means, docs/dem_dataset.md). Minimised by the shared weighted least squares
// (analysis/least_squares.hpp: Eigen's Levenberg-Marquardt with central-difference Jacobians,
// each parameter kept inside its interval by a logistic change of variables). Covariance of the
// estimates C = (Jᵀ W J)⁻¹, W = diag(1/σ²), J = ∂f/∂θ at the optimum (the transform's covariance
// propagated back to θ; not rescaled by χ²_red: the DEM error bars are taken as the noise level;
// χ²_red ≈ 1 checks it).
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "analysis/calibration/steady_shear_model.hpp"
#include "core/case.hpp"

namespace granflow::calibration {

// ---- parameters ------------------------------------------------------------------------------
// A fittable parameter: name (case option and summary key), where its value lives in a case file
// (empty: no case key exists, see docs/calibration.md), the open interval it must stay in.
struct ParameterSpec {
  std::string name;
  std::string case_key;  // e.g. "collisional.jamming_fraction"
  double lower, upper;
  std::string doc;
};
const std::vector<ParameterSpec>& parameter_specs();
const ParameterSpec& parameter_spec(const std::string& name);  // throws std::invalid_argument

// The model being calibrated: the shared sections plus the call-site factors. liquid_viscosity
// is the reference η0 for `liquid_viscosity_factor`.
struct CalibratedModel {
  continuum::MultiRegimeSettings settings;
  ModelFactors factors;
  double reference_liquid_viscosity = 1e-3;
};
double parameter_value(const CalibratedModel& model, const std::string& name);
void set_parameter(CalibratedModel& model, const std::string& name, double value);
// Value to write under the parameter's case key (η0 × factor for liquid_viscosity_factor).
double case_value(const CalibratedModel& model, const std::string& name);

// ---- observables and data --------------------------------------------------------------------
enum class Observable { friction, solid_fraction, scaled_temperature };
const std::vector<std::string>& observable_names();    // in enum order
Observable parse_observable(const std::string& name);  // throws std::invalid_argument
constexpr int observable_count = 3;

struct DataPoint {
  double shear_rate = 0;         // γ̇, 1/s
  double normal_stress = 0;      // measured steady σ_yy, Pa (the continuum's imposed p)
  double particle_friction = 0;  // μ_p of the condition (NaN: the material's)
  double inertial_number = 0;    // DEM I (reporting)
  // η0 of an immersed condition (/steady/viscosity, Pa s); NaN for a dry row or a dataset
  // without the column. The continuum is evaluated at this η0 × liquid_viscosity_factor.
  double liquid_viscosity = NAN;
  double value[observable_count] = {0, 0, 0};
  double error[observable_count] = {0, 0, 0};
  int source = 0;  // index of the file it came from
  int row = 0;     // row in that file's /steady table
};

struct DemDataset {
  std::vector<DataPoint> points;  // usable rows (finite values, positive error bars)
  double diameter = 0, particle_density = 0;
  std::vector<std::string> skipped;  // one line per skipped row, with the reason
};
// Reads /steady of a DEM result.h5 (schema v1, docs/dem_dataset.md). Throws std::runtime_error
// naming the file and dataset when it is not a DEM dataset.
DemDataset read_dem_dataset(const std::filesystem::path& file, int source_index);

// ---- fit -------------------------------------------------------------------------------------
SteadyShearState predict(const CalibratedModel& model, const DataPoint& point);
double predicted(const SteadyShearState& state, Observable observable);

struct FitResult {
  std::vector<std::string> names;
  Eigen::VectorXd initial, estimate, standard_error;
  Eigen::MatrixXd covariance, correlation;
  double chi2 = 0, chi2_initial = 0;
  int residual_count = 0, dof = 0;
  double chi2_red = 0;
  int evaluations = 0;       // forward-model sweeps over the data
  int status = 0;            // Eigen LevenbergMarquardt status code
  bool identifiable = true;  // Jᵀ W J of full rank
  // Per parameter: the estimate is on (within 1e-4 of its start's distance to) a wall of its
  // interval, i.e. the data want it beyond the bound; its error bar is then one-sided.
  std::vector<bool> at_bound;
  // No estimate on a wall and the model carries every condition there (false: the estimates are
  // a boundary value, not a minimum of χ²).
  bool inside_domain = true;
  Eigen::VectorXd normalised_residuals;  // (y - f)/σ at the estimate, point-major
};

// Fits `names` (each in parameter_specs()) starting from `start`, over `data` and `observables`.
// Throws std::invalid_argument with fewer residuals than parameters.
// starts > 1: also from starts - 1 starting points drawn around `start` (each parameter's
// logistic coordinate u moved by a standard normal draw, fixed seed, so reproducible), keeping
// the fit with the smallest χ²: a guard against the local minima of nonlinear models.
FitResult fit(const CalibratedModel& start, const std::vector<std::string>& names,
              const std::vector<DataPoint>& data, const std::vector<Observable>& observables,
              int max_evaluations = 4000, int starts = 1);
CalibratedModel apply(const CalibratedModel& start, const std::vector<std::string>& names,
                      const Eigen::VectorXd& values);

// ---- reading a calibrate or pair case ------------------------------------------------------
// "a b, c" -> {"a", "b", "c"} (fit.parameters, data.observables, data.files)
std::vector<std::string> split_names(const std::string& text);
// A data path: as given, then beside the case file, then in the source tree (as given if none
// exists: read_dem_dataset reports it).
std::filesystem::path resolve_data_path(const core::Case& c, const std::string& name);
// The model a case describes: its model sections (continuum::read_multi_regime_settings), the
// steady.* factors (continuum::steady_section), liquid.trulsson_alpha, and f_Λ from
// fit.fluctuation_dissipation_factor where the case has that key; the reference η0 is the
// case's liquid.viscosity.
CalibratedModel read_case_model(const core::Case& c);
// The DEM points of a calibrate case (data section: files, particle_friction filter, points) and
// the training / held-out split (holdout section). Throws core::CaseError located at the key.
struct CaseData {
  std::vector<DataPoint> used;
  std::vector<char> held;  // per used point: 1 = held out
  std::vector<DataPoint> training, holdout;
  std::vector<std::string> notes;  // skipped rows, material mismatches (for warnings)
  std::vector<std::string> files;  // "PATH: N usable conditions", one per file (for the log)
};
CaseData read_case_data(const core::Case& c);

// Mean over points of |f - y| / |y| for one observable (NaN if any prediction fails).
double mean_relative_error(const CalibratedModel& model, const std::vector<DataPoint>& data,
                           Observable observable);

}  // namespace granflow::calibration
