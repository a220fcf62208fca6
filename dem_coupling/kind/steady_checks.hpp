// Is the steady window of a DEM point steady, and is it at the imposed normal stress? And, for
// strain.target_error, are its standard errors within the targets?
// Header-only: one definition for the kind's analysis of series.tsv (point_analysis.cpp) and for
// granflow-dem's stopping rule (driver/stopping_rule.cpp), which applies it to the same values
// while the run goes on; the statistics are statistics/steady_state.hpp.
//
// Drift: every reported observable (named as the steady.* keys: p = σ_yy, tau, p_mean = tr(P)/3,
// phi, e, T, Z, and mu through the linearised residual τ − μ σ_yy whose error is μ's) is cut
// into the two halves of the window
// series[start:]; z = (mean_2 − mean_1) / combined standard error (statistics::drift_test). The
// window is steady when every |z| <= 3 (max_drift): a stationary window fails on one observable
// with probability ~0.25 % (tests/analysis/test_correlated_error.cpp), on any of the eight
// (correlated) in ~1-2 % of runs; a drift of 12 standard errors of the window's mean over the
// window gives z ~ 3 on average.
// Target (constant normal stress): miss = (<σ_yy> − p0) / se(<σ_yy>); on target when |miss| <= 2.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "dem_coupling/deck/driver_parameters.hpp"
#include "statistics/steady_state.hpp"

namespace granflow::dem {

constexpr double max_drift = 3.0;        // |z| above this: not steady
constexpr double max_target_miss = 2.0;  // |miss| above this: off the imposed σ_yy
// Frozen: the steady T/(d γ̇)² below this. A sheared sample that collides has T/(dγ̇)² of order
// 0.01-10: kinetic theory's homogeneous shear gives f2/f3 >= 2 J/(15 (1-ε²)) >= 1/15 (dense
// limit, J -> (1+e)/2), and dense DEM flows have δv ~ d γ̇ I^(-1/2) or more; a gas started on the
// affine profile without fluctuations that never collides stays at ~1e-8.
constexpr double frozen_temperature = 1e-4;

struct SteadyCheck {
  std::vector<std::pair<std::string, double>> drift;  // observable, z (NaN: too short)
  double worst = 0.0;                                 // largest |z|
  std::string worst_name;
  bool reached = true;  // every |z| <= max_drift (and finite)
};

// The series of a point by series.tsv column name (SeriesTable::columns).
using SeriesColumns = std::map<std::string, std::vector<double>>;

// `mu_residual` is τ − μ σ_yy per sample (steady_window). Observables missing from the columns
// are skipped; a window of < 16 samples cannot be tested and is not steady.
inline SteadyCheck check_steady(const SeriesColumns& columns, std::size_t start,
                                const std::vector<double>& mu_residual) {
  SteadyCheck c;
  auto test = [&](const std::string& name, const std::vector<double>& series) {
    const double z = statistics::drift_test(std::span(series).subspan(start)).z;
    c.drift.emplace_back(name, z);
    if (!std::isfinite(z) || std::abs(z) > max_drift) c.reached = false;
    if (std::isfinite(z) && std::abs(z) >= c.worst) {
      c.worst = std::abs(z);
      c.worst_name = name;
    }
  };
  // Named as the steady.* keys: p is σ_yy (series sigma_yy), p_mean is tr(P)/3 (series p).
  constexpr std::pair<const char*, const char*> observables[] = {
      {"sigma_yy", "p"}, {"tau", "tau"}, {"p", "p_mean"}, {"phi", "phi"},
      {"e", "e"},        {"T", "T"},     {"Z", "Z"}};
  for (const auto& [column, name] : observables)
    if (columns.count(column)) test(name, columns.at(column));
  test("mu", mu_residual);
  return c;
}

// The steady window of a point and its main steady values:
//   start: the latest MSER-5 truncation of σ_yy, τ, φ, T (statistics::mser_truncation);
//   means and standard errors: statistics::correlated_mean of series[start:];
//   μ = <τ>/<σ_yy> (ratio of means), se(μ) = se(<τ − μ σ_yy>)/<σ_yy> (delta method, the
//   residual's batch means);
//   reached: no observable drifts (check_steady) and T/(d γ̇)² >= frozen_temperature, with
//   temperature_scale = (d γ̇)².
// Needs the columns sigma_yy, tau, phi, T with at least 8 rows.
struct SteadyWindow {
  std::size_t start = 0;
  statistics::MeanEstimate sigma, tau, phi, temperature;
  double mu = 0.0, mu_err = 0.0;
  std::vector<double> mu_residual;  // τ − μ σ_yy per sample (the whole series)
  double scaled_temperature = 0.0;  // <T>/(d γ̇)²
  bool frozen = false;
  SteadyCheck check;
  bool reached = false;
};

inline SteadyWindow steady_window(const SeriesColumns& columns, double temperature_scale) {
  SteadyWindow w;
  for (const char* name : {"sigma_yy", "tau", "phi", "T"})
    w.start = std::max(w.start, statistics::mser_truncation(columns.at(name), 5));
  auto steady_of = [&](const std::vector<double>& series) {
    return statistics::correlated_mean(std::span(series).subspan(w.start));
  };
  const auto& sigma = columns.at("sigma_yy");
  const auto& tau = columns.at("tau");
  w.sigma = steady_of(sigma);
  w.tau = steady_of(tau);
  w.mu = w.tau.mean / w.sigma.mean;
  w.mu_residual.resize(sigma.size());
  for (std::size_t i = 0; i < sigma.size(); ++i) w.mu_residual[i] = tau[i] - w.mu * sigma[i];
  w.mu_err = steady_of(w.mu_residual).standard_error / w.sigma.mean;
  w.phi = steady_of(columns.at("phi"));
  w.temperature = steady_of(columns.at("T"));
  w.scaled_temperature = w.temperature.mean / temperature_scale;
  w.frozen = !(w.scaled_temperature >= frozen_temperature);
  w.check = check_steady(columns, w.start, w.mu_residual);
  w.reached = w.check.reached && !w.frozen;
  return w;
}

// strain.target_error: the achieved error of each observable of target_observables
// (deck/driver_parameters.hpp), se(μ)/μ, se(φ), se(T)/T, and whether the targets are met. The
// targets are met at a check when the window is steady, every given target is met and it has at
// least min_target_samples samples, the least a fixed run may have (dem_kind.cpp,
// check_run_length); the run stops once they have been met at strain.confirm_checks consecutive
// checks (TargetConfirmation below).
constexpr std::size_t min_target_samples = 100;

struct TargetStatus {
  std::array<double, target_observables.size()> achieved{};
  std::array<bool, target_observables.size()> met{};  // achieved <= target (given targets only)
  bool all_met = false;  // steady, every given target met, >= min_target_samples
};

inline TargetStatus target_status(const SteadyWindow& w, const ErrorTargets& targets) {
  TargetStatus s;
  s.achieved = {w.mu_err / std::abs(w.mu), w.phi.standard_error,
                w.temperature.standard_error / std::abs(w.temperature.mean)};
  s.all_met = w.reached && w.mu_residual.size() >= min_target_samples;
  for (std::size_t k = 0; k < s.achieved.size(); ++k) {
    if (!(targets.error[k] > 0.0)) continue;
    s.met[k] = s.achieved[k] <= targets.error[k];  // false for a NaN error (too few batches)
    s.all_met = s.all_met && s.met[k];
  }
  return s;
}

// strain.confirm_checks: the run stops at the check where all_met has held at `needed`
// consecutive checks (a check that misses starts the count again). Stopping at the first check
// that meets the targets selects the runs whose estimated error happens to be low, so their true
// error exceeds the reported one; requiring the targets again at later checks, with more samples
// in the window, lets a low estimate be corrected before the run stops (measured on a synthetic
// AR(1) μ in tests/dem/test_target_error.cpp; docs/dem_dataset.md, "What 'met' means").
struct TargetConfirmation {
  int needed = default_confirm_checks;
  int held = 0;  // consecutive checks so far at which all_met

  // The status of the next check; true: stop here.
  bool update(const TargetStatus& status) {
    held = status.all_met ? held + 1 : 0;
    return held >= needed;
  }
};

}  // namespace granflow::dem
