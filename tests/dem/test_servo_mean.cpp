// The constant-normal-stress servo must hold the MEAN σ_yy on the target when σ_yy is skewed.
// Plant: σ_k = p0 (L0/L_k)^40 X_k (d ln σ/d ln φ = 40, a dense flow), X_k independent lognormal
// with E[X] = 1 and ln-standard deviation 0.8 (median e^{-0.32} = 0.73, standard deviation 0.9,
// skewness 3.7): the interval means of 300 dry Hertz spheres at I = 0.1 (docs/dem_dataset.md,
// servo) have a relative standard deviation ~1 and spikes several times p0.
// The servo (gain 0.01, at most 0.002 per update) clamps a spike's demand (gain × 5 = 0.05) but
// not a dip's (at most gain × 1 = 0.01): without the carry of the clipped remainder the loop
// balanced clipped errors and held σ_yy near the median; with it, the mean.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "dem_coupling/extraction/normal_stress_servo.hpp"

namespace {

using granflow::dem::NormalStressServo;

constexpr double p0 = 100.0, l0 = 0.01, gain = 0.01, max_strain = 0.002, ln_sd = 0.8;
constexpr int updates = 40000;

// Mean measured σ over the second half of the run, through `update(L, σ) -> L'`.
template <class Update>
double held_mean(Update update, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(-0.5 * ln_sd * ln_sd, ln_sd);  // E[e^N] = 1
  double l = l0, sum = 0.0;
  for (int k = 0; k < updates; ++k) {
    const double sigma = p0 * std::pow(l0 / l, 40.0) * std::exp(normal(rng));
    if (k >= updates / 2) sum += sigma;
    l = update(l, sigma);
  }
  return sum / (updates / 2);
}

TEST(DemServoMean, CarryHoldsTheMeanOnTheTarget) {
  NormalStressServo servo(p0, gain, max_strain, 50.0);  // granflow-dem's dry setting
  const double mean =
      held_mean([&](double l, double sigma) { return servo.next_height(l, sigma); }, 7);
  // Standard error of the mean of 20 000 updates: the loop correlates successive σ weakly (loop
  // gain 0.4 per update), so ~0.9 p0 / sqrt(20 000 / 2) = 0.009 p0; 3 % is > 3 standard errors.
  EXPECT_NEAR(mean / p0, 1.0, 0.03);
}

TEST(DemServoMean, ClampWithoutCarryHoldsNearTheMedian) {
  // The loop granflow-dem ran before: symmetric clamp, no carry. The mean sits well above p0
  // (between the target and 1/median = 1.37 p0): this is the bias the carry removes.
  const auto clamp_only = [](double l, double sigma) {
    return l * (1.0 + std::clamp(gain * (sigma - p0) / p0, -max_strain, max_strain));
  };
  EXPECT_GT(held_mean(clamp_only, 7) / p0, 1.15);
}

}  // namespace
