// Weighted least squares for the DEM rheology fits (inertial_law_fit.hpp,
// mixed_number_law_fit.hpp):
//
//     χ²(θ) = Σ_i ((y_i − f_i(θ)) / σ_i)²,
//
// minimised by Eigen's Levenberg-Marquardt (MINPACK lmdif port, unsupported/Eigen/
// NonLinearOptimization, as analysis/calibration) with central-difference Jacobians. Parameters
// that must stay positive (I_0, K_0, α, ...) are fitted as ln θ. Covariance of the estimates
// C = (Jᵀ W J)⁻¹ with W = diag(1/σ²) and J = ∂f/∂θ at the optimum, NOT rescaled by χ²_red: the
// DEM error bars are the noise level, and χ²_red ≈ 1 checks that (Press et al., Numerical Recipes
// 3rd ed., §15.5). The straight line y = c0 + c1 x has the closed form of §15.2.
//
// Header-only on purpose: `granflow report` (analysis/report.cpp, in granflow_analysis) re-derives
// the fits of an existing DEM run without linking the DEM libraries.
#pragma once

#include <Eigen/Dense>
#include <cmath>
#include <functional>
#include <limits>
#include <unsupported/Eigen/NonLinearOptimization>
#include <unsupported/Eigen/NumericalDiff>
#include <vector>

namespace granflow::dem {

struct LeastSquaresFit {
  Eigen::VectorXd estimate, standard_error;
  Eigen::MatrixXd covariance;
  Eigen::VectorXd normalised_residuals;  // (y_i − f_i)/σ_i at the estimate
  double chi2 = std::numeric_limits<double>::quiet_NaN();
  int points = 0, dof = 0;
  double chi2_red = std::numeric_limits<double>::quiet_NaN();  // χ² / (points − parameters)
  bool converged = false;     // LM stopped on a tolerance, not on the evaluation budget
  bool identifiable = false;  // Jᵀ W J of full rank (every parameter constrained by the data)
  // Largest |normalised residual|: the worst point's distance to the fitted curve in its SE.
  double max_abs_residual() const {
    return normalised_residuals.size() ? normalised_residuals.cwiseAbs().maxCoeff()
                                       : std::numeric_limits<double>::quiet_NaN();
  }
};

// model(i, θ) = f_i(θ), the prediction for point i. `positive[j]`: θ_j > 0 (fitted as ln θ_j;
// start[j] must then be > 0). Needs more points than parameters (else an empty fit, points set).
inline LeastSquaresFit weighted_least_squares(
    const std::function<double(std::size_t, const Eigen::VectorXd&)>& model,
    const std::vector<double>& y, const std::vector<double>& sigma, const Eigen::VectorXd& start,
    const std::vector<bool>& positive = {}) {
  LeastSquaresFit fit;
  const int n = static_cast<int>(start.size());
  const int m = static_cast<int>(y.size());
  fit.points = m;
  fit.dof = m - n;
  if (m <= n) return fit;
  auto is_positive = [&](int j) { return j < int(positive.size()) && positive[j]; };
  auto to_theta = [&](const Eigen::VectorXd& u) {
    Eigen::VectorXd theta = u;
    for (int j = 0; j < n; ++j)
      if (is_positive(j)) theta[j] = std::exp(u[j]);
    return theta;
  };
  struct Residuals {
    using Scalar = double;
    using InputType = Eigen::VectorXd;
    using ValueType = Eigen::VectorXd;
    using JacobianType = Eigen::MatrixXd;
    enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };
    std::function<void(const Eigen::VectorXd&, Eigen::VectorXd&)> evaluate;
    int n, m;
    int inputs() const { return n; }
    int values() const { return m; }
    int operator()(const Eigen::VectorXd& u, Eigen::VectorXd& r) const {
      evaluate(u, r);
      return 0;
    }
  };
  Residuals functor{[&](const Eigen::VectorXd& u, Eigen::VectorXd& r) {
                      const Eigen::VectorXd theta = to_theta(u);
                      r.resize(m);
                      for (int i = 0; i < m; ++i) {
                        const double f = model(std::size_t(i), theta);
                        // A trial where the model is undefined (e.g. K <= 0) gets a large
                        // residual, so LM rejects the step and shortens it.
                        r[i] = std::isfinite(f) ? (y[i] - f) / sigma[i] : 1e6;
                      }
                    },
                    n, m};
  Eigen::VectorXd u = start;
  for (int j = 0; j < n; ++j)
    if (is_positive(j)) u[j] = std::log(start[j]);
  // Central differences, step sqrt(1e-10) = 1e-5 relative (as analysis/calibration).
  Eigen::NumericalDiff<Residuals, Eigen::Central> numerical(functor, 1e-10);
  Eigen::LevenbergMarquardt<Eigen::NumericalDiff<Residuals, Eigen::Central>> lm(numerical);
  lm.parameters.maxfev = 4000;
  lm.parameters.xtol = 1e-12;
  lm.parameters.ftol = 1e-12;
  const auto status = lm.minimize(u);
  fit.converged = status == Eigen::LevenbergMarquardtSpace::RelativeReductionTooSmall ||
                  status == Eigen::LevenbergMarquardtSpace::RelativeErrorTooSmall ||
                  status == Eigen::LevenbergMarquardtSpace::RelativeErrorAndReductionTooSmall ||
                  status == Eigen::LevenbergMarquardtSpace::CosinusTooSmall ||
                  status == Eigen::LevenbergMarquardtSpace::FtolTooSmall ||
                  status == Eigen::LevenbergMarquardtSpace::XtolTooSmall ||
                  status == Eigen::LevenbergMarquardtSpace::GtolTooSmall;
  fit.estimate = to_theta(u);
  Eigen::VectorXd r(m);
  functor(u, r);
  fit.normalised_residuals = r;
  fit.chi2 = r.squaredNorm();
  fit.chi2_red = fit.chi2 / fit.dof;
  // Jacobian ∂r/∂θ in the original parameters (central differences, step 1e-5 max(|θ|, 1e-6)).
  Eigen::MatrixXd jacobian(m, n);
  for (int j = 0; j < n; ++j) {
    const double h = 1e-5 * std::max(std::abs(fit.estimate[j]), 1e-6);
    Eigen::VectorXd up = fit.estimate, down = fit.estimate;
    up[j] += h;
    down[j] -= h;
    if (is_positive(j)) down[j] = std::max(down[j], 0.5 * fit.estimate[j]);
    Eigen::VectorXd r_up(m), r_down(m);
    for (int i = 0; i < m; ++i) {
      r_up[i] = (y[i] - model(std::size_t(i), up)) / sigma[i];
      r_down[i] = (y[i] - model(std::size_t(i), down)) / sigma[i];
    }
    jacobian.col(j) = (r_up - r_down) / (up[j] - down[j]);
  }
  // ∂r/∂θ = −W^½ ∂f/∂θ, so Jᵀ J = (∂f/∂θ)ᵀ W (∂f/∂θ). A singular value below 1e-10 of the
  // largest: a direction the data do not constrain.
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(jacobian);
  const auto sv = svd.singularValues();
  fit.identifiable = sv.size() > 0 && std::isfinite(sv[0]) && sv[sv.size() - 1] > 1e-10 * sv[0];
  fit.covariance = Eigen::MatrixXd::Constant(n, n, std::numeric_limits<double>::quiet_NaN());
  fit.standard_error = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::quiet_NaN());
  if (fit.identifiable) {
    fit.covariance =
        (jacobian.transpose() * jacobian).ldlt().solve(Eigen::MatrixXd::Identity(n, n));
    fit.standard_error = fit.covariance.diagonal().cwiseSqrt();
  }
  return fit;
}

// Weighted straight line y = intercept + slope x (Numerical Recipes §15.2):
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
  double max_abs_residual() const {
    double worst = std::numeric_limits<double>::quiet_NaN();
    for (double r : normalised_residuals)
      worst = std::isnan(worst) ? std::abs(r) : std::max(worst, std::abs(r));
    return worst;
  }
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

}  // namespace granflow::dem
