// Weighted least squares with box-bounded parameters, shared by the DEM rheology fits
// (dem_coupling/kind/*_fit.hpp) and the calibration of closure parameters (analysis/calibration):
//
//     χ²(θ) = Σ_i r_i(θ)²,   r_i = (y_i − f_i(θ)) / σ_i,
//
// minimised by Eigen's Levenberg-Marquardt (MINPACK lmdif port, unsupported/Eigen/
// NonLinearOptimization) with central-difference Jacobians.
//
// Bounds are enforced by a change of variables, not a penalty: LM works on an unconstrained u and
// the model sees θ = T(u) (Press et al., Numerical Recipes 3rd ed., §10.0; MINUIT's "internal
// parameters", James & Roos 1975):
//     lower and upper finite:  θ = l + (h − l) / (1 + e^(−u))   (logistic: every u is inside)
//     lower only:              θ = l + e^u
//     upper only:              θ = h − e^u
//     neither:                 θ = u
// so every trial is inside the box and no step is rejected for leaving it. An optimum that the
// unconstrained χ² would place outside the box is approached as u → ±∞ and ends on the wall
// (`at_bound`).
//
// Errors: covariance of the estimates C = (Jᵀ J)⁻¹ with J = ∂r/∂θ at the optimum (r already
// divided by σ, so Jᵀ J = (∂f/∂θ)ᵀ W (∂f/∂θ), W = diag(1/σ²)), NOT rescaled by χ²_red: the error
// bars given are the noise level and χ²_red ≈ 1 checks that (Numerical Recipes §15.5). This is
// the covariance of u propagated to θ: with D = diag(dθ/du), J_u = J D, so
// C_θ = D (J_uᵀ J_u)⁻¹ D = (Jᵀ J)⁻¹ exactly when D is regular (first-order delta method); J is
// differentiated in θ directly, which stays finite when θ sits on a wall (D → 0 there, where the
// propagated u-covariance would be 0·∞). On the wall the Gaussian error bar is the curvature of
// χ² along θ, a one-sided statement: the fit says only that the data want θ beyond the bound.
//
// Header-only: `granflow report` (analysis/report.cpp, granflow_analysis) re-derives DEM fits
// without linking the DEM libraries, and granflow_calibration includes it as well.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <unsupported/Eigen/NonLinearOptimization>
#include <unsupported/Eigen/NumericalDiff>
#include <vector>

namespace granflow::statistics {

// The open interval (lower, upper) a parameter must stay in; ±∞ for an open side.
struct ParameterBounds {
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  static ParameterBounds unbounded() { return {}; }
  static ParameterBounds positive() { return {0.0, std::numeric_limits<double>::infinity()}; }
  static ParameterBounds between(double lower, double upper) { return {lower, upper}; }
  bool contains(double theta) const { return theta > lower && theta < upper; }
};

// θ = T(u) and its inverse (θ strictly inside the bounds), see the header comment. Far out in u
// the maps round to the wall itself (1/(1 + e^(−u)) = 1 for u > 37); θ is then held one ulp
// inside, so the model never sees a bound (which may be a singular point of it).
inline double bounded_parameter(double u, const ParameterBounds& b) {
  const bool has_lower = std::isfinite(b.lower), has_upper = std::isfinite(b.upper);
  double theta = u;
  if (has_lower && has_upper)
    theta = b.lower + (b.upper - b.lower) / (1.0 + std::exp(-u));
  else if (has_lower)
    theta = b.lower + std::exp(u);
  else if (has_upper)
    theta = b.upper - std::exp(u);
  if (has_lower) theta = std::max(theta, std::nextafter(b.lower, b.upper));
  if (has_upper) theta = std::min(theta, std::nextafter(b.upper, b.lower));
  return theta;
}
inline double unconstrained_parameter(double theta, const ParameterBounds& b) {
  const bool has_lower = std::isfinite(b.lower), has_upper = std::isfinite(b.upper);
  if (has_lower && has_upper) return std::log((theta - b.lower) / (b.upper - theta));
  if (has_lower) return std::log(theta - b.lower);
  if (has_upper) return std::log(b.upper - theta);
  return theta;
}

struct LeastSquaresOptions {
  int max_evaluations = 4000;  // residual-vector evaluations (MINPACK maxfev)
  double tolerance = 1e-12;    // MINPACK xtol and ftol (relative)
  // Central-difference step: LM's in u (epsfcn = step², NumericalDiff steps sqrt(epsfcn)|u|), and
  // the covariance Jacobian's in θ, h = step · max(|θ|, step_floor), halved towards a wall.
  // 1e-5: truncation O(h²) ≈ 1e-10 against rounding O(1e-16/1e-5) ≈ 1e-11.
  double relative_step = 1e-5;
  double step_floor = 1e-6;
  // Smallest over largest singular value of J below this: a direction of θ the data do not
  // constrain (not identifiable; covariance NaN).
  double rank_tolerance = 1e-10;
  // A residual that comes back non-finite (the model is undefined at the trial θ) is replaced by
  // this, so LM rejects the step and shortens it.
  double failed_residual = 1e6;
  // `at_bound` when an estimate is within bound_margin of a finite bound, measured in the start's
  // distance to that bound (at most the box width): a scale the caller chose, right for linear
  // boxes like (0, 2) and for log-wide ones like (1e-6, 1e6) alike.
  double bound_margin = 1e-4;
};

struct LeastSquaresFit {
  Eigen::VectorXd estimate, standard_error;
  Eigen::MatrixXd covariance, correlation;
  Eigen::VectorXd normalised_residuals;  // r_i = (y_i − f_i)/σ_i at the estimate
  double chi2 = std::numeric_limits<double>::quiet_NaN();
  double chi2_initial = std::numeric_limits<double>::quiet_NaN();  // at the start
  int points = 0, dof = 0;                                     // residuals, residuals − params
  double chi2_red = std::numeric_limits<double>::quiet_NaN();  // χ² / dof
  int evaluations = 0;        // residual-vector evaluations (LM and the covariance Jacobian)
  int status = 0;             // Eigen LevenbergMarquardtSpace::Status
  bool converged = false;     // LM stopped on a tolerance, not on the evaluation budget
  bool identifiable = false;  // Jᵀ J of full rank (every parameter constrained by the data)
  bool at_bound = false;      // some estimate on (within bound_margin of) a wall of its box
  std::vector<bool> parameter_at_bound;
  // Largest |normalised residual|: the worst point's distance to the fitted curve in its SE.
  double max_abs_residual() const {
    return normalised_residuals.size() ? normalised_residuals.cwiseAbs().maxCoeff()
                                       : std::numeric_limits<double>::quiet_NaN();
  }
};

// residuals(θ, r): r (resized to `count` by the caller or here) = (y − f(θ))/σ.
using ResidualFunction = std::function<void(const Eigen::VectorXd&, Eigen::VectorXd&)>;

// Minimises Σ r² over θ within `bounds` (one per parameter, or empty: all unbounded) from
// `start` (strictly inside). Needs more residuals than parameters, else returns an empty fit
// (estimate of size 0) with points and dof set. Throws std::invalid_argument for a start outside
// its bounds or a bounds vector of the wrong size.
inline LeastSquaresFit minimise_residuals(const ResidualFunction& residuals, int count,
                                          const Eigen::VectorXd& start,
                                          std::vector<ParameterBounds> bounds = {},
                                          const LeastSquaresOptions& options = {}) {
  LeastSquaresFit fit;
  const int n = static_cast<int>(start.size());
  const int m = count;
  fit.points = m;
  fit.dof = m - n;
  if (bounds.empty()) bounds.assign(std::size_t(n), ParameterBounds{});
  if (static_cast<int>(bounds.size()) != n)
    throw std::invalid_argument("minimise_residuals: one ParameterBounds per parameter expected");
  for (int j = 0; j < n; ++j)
    if (!bounds[j].contains(start[j]))
      throw std::invalid_argument("minimise_residuals: start of parameter " + std::to_string(j) +
                                  " = " + std::to_string(start[j]) + " is not inside (" +
                                  std::to_string(bounds[j].lower) + ", " +
                                  std::to_string(bounds[j].upper) + ")");
  if (m <= n) return fit;

  int evaluations = 0;
  // r at θ with non-finite entries replaced (see LeastSquaresOptions::failed_residual).
  auto evaluate = [&](const Eigen::VectorXd& theta, Eigen::VectorXd& r) {
    ++evaluations;
    r.resize(m);
    residuals(theta, r);
    for (int i = 0; i < m; ++i)
      if (!std::isfinite(r[i])) r[i] = options.failed_residual;
  };
  auto to_theta = [&](const Eigen::VectorXd& u) {
    Eigen::VectorXd theta(n);
    for (int j = 0; j < n; ++j) theta[j] = bounded_parameter(u[j], bounds[j]);
    return theta;
  };
  struct Residuals {
    using Scalar = double;
    using InputType = Eigen::VectorXd;
    using ValueType = Eigen::VectorXd;
    using JacobianType = Eigen::MatrixXd;
    enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };
    std::function<void(const Eigen::VectorXd&, Eigen::VectorXd&)> of_u;
    int n, m;
    int inputs() const { return n; }
    int values() const { return m; }
    int operator()(const Eigen::VectorXd& u, Eigen::VectorXd& r) const {
      of_u(u, r);
      return 0;
    }
  };
  Residuals functor{[&](const Eigen::VectorXd& u, Eigen::VectorXd& r) { evaluate(to_theta(u), r); },
                    n, m};

  Eigen::VectorXd r(m);
  evaluate(start, r);
  fit.chi2_initial = r.squaredNorm();
  Eigen::VectorXd u(n);
  for (int j = 0; j < n; ++j) u[j] = unconstrained_parameter(start[j], bounds[j]);
  Eigen::NumericalDiff<Residuals, Eigen::Central> numerical(
      functor, options.relative_step * options.relative_step);
  Eigen::LevenbergMarquardt<Eigen::NumericalDiff<Residuals, Eigen::Central>> lm(numerical);
  lm.parameters.maxfev = options.max_evaluations;
  lm.parameters.xtol = options.tolerance;
  lm.parameters.ftol = options.tolerance;
  const auto status = lm.minimize(u);
  fit.status = static_cast<int>(status);
  using S = Eigen::LevenbergMarquardtSpace::Status;
  fit.converged = status == S::RelativeReductionTooSmall || status == S::RelativeErrorTooSmall ||
                  status == S::RelativeErrorAndReductionTooSmall || status == S::CosinusTooSmall ||
                  status == S::FtolTooSmall || status == S::XtolTooSmall ||
                  status == S::GtolTooSmall;
  const Eigen::VectorXd theta = to_theta(u);
  fit.estimate = theta;
  evaluate(theta, r);
  fit.normalised_residuals = r;
  fit.chi2 = r.squaredNorm();
  fit.chi2_red = fit.chi2 / fit.dof;

  // Walls: within bound_margin of a finite bound (header comment: the error bar is one-sided).
  fit.parameter_at_bound.assign(std::size_t(n), false);
  for (int j = 0; j < n; ++j) {
    const ParameterBounds& b = bounds[j];
    for (double wall : {b.lower, b.upper}) {
      if (!std::isfinite(wall)) continue;
      const double scale = std::min(std::abs(start[j] - wall), b.upper - b.lower);
      if (std::abs(theta[j] - wall) < options.bound_margin * scale)
        fit.parameter_at_bound[j] = true;
    }
    fit.at_bound = fit.at_bound || fit.parameter_at_bound[j];
  }

  // J = ∂r/∂θ by central differences in θ, the step shortened to half the distance to a wall.
  Eigen::MatrixXd jacobian(m, n);
  for (int j = 0; j < n; ++j) {
    const double h = options.relative_step * std::max(std::abs(theta[j]), options.step_floor);
    Eigen::VectorXd up = theta, down = theta, r_up(m), r_down(m);
    // Half-way to a wall at most, and never onto it (on the wall the step is one-sided).
    up[j] = std::min({theta[j] + h, 0.5 * (theta[j] + bounds[j].upper),
                      std::nextafter(bounds[j].upper, bounds[j].lower)});
    down[j] = std::max({theta[j] - h, 0.5 * (theta[j] + bounds[j].lower),
                        std::nextafter(bounds[j].lower, bounds[j].upper)});
    up[j] = std::max(up[j], theta[j]);
    down[j] = std::min(down[j], theta[j]);
    evaluate(up, r_up);
    evaluate(down, r_down);
    jacobian.col(j) = (r_up - r_down) / (up[j] - down[j]);
  }
  fit.evaluations = evaluations;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(jacobian);
  const auto sv = svd.singularValues();
  fit.identifiable = sv.size() > 0 && std::isfinite(sv[0]) && sv[0] > 0 &&
                     sv[sv.size() - 1] > options.rank_tolerance * sv[0];
  const double nan = std::numeric_limits<double>::quiet_NaN();
  fit.covariance = Eigen::MatrixXd::Constant(n, n, nan);
  fit.correlation = Eigen::MatrixXd::Constant(n, n, nan);
  fit.standard_error = Eigen::VectorXd::Constant(n, nan);
  if (fit.identifiable) {
    fit.covariance =
        (jacobian.transpose() * jacobian).ldlt().solve(Eigen::MatrixXd::Identity(n, n));
    fit.standard_error = fit.covariance.diagonal().cwiseSqrt();
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b)
        fit.correlation(a, b) =
            fit.covariance(a, b) / (fit.standard_error[a] * fit.standard_error[b]);
  }
  return fit;
}

// Point-wise form: f_i(θ) = model(i, θ), data y_i ± σ_i.
inline LeastSquaresFit weighted_least_squares(
    const std::function<double(std::size_t, const Eigen::VectorXd&)>& model,
    const std::vector<double>& y, const std::vector<double>& sigma, const Eigen::VectorXd& start,
    std::vector<ParameterBounds> bounds = {}, const LeastSquaresOptions& options = {}) {
  if (y.size() != sigma.size())
    throw std::invalid_argument("weighted_least_squares: y and sigma differ in length");
  return minimise_residuals(
      [&](const Eigen::VectorXd& theta, Eigen::VectorXd& r) {
        for (std::size_t i = 0; i < y.size(); ++i)
          r[static_cast<Eigen::Index>(i)] = (y[i] - model(i, theta)) / sigma[i];
      },
      static_cast<int>(y.size()), start, std::move(bounds), options);
}

// Weighted straight line y = intercept + slope x in closed form (Numerical Recipes §15.2):
//   S = Σ w, S_x = Σ w x, S_y = Σ w y, S_xx = Σ w x², S_xy = Σ w x y, w = 1/σ², Δ = S S_xx − S_x²,
//   intercept = (S_xx S_y − S_x S_xy)/Δ, slope = (S S_xy − S_x S_y)/Δ,
//   var(intercept) = S_xx/Δ, var(slope) = S/Δ, cov = −S_x/Δ.
struct LineFit {
  double intercept = std::numeric_limits<double>::quiet_NaN();
  double slope = std::numeric_limits<double>::quiet_NaN();
  double intercept_err = std::numeric_limits<double>::quiet_NaN();
  double slope_err = std::numeric_limits<double>::quiet_NaN();
  double covariance = std::numeric_limits<double>::quiet_NaN();
  double chi2 = std::numeric_limits<double>::quiet_NaN();
  double chi2_red = std::numeric_limits<double>::quiet_NaN();
  int points = 0, dof = 0;
  std::vector<double> normalised_residuals;
};

inline LineFit weighted_line(const std::vector<double>& x, const std::vector<double>& y,
                             const std::vector<double>& sigma) {
  LineFit fit;
  fit.points = static_cast<int>(x.size());
  fit.dof = fit.points - 2;
  if (fit.points < 3) return fit;  // two points give a line but no error check
  double s = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double w = 1.0 / (sigma[i] * sigma[i]);
    s += w, sx += w * x[i], sy += w * y[i], sxx += w * x[i] * x[i], sxy += w * x[i] * y[i];
  }
  const double delta = s * sxx - sx * sx;
  fit.intercept = (sxx * sy - sx * sxy) / delta;
  fit.slope = (s * sxy - sx * sy) / delta;
  fit.intercept_err = std::sqrt(sxx / delta);
  fit.slope_err = std::sqrt(s / delta);
  fit.covariance = -sx / delta;
  fit.chi2 = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double r = (y[i] - fit.intercept - fit.slope * x[i]) / sigma[i];
    fit.normalised_residuals.push_back(r);
    fit.chi2 += r * r;
  }
  fit.chi2_red = fit.chi2 / fit.dof;
  return fit;
}

}  // namespace granflow::statistics
