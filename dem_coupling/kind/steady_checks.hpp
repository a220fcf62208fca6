// Is the steady window of a DEM point steady, and is it at the imposed normal stress?
// Header-only (used by dem_kind.cpp's analyse_point; the statistics are analysis/steady_state).
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

#include <cmath>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "statistics/steady_state.hpp"
#include "dem_coupling/kind/series_table.hpp"

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

// `mu_residual` is τ − μ σ_yy per sample (dem_kind.cpp). Observables missing from the table are
// skipped; a window of < 16 samples cannot be tested and is not steady.
inline SteadyCheck check_steady(const SeriesTable& t, std::size_t start,
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
    if (t.columns.count(column)) test(name, t.at(column));
  test("mu", mu_residual);
  return c;
}

}  // namespace granflow::dem
