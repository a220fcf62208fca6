// `kind: dem` started from a prepared state (start.preparation: a `kind: dem_prepare` run
// directory; docs/transient_dem.md): the transient from rest at constant volume (the undrained
// test of a saturated sample, whose incompressible liquid keeps the volume) and its metrics.
//   p0: the prepared mean stress of the seed's packing (prepared.tsv);
//   peak τ and its strain: the largest τ sample;
//   liquefaction strain: the first strain where p = tr(P)/3 < f p0 (f = transient.
//     liquefaction_fraction, 0.05 by default, the seed paper's and the usual 5 % of p0); absent
//     (transient.liquefied = 0) when p never falls below it;
//   residual τ, p: mean over the samples of the last part of the run (strain >= (1 - r) γ_total,
//     r = transient.residual_fraction) with its correlated standard error
//     (statistics::correlated_mean), and p_final_over_p0 = residual p / p0.
// Several seeds (statistics.seeds): seed S starts from the preparation's seed_S packing; the
// series are reported as the mean and the band (min, max) over the seeds, sample by sample
// (/transient/group_G), the metrics as the mean over the seeds and its standard error.
#pragma once

#include <filesystem>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "core/case.hpp"
#include "core/run.hpp"
#include "dem_coupling/deck/shear_deck.hpp"
#include "dem_coupling/kind/rate_step_metrics.hpp"
#include "dem_coupling/kind/seed_statistics.hpp"

namespace granflow::dem {

struct TransientMetrics {
  double peak_tau = 0, peak_strain = 0;
  double liquefaction_strain = -1;  // -1: p never fell below the threshold
  double residual_tau = 0, residual_tau_err = 0, residual_p = 0, residual_p_err = 0;
  double p_final_over_p0 = 0;
};

TransientMetrics transient_metrics(std::span<const double> strain, std::span<const double> p,
                                   std::span<const double> tau, double p0,
                                   double liquefaction_fraction, double residual_fraction);

// The shear stopped (stop.duration > 0; driver/shear_stop.hpp): the agitation after the stop.
//   flowing T: the mean T over the residual window of the shear (strain >= (1 - r) γ_total);
//   cooling time: the first time after the stop at which T <= f × flowing T (f = stop.
//     cooling_fraction), interpolated in ln T between samples (from (0, flowing T)); -1: never;
//   final T / flowing T and final p' / p0: the last sample of the stop.
struct StopMetrics {
  double flowing_temperature = 0, cooling_time = -1, final_temperature_ratio = 0;
  double final_p_over_p0 = 0;
};

StopMetrics stop_metrics(std::span<const double> time_since_stop, std::span<const double> T,
                         std::span<const double> p, double flowing_temperature, double p0,
                         double cooling_fraction);

// A drained stop (stop.drainage_length > 0): the sample compacts under the normal stress σ_n.
//   reconsolidation time: the first time σ_yy >= f σ_n (f = stop.reconsolidation_fraction; the
//     excess pore pressure u = σ_n − σ_yy below (1 − f) σ_n), interpolated linearly between
//     samples (from (0, the first sample)); -1: never;
//   final φ and its change from the stop: the last sample against φ at the stop.
struct DrainedStopMetrics {
  double reconsolidation_time = -1, final_solid_fraction = 0, solid_fraction_change = 0;
};

DrainedStopMetrics drained_stop_metrics(std::span<const double> time_since_stop,
                                        std::span<const double> sigma_yy,
                                        std::span<const double> solid_fraction,
                                        double solid_fraction_at_stop, double normal_stress,
                                        double reconsolidation_fraction);

// Mean of `values` over the residual window (strain >= (1 - r) × the last strain).
double residual_mean(std::span<const double> strain, std::span<const double> values,
                     double residual_fraction);

// The prepared state of one seed: the restart file and the state it holds.
struct PreparedState {
  std::filesystem::path restart;
  double phi = 0, p = 0, sigma_yy = 0, particles = 0;
};

// Reads DIR/seed_S/prepared.tsv of start.preparation (resolved from the working directory, then
// beside the case file); a missing directory, one that is no dem_prepare run or one without this
// seed's state is a one-line case error naming start.preparation (exit 2).
PreparedState read_prepared_state(const core::Case& c, long seed);

// KindEntry::check_inputs of kind: dem: every condition and seed has its prepared state.
void check_preparation_inputs(const core::Case& run_case);

class TransientShear {
 public:
  explicit TransientShear(const core::Case& run_case);
  bool enabled() const { return enabled_; }
  // A prepared start: the restart, its particle count and φ, and T0 = 0 unless
  // control.initial_temperature is given. No-op without start.preparation.
  void apply(const core::Case& c, ShearDeckParams& p) const;
  // One finished point: the network series (Z_nr, nonrattler_fraction, fabric_xy, anisotropy)
  // under group/series, its metrics under group/transient and transient.NAME{suffix}.
  void absorb(core::RunContext& ctx, std::size_t n, const std::filesystem::path& dir,
              const std::string& group, const ShearDeckParams& p, const std::string& suffix);
  // Seed bands and means (/transient/group_G, transient.mean.NAME, transient.err.NAME) and the
  // plot.
  void finish(core::RunContext& ctx, const std::vector<Condition>& swept);

 private:
  struct Point {
    std::vector<double> strain;
    std::vector<std::vector<double>> band;  // one series per row of dem_columns::transient_band
    TransientMetrics metrics;
    double p0 = 0, phi0 = 0;
    std::vector<double> stop_time;               // since the stop (empty: no stop stage)
    std::vector<std::vector<double>> stop_band;  // as band, over the stop's rows
    StopMetrics stop;
    bool drained = false;           // the stop compacted under stop.normal_stress (drainage)
    double stop_normal_stress = 0;  // σ_n of a drained stop, Pa
    DrainedStopMetrics drained_stop;
    bool rate_step = false;  // the shear rate stepped (rate_step.strain)
    double step_strain = 0, step_rate = 0;
    RateStepMetrics stepped;
  };
  // The seed mean, lowest and highest seed of each dem_columns::transient_band column, row by
  // row (rows: the fewest any member has), as PREFIX + NAME_{mean,min,max}; `note` is added to
  // the descriptions.
  static void write_band(core::RunContext& ctx, const std::string& prefix,
                         const std::vector<const Point*>& members, std::size_t rows,
                         std::vector<std::vector<double>> Point::*series, const std::string& note);
  bool enabled_ = false;
  double fraction_ = 0.05, residual_ = 0.2, cooling_fraction_ = 0.1;
  double reconsolidation_fraction_ = 0.9;
  std::map<std::size_t, Point> points_;
};

}  // namespace granflow::dem
