// Seed-to-seed statistics of a DEM sweep over dem.seed (docs/dem_dataset.md, "Error bars").
// A point's standard errors (statistics::correlated_mean) hold the sampling noise of one run only;
// two samples drawn with different seeds differ by more near jamming (e.g. σ_yy 102 ± 15 and
// 64.5 ± 4 Pa at φ 0.578). A sweep that lists dem.seed (`--set 'sweep.dem.seed=[1,2,3,4]'`)
// is grouped by its other swept keys, and per group and observable x over the N seeds with a
// steady value:
//   mean  = (1/N) Σ x_s                         (equal weights: every seed is one sample)
//   error = s / √N,  s² = Σ (x_s − mean)² / (N − 1)   (between-seed standard deviation: within-run
//           noise and sample-to-sample scatter together; Student t with N − 1 dof for intervals)
//   within = sqrt((1/N) Σ se_s²) / √N           (what the per-run error bars alone would give)
//   scatter_ratio = error / within             (≈ 1 when the per-run error bars are complete;
//           its own uncertainty is ~1/sqrt(2 (N − 1)), i.e. ±50 % for 3 seeds)
// Header-only (dem_kind.cpp; tests/dem/test_seed_statistics.cpp).
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace granflow::dem {

using Condition = std::vector<std::pair<std::string, double>>;  // swept key -> value

struct SeedGroup {
  Condition condition;               // the swept keys other than dem.seed
  std::vector<std::size_t> members;  // indices of the conditions (one per seed)
};

// Groups of conditions that differ only in dem.seed, in order of first appearance; empty when
// dem.seed is not swept.
inline std::vector<SeedGroup> group_by_seed(const std::vector<Condition>& conditions) {
  std::vector<SeedGroup> groups;
  bool seeded = false;
  for (const Condition& c : conditions)
    for (const auto& [key, value] : c) seeded = seeded || key == "dem.seed";
  if (!seeded) return groups;
  for (std::size_t n = 0; n < conditions.size(); ++n) {
    Condition rest;
    for (const auto& kv : conditions[n])
      if (kv.first != "dem.seed") rest.push_back(kv);
    std::size_t g = 0;
    while (g < groups.size() && groups[g].condition != rest) ++g;
    if (g == groups.size()) groups.push_back({rest, {}});
    groups[g].members.push_back(n);
  }
  return groups;
}

struct SeedCombined {
  double mean = std::numeric_limits<double>::quiet_NaN();
  double error = std::numeric_limits<double>::quiet_NaN();   // s / √N
  double within = std::numeric_limits<double>::quiet_NaN();  // per-run errors alone
  double scatter_ratio = std::numeric_limits<double>::quiet_NaN();
  std::size_t seeds = 0;  // seeds with a finite value
};

// values[s], errors[s] of one observable over the seeds of a group; non-finite values (failed
// runs) are left out. error needs >= 2 seeds.
inline SeedCombined combine_seeds(const std::vector<double>& values,
                                  const std::vector<double>& errors) {
  SeedCombined c;
  double sum = 0.0, se2 = 0.0;
  for (std::size_t s = 0; s < values.size(); ++s)
    if (std::isfinite(values[s])) {
      sum += values[s];
      se2 += s < errors.size() && std::isfinite(errors[s]) ? errors[s] * errors[s] : 0.0;
      ++c.seeds;
    }
  if (c.seeds == 0) return c;
  const double n = double(c.seeds);
  c.mean = sum / n;
  c.within = std::sqrt(se2 / n) / std::sqrt(n);
  if (c.seeds < 2) return c;
  double ss = 0.0;
  for (double v : values)
    if (std::isfinite(v)) ss += (v - c.mean) * (v - c.mean);
  c.error = std::sqrt(ss / (n - 1.0)) / std::sqrt(n);
  // A per-run error at round-off (below 1e-9 of the mean: an imposed quantity, e.g. φ at constant
  // volume, whose series jitters in its last digits) has no ratio to speak of: NaN, not 1e12.
  if (c.within > 1e-9 * std::abs(c.mean)) c.scatter_ratio = c.error / c.within;
  return c;
}

}  // namespace granflow::dem
