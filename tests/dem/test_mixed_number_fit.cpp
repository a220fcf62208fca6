// fit.alpha of a wet sweep: α of K = J + α I² recovered from data that lie on Boyer's law in K.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "dem_coupling/kind/mixed_number_fit.hpp"

namespace {

using granflow::dem::boyer_friction;
using granflow::dem::fit_trulsson_alpha;

TEST(DemMixedNumberFit, BoyerLawHasItsPublishedLimits) {
  // μ_B(J → 0) → μ1 = 0.32; μ_B(J0) = μ1 + (μ2 − μ1)/2 + J0 + 2.5 ν_m sqrt(J0) (closed form).
  EXPECT_NEAR(boyer_friction(1e-12), 0.32, 2e-6);  // the J^½ term is 1.46e-6 at J = 1e-12
  EXPECT_NEAR(boyer_friction(0.005), 0.32 + 0.19 + 0.005 + 2.5 * 0.585 * std::sqrt(0.005), 1e-14);
}

TEST(DemMixedNumberFit, RecoversAlphaFromDataOnTheLawInK) {
  // A viscous-to-inertial sweep at fixed I: J = I²/St, μ_i = μ_B(J_i + α I_i²) with α = 0.635.
  const double alpha = 0.635, inertial = 0.1;
  std::vector<double> j, i, mu, err;
  for (double st : {0.1, 0.3, 1.0, 3.0, 10.0, 100.0}) {
    j.push_back(inertial * inertial / st);
    i.push_back(inertial);
    mu.push_back(boyer_friction(j.back() + alpha * inertial * inertial));
    err.push_back(0.01);
  }
  const auto fit = fit_trulsson_alpha(j, i, mu, err);
  EXPECT_EQ(fit.points, 6);
  // Exact data: the golden section converges to the minimum of S; 1e-6 relative is far above
  // its bracket (0.618^80 of one scan cell) and far below any physical resolution.
  EXPECT_NEAR(fit.alpha, alpha, 1e-6 * alpha);
  EXPECT_LT(fit.rms, 1e-8);
}

TEST(DemMixedNumberFit, NoisyDataAndSkippedPoints) {
  // ±0.01 alternating noise on μ (the typical DEM error bar) moves α by a bounded amount; a NaN
  // point (a failed condition) is skipped.
  const double alpha = 0.3;
  std::vector<double> j, i, mu, err;
  int k = 0;
  for (double st : {0.1, 1.0, 10.0, 100.0, 1000.0}) {
    for (double inertial : {0.05, 0.1}) {
      j.push_back(inertial * inertial / st);
      i.push_back(inertial);
      mu.push_back(boyer_friction(j.back() + alpha * inertial * inertial) +
                   (k++ % 2 ? 0.01 : -0.01));
      err.push_back(0.01);
    }
  }
  j.push_back(NAN), i.push_back(0.1), mu.push_back(0.5), err.push_back(0.01);
  const auto fit = fit_trulsson_alpha(j, i, mu, err);
  EXPECT_EQ(fit.points, 10);
  // dμ_B/dK ≈ 1-3 at K ~ 0.01-0.03, so ±0.01 in μ is ~±0.005 in K = ±0.5 in α I² / I²; the
  // alternating noise largely cancels: α within 30 %.
  EXPECT_NEAR(fit.alpha, alpha, 0.3 * alpha);
  EXPECT_NEAR(fit.rms, 0.01, 0.005);
}

}  // namespace
