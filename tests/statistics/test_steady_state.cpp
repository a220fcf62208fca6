// Statistics on synthetic AR(1) series x_t = mu + a (x_{t-1} - mu) + sigma eps_t, for which
// Var(x) = sigma^2 / (1 - a^2), tau_int = (1 + a) / (1 - a) and the variance of the mean of n
// stationary samples is known in closed form (e.g. Priestley 1981, eq. 5.3.26):
//   Var(mean) = Var(x)/n [ (1 + a)/(1 - a) - 2 a (1 - a^n) / (n (1 - a)^2) ].
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "statistics/steady_state.hpp"

namespace {

using granflow::statistics::batch_means;
using granflow::statistics::integrated_autocorrelation_time;
using granflow::statistics::mser_truncation;
using granflow::statistics::steady_state;
using granflow::statistics::student_t_975;

std::vector<double> ar1(std::mt19937_64& rng, std::size_t n, double mu, double a, double sigma) {
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> x(n);
  // start in the stationary distribution, so the whole series is steady
  double y = normal(rng) * sigma / std::sqrt(1.0 - a * a);
  for (auto& v : x) {
    v = mu + y;
    y = a * y + sigma * normal(rng);
  }
  return x;
}

double variance_of_mean(std::size_t n, double a, double sigma) {
  const double var = sigma * sigma / (1.0 - a * a);
  const double nn = double(n);
  return var / nn *
         ((1.0 + a) / (1.0 - a) - 2.0 * a * (1.0 - std::pow(a, nn)) / (nn * (1.0 - a) * (1.0 - a)));
}

TEST(StudentT, MatchesTabulatedQuantiles) {
  // Tables (e.g. Abramowitz & Stegun table 26.10): t_{0.975} = 2.228 (10), 2.093 (19), 2.042 (30);
  // the expansion is good to 1e-3 there.
  EXPECT_NEAR(student_t_975(10), 2.2281, 1e-3);
  EXPECT_NEAR(student_t_975(19), 2.0930, 1e-3);
  EXPECT_NEAR(student_t_975(30), 2.0423, 1e-3);
}

TEST(BatchMeans, StandardErrorMatchesClosedFormVarianceOfTheMean) {
  std::mt19937_64 rng(12345);
  const std::size_t n = 4000, realisations = 400;
  const double a = 0.9, sigma = 1.0, mu = 3.0;
  double mean_se2 = 0.0;
  for (std::size_t r = 0; r < realisations; ++r) {
    const auto x = ar1(rng, n, mu, a, sigma);
    mean_se2 += std::pow(batch_means(x, 20).standard_error, 2) / realisations;
  }
  // Batches of 200 samples vs tau_int = 19: batch means underestimate Var(mean) by about
  // tau_int / batch size ~ 10 %; 400 realisations of a chi^2_19 / 19 estimate add ~1.6 % noise.
  EXPECT_NEAR(mean_se2 / variance_of_mean(n, a, sigma), 1.0, 0.15);
}

TEST(BatchMeans, NinetyFivePercentIntervalsCoverTheTrueMean) {
  std::mt19937_64 rng(777);
  const std::size_t n = 4000, realisations = 1000;
  const double a = 0.8, mu = -1.5;
  int covered = 0;
  for (std::size_t r = 0; r < realisations; ++r) {
    const auto x = ar1(rng, n, mu, a, 0.5);
    const auto e = batch_means(x, 20);
    covered += std::abs(e.mean - mu) <= e.ci95;
  }
  // Binomial(1000, 0.95) has a standard deviation of 0.7 %: 3 sigma is 2.1 %, plus 1 % for the
  // small batch-size bias of batch means.
  EXPECT_NEAR(covered / double(realisations), 0.95, 0.031);
}

TEST(BatchMeans, IgnoringCorrelationWouldUnderestimateTheError) {
  // The naive SE (uncorrelated samples) is sqrt(tau_int) ~ 4.4 times too small for a = 0.9; the
  // batch-means SE must be much larger than the naive one (guards against a naive estimator).
  std::mt19937_64 rng(4);
  const auto x = ar1(rng, 20000, 0.0, 0.9, 1.0);
  double m = 0, v = 0;
  for (double xi : x) m += xi / x.size();
  for (double xi : x) v += (xi - m) * (xi - m) / (x.size() - 1);
  const double naive = std::sqrt(v / x.size());
  EXPECT_GT(batch_means(x, 20).standard_error / naive, 3.0);
}

TEST(AutocorrelationTime, MatchesAr1ClosedForm) {
  std::mt19937_64 rng(99);
  for (double a : {0.0, 0.5, 0.9}) {
    const auto x = ar1(rng, 200000, 1.0, a, 1.0);
    const double exact = (1.0 + a) / (1.0 - a);
    // Sokal's window estimator: statistical error ~ sqrt(2 (2 W + 1) / n) tau ~ 2 % here, window
    // truncation bias ~ exp(-W/tau) < 1 %; 8 % covers both with margin.
    EXPECT_NEAR(integrated_autocorrelation_time(x) / exact, 1.0, 0.08) << "a = " << a;
  }
}

TEST(Mser, FindsAKnownTransient) {
  std::mt19937_64 rng(2024);
  const std::size_t transient = 300;
  for (int r = 0; r < 20; ++r) {
    auto x = ar1(rng, 3000, 10.0, 0.5, 1.0);
    // Exponentially decaying start-up bias of 8 standard deviations, time constant 50 samples.
    const double sd = 1.0 / std::sqrt(1.0 - 0.25);
    for (std::size_t t = 0; t < transient; ++t) x[t] += 8.0 * sd * std::exp(-double(t) / 50.0);
    const std::size_t start = mser_truncation(x, 5);
    // What MSER must achieve: the bias left in the kept mean, sum_{t>=start} bias_t / (n - start)
    // (known here), is below the standard error of that mean, sd sqrt(tau_int / (n - start)) with
    // tau_int = 3; and it must not throw away much more than the transient.
    double residual_bias = 0.0;
    for (std::size_t t = start; t < transient; ++t)
      residual_bias += 8.0 * sd * std::exp(-double(t) / 50.0);
    residual_bias /= double(x.size() - start);
    EXPECT_LT(residual_bias, sd * std::sqrt(3.0 / double(x.size() - start))) << "realisation " << r;
    EXPECT_GE(start, 50u) << "realisation " << r;
    EXPECT_LE(start, 600u) << "realisation " << r;
    const auto s = steady_state(x);
    EXPECT_LE(std::abs(s.mean.mean - 10.0), 4.0 * s.mean.standard_error) << "realisation " << r;
  }
}

TEST(Mser, KeepsAStationarySeries) {
  std::mt19937_64 rng(5);
  int small_cuts = 0;
  for (int r = 0; r < 50; ++r) {
    const auto x = ar1(rng, 2000, 0.0, 0.5, 1.0);
    small_cuts += mser_truncation(x, 5) < 400;
  }
  // A stationary series has no bias to remove: MSER drops little (it may trim a few batches by
  // chance). Most realisations keep more than 80 % of the data.
  EXPECT_GE(small_cuts, 40);
}

}  // namespace
