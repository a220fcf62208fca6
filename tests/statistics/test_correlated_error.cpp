// Correlation-aware standard errors and the drift test (statistics/steady_state.hpp) on synthetic
// AR(1) series x_t = mu + a (x_{t-1} - mu) + sigma eps_t: Var(x) = sigma^2 / (1 - a^2),
// tau_int = (1 + a) / (1 - a), and the variance of the mean of n stationary samples is
//   Var(mean) = Var(x)/n [ (1 + a)/(1 - a) - 2 a (1 - a^n) / (n (1 - a)^2) ]
// (e.g. Priestley 1981, eq. 5.3.26).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "statistics/steady_state.hpp"

namespace {

using granflow::statistics::batch_means;
using granflow::statistics::correlated_mean;
using granflow::statistics::drift_test;
using granflow::statistics::mser_truncation;

std::vector<double> ar1(std::mt19937_64& rng, std::size_t n, double a, double sigma = 1.0) {
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> x(n);
  double y = normal(rng) * sigma / std::sqrt(1.0 - a * a);  // stationary start
  for (auto& v : x) {
    v = y;
    y = a * y + sigma * normal(rng);
  }
  return x;
}

double variance_of_mean(std::size_t n, double a) {
  const double nn = double(n);
  return 1.0 / (1.0 - a * a) / nn *
         ((1.0 + a) / (1.0 - a) - 2.0 * a * (1.0 - std::pow(a, nn)) / (nn * (1.0 - a) * (1.0 - a)));
}

TEST(CorrelatedMean, StandardErrorWithinTwentyPercentOfTheClosedForm) {
  // a = 0.98: tau_int = 99 samples, n = 4000 (40 correlation times, as a short DEM run whose φ
  // wanders slowly). 20 fixed batches of 200 = 2 tau_int underestimate Var(mean) by ~tau_int/(2b)
  // = 25 % (SE by ~13 % and more through the chi-square of the batches); correlated_mean takes
  // b = 5 tau_int. Root-mean-square over 400 realisations (2.5 % noise) within 20 % of the
  // closed form; the fixed 20 batches must be the lower of the two.
  std::mt19937_64 rng(31);
  const std::size_t n = 4000, realisations = 400;
  const double a = 0.98;
  double se2 = 0.0, fixed2 = 0.0;
  for (std::size_t r = 0; r < realisations; ++r) {
    const auto x = ar1(rng, n, a);
    se2 += std::pow(correlated_mean(x).standard_error, 2) / realisations;
    fixed2 += std::pow(batch_means(x, 20).standard_error, 2) / realisations;
  }
  const double exact = std::sqrt(variance_of_mean(n, a));
  EXPECT_NEAR(std::sqrt(se2) / exact, 1.0, 0.2);
  EXPECT_LT(std::sqrt(fixed2), std::sqrt(se2));
}

TEST(CorrelatedMean, NinetyFivePercentIntervalsCoverTheTrueMean) {
  // Binomial(1000, 0.95): standard deviation 0.7 %; 3 of them plus 1.5 % for the remaining bias of
  // batch means with few (here 8) batches, the max of two estimators erring on the wide side.
  std::mt19937_64 rng(5);
  const std::size_t n = 4000, realisations = 1000;
  int covered = 0;
  for (std::size_t r = 0; r < realisations; ++r) {
    const auto e = correlated_mean(ar1(rng, n, 0.98));
    covered += std::abs(e.mean) <= e.ci95;
  }
  EXPECT_NEAR(covered / double(realisations), 0.95, 0.036);
}

TEST(DriftTest, StationarySeriesPassAtTheStatedFalseAlarmRate) {
  // 800 samples with tau_int = 6.5 (a = 0.733), like a 300-sphere DEM window: |z| > 3 in at most
  // 2 % of 2000 realisations (normal: 0.27 %; Student t with the halves' ~8-19 batches: ~1 %;
  // binomial noise at 1 %: 0.2 %).
  std::mt19937_64 rng(2027);
  const int realisations = 2000;
  int alarms = 0;
  for (int r = 0; r < realisations; ++r)
    alarms += std::abs(drift_test(ar1(rng, 800, 0.733)).z) > 3.0;
  std::printf("false alarms: %d of %d\n", alarms, realisations);
  EXPECT_LT(alarms / double(realisations), 0.02);
}

TEST(DriftTest, ALinearTrendOfTwentyFourStandardErrorsIsRefused) {
  // x_t + D t / n with D = 24 standard errors of the window's mean: E[z] = D / (4 SE) = 6 (the
  // halves differ by D/2, their combined error is 2 SE): a normal z would exceed 3 in 99.9 % of
  // cases; the halves' errors come from ~8-20 batches each and are the larger of two estimates,
  // so z is Student-like and a little smaller (measured: 494 of 500). At least 98 %.
  std::mt19937_64 rng(11);
  const std::size_t n = 800;
  const double a = 0.733, drift = 24.0 * std::sqrt(variance_of_mean(n, a));
  int refused = 0;
  for (int r = 0; r < 500; ++r) {
    auto x = ar1(rng, n, a);
    for (std::size_t t = 0; t < n; ++t) x[t] += drift * double(t) / double(n);
    refused += drift_test(x).z > 3.0;
  }
  EXPECT_GE(refused, 490);
}

TEST(DriftTest, ASlowWarmUpIsNotSteadyAfterMser) {
  // A granular temperature rising from a cold start over a strain longer than the run (issue
  // of short collisional runs): x_t = 1 - exp(-t / 1500) plus AR(1) noise of standard deviation
  // 0.02, 1000 samples. MSER picks a start, but what it keeps still rises: z far above 3.
  std::mt19937_64 rng(3);
  for (int r = 0; r < 20; ++r) {
    auto x = ar1(rng, 1000, 0.733, 0.02 * std::sqrt(1.0 - 0.733 * 0.733));
    for (std::size_t t = 0; t < x.size(); ++t) x[t] += 1.0 - std::exp(-double(t) / 1500.0);
    const std::size_t start = mser_truncation(x, 5);
    EXPECT_GT(drift_test(std::span<const double>(x).subspan(start)).z, 3.0) << "realisation " << r;
  }
}

TEST(DriftTest, ConstantSeriesHasNoDrift) {
  // φ at constant volume is constant: zero error, equal halves, z = 0 (not NaN or infinite).
  const std::vector<double> phi(500, 0.5);
  EXPECT_EQ(drift_test(phi).z, 0.0);
}

}  // namespace
