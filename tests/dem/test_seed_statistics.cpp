// Seed-to-seed statistics of a sweep over dem.seed (dem_coupling/kind/seed_statistics.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dem_coupling/kind/seed_statistics.hpp"

namespace {

using granflow::dem::combine_seeds;
using granflow::dem::Condition;
using granflow::dem::group_by_seed;

TEST(SeedStatistics, GroupsConditionsThatDifferOnlyInTheSeed) {
  // sweep: shear_rate [10, 20] x dem.seed [1, 2, 3] (the last key varies fastest)
  std::vector<Condition> conditions;
  for (double rate : {10.0, 20.0})
    for (double seed : {1.0, 2.0, 3.0})
      conditions.push_back({{"shear_rate", rate}, {"dem.seed", seed}});
  const auto groups = group_by_seed(conditions);
  ASSERT_EQ(groups.size(), 2u);
  EXPECT_EQ(groups[1].condition, (Condition{{"shear_rate", 20.0}}));
  EXPECT_EQ(groups[1].members, (std::vector<std::size_t>{3, 4, 5}));
  // no seed in the sweep: nothing to combine
  EXPECT_TRUE(group_by_seed({{{"shear_rate", 10.0}}, {{"shear_rate", 20.0}}}).empty());
}

TEST(SeedStatistics, CombinedErrorIsTheBetweenSeedStandardError) {
  // 102 ± 15 and 64.5 ± 4 Pa (two seeds near jamming): mean 83.25, s = 26.52, s/√2 = 18.75
  // against sqrt((15² + 4²)/2)/√2 = 7.76 from the per-run errors: ratio 2.4.
  const auto c = combine_seeds({102.0, 64.5}, {15.0, 4.0});
  EXPECT_DOUBLE_EQ(c.mean, 83.25);
  EXPECT_NEAR(c.error, 18.75, 1e-12);
  EXPECT_NEAR(c.within, std::sqrt((225.0 + 16.0) / 2.0) / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(c.scatter_ratio, 18.75 / c.within, 1e-12);
  // a failed seed (NaN) is left out; one seed has no between-seed error
  const auto one = combine_seeds({1.0, std::nan("")}, {0.1, 0.1});
  EXPECT_EQ(one.seeds, 1u);
  EXPECT_TRUE(std::isnan(one.error));
}

TEST(SeedStatistics, RatioIsNearOneWhenPerRunErrorsAreComplete) {
  // Each "run" x_s = μ + e_s with e_s ~ N(0, se²) and its reported error se: the between-seed
  // error estimates the same se/√N, so the ratio averages ~1 (E[s]/σ = 0.94 for 8 seeds; 2000
  // groups give the mean ratio to ~0.6 %): within 0.9-1.0.
  std::mt19937_64 rng(17);
  std::normal_distribution<double> normal(0.0, 1.0);
  double sum = 0.0;
  const int groups = 2000;
  for (int g = 0; g < groups; ++g) {
    std::vector<double> v, e;
    for (int s = 0; s < 8; ++s) {
      v.push_back(5.0 + 0.3 * normal(rng));
      e.push_back(0.3);
    }
    sum += combine_seeds(v, e).scatter_ratio / groups;
  }
  EXPECT_GT(sum, 0.9);
  EXPECT_LT(sum, 1.0);
}

}  // namespace
