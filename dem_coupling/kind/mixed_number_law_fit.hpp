// Immersed DEM sweeps: a free viscous-inertial law in the mixed number and the split of
// Boyer's μ(J) into its contact and hydrodynamic parts.
//
// Mixed number K = J + α I² (Trulsson, Andreotti & Claudin 2012, PRL 109, 118305; Ness & Sun 2015)
// with a μ(K) of the μ(I) form and μ_1, μ_2, K_0 and α fitted together (weighted least squares,
// statistics/least_squares.hpp; K_0 > 0 and α > 0 by the transform θ = e^u):
//   μ(K) = μ_1 + (μ_2 − μ_1)/(1 + K_0/K),
// then, with that α, φ(K) = φ_m/(1 + b K^½) (φ_m and b > 0 fitted; Boyer's φ(J) form in K).
// This replaces the one-parameter α of mixed_number_fit.hpp (Boyer's constants imposed), which is
// biased when the DEM's μ(J) constants differ from Boyer's beads.
//
// Boyer, Guazzelli & Pouliquen 2011 (PRL 107, 188301; docs/dem_dataset.md): μ(J) = μ_c(J) + μ_h(J)
// with
//   contact part      μ_c(J) = μ1 + (μ2 − μ1)/(1 + J0/J),  μ1 = 0.32, μ2 = 0.7, J0 = 0.005,
//   hydrodynamic part μ_h(J) = J + (5/2) ν_m J^½,          ν_m = 0.585,
// and φ(J) = ν_m/(1 + J^½). The DEM's τ_contact/σ_yy is compared with μ_c and τ_lub/σ_yy with μ_h:
// the DEM has pairwise lubrication for h < h_max only, no far-field hydrodynamics.
// Header-only (see statistics/least_squares.hpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "statistics/least_squares.hpp"

namespace granflow::dem {

using statistics::LeastSquaresFit;
using statistics::ParameterBounds;

namespace boyer2011 {
constexpr double mu_1 = 0.32, mu_2 = 0.7, j_0 = 0.005, nu_m = 0.585;
inline double contact_friction(double j) { return mu_1 + (mu_2 - mu_1) / (1.0 + j_0 / j); }
inline double hydrodynamic_friction(double j) { return j + 2.5 * nu_m * std::sqrt(j); }
inline double solid_fraction(double j) { return nu_m / (1.0 + std::sqrt(j)); }
// d μ_c / dJ (for the error of μ_c(J) from that of J).
inline double contact_friction_slope(double j) {
  return (mu_2 - mu_1) * j_0 / ((j + j_0) * (j + j_0));
}
}  // namespace boyer2011

inline double mixed_number_friction_law(double k, double mu_1, double mu_2, double k_0) {
  return mu_1 + (mu_2 - mu_1) / (1.0 + k_0 / k);
}
inline double mixed_number_solid_fraction_law(double k, double phi_m, double b) {
  return phi_m / (1.0 + b * std::sqrt(k));
}

struct MixedNumberLawFit {
  std::vector<double> viscous, inertial, friction, friction_err, solid_fraction,
      solid_fraction_err;  // the points used
  LeastSquaresFit mu;      // estimate = (μ_1, μ_2, K_0, α)
  LeastSquaresFit phi;     // estimate = (φ_m, b) at the fitted α
  double value(int j) const { return mu.estimate.size() ? mu.estimate[j] : NAN; }
  double error(int j) const { return mu.standard_error.size() ? mu.standard_error[j] : NAN; }
  double alpha() const { return value(3); }
  double alpha_err() const { return error(3); }
  double mixed_number(std::size_t i) const {
    return viscous[i] + alpha() * inertial[i] * inertial[i];
  }
};

// J, I, μ, err μ, φ, err φ per condition; points with a non-finite value, J <= 0 or a
// non-positive error are skipped. μ(K) needs >= 5 points (4 parameters), φ(K) >= 3.
inline MixedNumberLawFit fit_mixed_number_law(const std::vector<double>& viscous_number,
                                              const std::vector<double>& inertial_number,
                                              const std::vector<double>& friction,
                                              const std::vector<double>& friction_err,
                                              const std::vector<double>& solid_fraction,
                                              const std::vector<double>& solid_fraction_err) {
  MixedNumberLawFit fit;
  for (std::size_t k = 0; k < viscous_number.size(); ++k) {
    const double values[] = {viscous_number[k], inertial_number[k], friction[k],
                             friction_err[k],   solid_fraction[k],  solid_fraction_err[k]};
    if (!std::all_of(std::begin(values), std::end(values),
                     [](double v) { return std::isfinite(v); }))
      continue;
    if (!(viscous_number[k] > 0 && friction_err[k] > 0 && solid_fraction_err[k] > 0)) continue;
    fit.viscous.push_back(viscous_number[k]);
    fit.inertial.push_back(inertial_number[k]);
    fit.friction.push_back(friction[k]);
    fit.friction_err.push_back(friction_err[k]);
    fit.solid_fraction.push_back(solid_fraction[k]);
    fit.solid_fraction_err.push_back(solid_fraction_err[k]);
  }
  const std::size_t n = fit.viscous.size();
  fit.mu.points = int(n);
  fit.phi.points = int(n);
  if (n < 5) return fit;
  auto mu_model = [&](std::size_t i, const Eigen::VectorXd& t) {
    const double k = fit.viscous[i] + t[3] * fit.inertial[i] * fit.inertial[i];
    return mixed_number_friction_law(k, t[0], t[1], t[2]);
  };
  // Starts over a ladder of (K_0, α): the χ² surface is flat along K_0 when the data do not reach
  // μ_2, and several minima in α exist when the viscous and inertial points do not overlap in K.
  const auto [lo, hi] = std::minmax_element(fit.friction.begin(), fit.friction.end());
  for (double k_0 : {1e-3, 1e-2, 1e-1})
    for (double alpha : {0.01, 0.1, 1.0, 10.0}) {
      Eigen::VectorXd start(4);
      start << *lo - 0.02, *hi + 0.2, k_0, alpha;
      LeastSquaresFit trial = statistics::weighted_least_squares(
          mu_model, fit.friction, fit.friction_err, start,
          {ParameterBounds{}, ParameterBounds{}, ParameterBounds::positive(),
           ParameterBounds::positive()});
      if (std::isfinite(trial.chi2) && (fit.mu.estimate.size() == 0 || trial.chi2 < fit.mu.chi2))
        fit.mu = trial;
    }
  if (fit.mu.estimate.size() == 0) return fit;
  const double alpha = fit.alpha();
  auto phi_model = [&](std::size_t i, const Eigen::VectorXd& t) {
    return mixed_number_solid_fraction_law(
        fit.viscous[i] + alpha * fit.inertial[i] * fit.inertial[i], t[0], t[1]);
  };
  Eigen::VectorXd start(2);
  start << *std::max_element(fit.solid_fraction.begin(), fit.solid_fraction.end()) + 0.01, 1.0;
  fit.phi =
      statistics::weighted_least_squares(phi_model, fit.solid_fraction, fit.solid_fraction_err, start,
                                       {ParameterBounds{}, ParameterBounds::positive()});
  return fit;
}

}  // namespace granflow::dem
