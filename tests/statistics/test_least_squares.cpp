// The shared weighted least squares (statistics/least_squares.hpp) used by the calibration and the
// DEM rheology fits: bounds enforced by a change of variables, errors propagated back to θ.
// Straight lines, whose constrained and unconstrained optima have closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "statistics/least_squares.hpp"

namespace granflow::statistics {
namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

// y = 0.3 + 1.0 x with fixed deviations (a deterministic "noise" of about one σ), σ from 0.02.
struct LineData {
  std::vector<double> x, y, sigma;
};
LineData line_data() {
  LineData d;
  const double deviation[] = {0.8, -1.1, 0.3, 1.4, -0.6, -0.9, 0.2, 1.0};
  for (int i = 0; i < 8; ++i) {
    d.x.push_back(0.1 * (i + 1));
    d.sigma.push_back(0.02 + 0.005 * i);
    d.y.push_back(0.3 + 1.0 * d.x.back() + deviation[i] * d.sigma.back());
  }
  return d;
}
double line_model(const LineData& d, std::size_t i, const Eigen::VectorXd& t) {
  return t[0] + t[1] * d.x[i];
}

TEST(LeastSquaresFitTransform, MapsRoundTripAndStayInside) {
  const ParameterBounds kinds[] = {
      ParameterBounds::between(0.49, 0.74), ParameterBounds::positive(), ParameterBounds{-inf, 2.0},
      ParameterBounds::unbounded(), ParameterBounds::between(1e-6, 1e6)};
  const double thetas[] = {0.6, 3.5, -7.0, -2.5, 1.0};
  for (int k = 0; k < 5; ++k) {
    const double u = unconstrained_parameter(thetas[k], kinds[k]);
    // Round trip to rounding (a few ulp of the box scale).
    EXPECT_NEAR(bounded_parameter(u, kinds[k]), thetas[k],
                1e-12 * std::max(1.0, std::abs(thetas[k])))
        << k;
    // Far out in u the parameter approaches the wall but stays inside it.
    for (double far : {-30.0, 30.0})
      EXPECT_TRUE(kinds[k].contains(bounded_parameter(far, kinds[k]))) << k;
  }
}

TEST(LeastSquaresFitBounds, InteriorOptimumIsTheUnboundedFitWithTheSameErrors) {
  // The box (−1, 1) × (0, 5) contains the optimum: the transform must change neither the
  // estimate nor its errors, which are computed in θ (= D C_u D, header comment). Agreement to
  // the LM tolerance and the 1e-5 finite differences of a linear model: 1e-7 relative.
  const LineData d = line_data();
  const LineFit exact = weighted_line(d.x, d.y, d.sigma);
  auto model = [&](std::size_t i, const Eigen::VectorXd& t) { return line_model(d, i, t); };
  const LeastSquaresFit boxed = weighted_least_squares(
      model, d.y, d.sigma, Eigen::Vector2d(0.0, 2.0),
      {ParameterBounds::between(-1.0, 1.0), ParameterBounds::between(0.0, 5.0)});
  ASSERT_TRUE(boxed.converged && boxed.identifiable);
  EXPECT_FALSE(boxed.at_bound);
  EXPECT_NEAR(boxed.estimate[0], exact.intercept, 1e-7 * std::abs(exact.intercept));
  EXPECT_NEAR(boxed.estimate[1], exact.slope, 1e-7 * std::abs(exact.slope));
  EXPECT_NEAR(boxed.standard_error[0], exact.intercept_err, 1e-7 * exact.intercept_err);
  EXPECT_NEAR(boxed.standard_error[1], exact.slope_err, 1e-7 * exact.slope_err);
  EXPECT_NEAR(boxed.covariance(0, 1), exact.covariance, 1e-7 * std::abs(exact.covariance));
  EXPECT_NEAR(boxed.chi2, exact.chi2, 1e-7 * exact.chi2);
}

TEST(LeastSquaresFitBounds, ErrorsAreTheTransformedCovariancePropagated) {
  // Second path to the same errors: fit the model written in u (θ_1 = 5/(1 + e^(−u)), the
  // logistic map of (0, 5)) without bounds, take C_u = (J_uᵀ J_u)⁻¹ and propagate it,
  // C_θ = D C_u D with D = dθ/du = θ (5 − θ)/5. Same estimate; errors within 1e-6 relative (two
  // finite-difference Jacobians of step 1e-5).
  const LineData d = line_data();
  auto theta_1 = [](double u) { return 5.0 / (1.0 + std::exp(-u)); };
  const LeastSquaresFit in_u = weighted_least_squares(
      [&](std::size_t i, const Eigen::VectorXd& t) { return t[0] + theta_1(t[1]) * d.x[i]; }, d.y,
      d.sigma, Eigen::Vector2d(0.0, 0.5));
  const LeastSquaresFit boxed = weighted_least_squares(
      [&](std::size_t i, const Eigen::VectorXd& t) { return line_model(d, i, t); }, d.y, d.sigma,
      Eigen::Vector2d(0.0, 2.0),
      {ParameterBounds::unbounded(), ParameterBounds::between(0.0, 5.0)});
  const double slope = theta_1(in_u.estimate[1]);
  EXPECT_NEAR(boxed.estimate[1], slope, 1e-7 * slope);
  const double D = slope * (5.0 - slope) / 5.0;
  EXPECT_NEAR(boxed.standard_error[1], D * in_u.standard_error[1], 1e-6 * boxed.standard_error[1]);
  EXPECT_NEAR(boxed.covariance(0, 1), D * in_u.covariance(0, 1),
              1e-6 * std::abs(boxed.covariance(0, 1)));
  EXPECT_NEAR(boxed.standard_error[0], in_u.standard_error[0], 1e-6 * boxed.standard_error[0]);
}

TEST(LeastSquaresFitBounds, OptimumOutsideTheBoxEndsOnTheWallAndIsFlagged) {
  // The data want slope ≈ 1; the box allows (0, 0.5). Every trial stays inside the box, the fit
  // ends on the wall b = 0.5, flagged, and there the intercept is the constrained closed form
  // a = Σ w (y − 0.5 x) / Σ w with χ² = Σ w (y − a − 0.5 x)², above the unconstrained χ².
  const LineData d = line_data();
  int outside = 0;
  const LeastSquaresFit fit = weighted_least_squares(
      [&](std::size_t i, const Eigen::VectorXd& t) {
        outside += !(t[1] > 0.0 && t[1] < 0.5);
        return line_model(d, i, t);
      },
      d.y, d.sigma, Eigen::Vector2d(0.0, 0.25),
      {ParameterBounds::unbounded(), ParameterBounds::between(0.0, 0.5)});
  EXPECT_EQ(outside, 0);
  EXPECT_TRUE(fit.at_bound);
  EXPECT_FALSE(fit.parameter_at_bound[0]);
  EXPECT_TRUE(fit.parameter_at_bound[1]);
  EXPECT_LE(fit.estimate[1], 0.5);
  // On the wall within bound_margin × 0.25 (the start's distance to it).
  EXPECT_GT(fit.estimate[1], 0.5 - 1e-4 * 0.25);
  double sw = 0, swr = 0;
  for (std::size_t i = 0; i < d.x.size(); ++i) {
    const double w = 1.0 / (d.sigma[i] * d.sigma[i]);
    sw += w;
    swr += w * (d.y[i] - 0.5 * d.x[i]);
  }
  const double a = swr / sw;
  double chi2 = 0;
  for (std::size_t i = 0; i < d.x.size(); ++i)
    chi2 += std::pow((d.y[i] - a - 0.5 * d.x[i]) / d.sigma[i], 2);
  // The slope is within ~1e-5 of the wall (the logistic saturates), which moves a and χ² by
  // O(1e-5) relative: 1e-4.
  EXPECT_NEAR(fit.estimate[0], a, 1e-4 * std::abs(a));
  EXPECT_NEAR(fit.chi2, chi2, 1e-4 * chi2);
  EXPECT_GT(fit.chi2, 10 * weighted_line(d.x, d.y, d.sigma).chi2);
}

TEST(LeastSquaresFitBounds, StartOutsideItsBoxIsRefused) {
  const LineData d = line_data();
  EXPECT_THROW(weighted_least_squares(
                   [&](std::size_t i, const Eigen::VectorXd& t) { return line_model(d, i, t); },
                   d.y, d.sigma, Eigen::Vector2d(0.0, 0.7),
                   {ParameterBounds::unbounded(), ParameterBounds::between(0.0, 0.5)}),
               std::invalid_argument);
}

}  // namespace
}  // namespace granflow::statistics
