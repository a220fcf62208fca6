#include "analysis/calibration/steady_shear_model.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "continuum/model/correlation_length_jenkins.hpp"

namespace granflow::calibration {

namespace {

// s solving d f2 γ̇² = f3 s³ / (d max(s, a)) + λ s (see the header).
double solve_sqrt_temperature(double d, double f2, double f3, double lambda, double speed,
                              double shear_rate) {
  const double production = d * f2 * shear_rate * shear_rate;  // C
  // s ≥ a: (f3/d) s² + λ s - C = 0, stable root 2C / (λ + sqrt(λ² + 4 (f3/d) C)).
  const double quad = f3 / d;
  const double s_quadratic =
      2.0 * production / (lambda + std::sqrt(lambda * lambda + 4.0 * quad * production));
  if (s_quadratic >= speed) return s_quadratic;
  // s < a: g(s) = (f3/(d a)) s³ + λ s - C, increasing and convex for s > 0; Newton from s = a
  // (g(a) > 0 here) decreases monotonically to the root.
  const double cubic = f3 / (d * speed);
  double s = speed;
  for (int i = 0; i < 200; ++i) {
    const double g = cubic * s * s * s + lambda * s - production;
    const double slope = 3.0 * cubic * s * s + lambda;
    const double next = s - g / slope;
    if (!(next < s) || next <= 0.0) break;  // converged to rounding (or the root is at 0)
    s = next;
  }
  return s;
}

}  // namespace

double steady_sqrt_temperature_at(const continuum::MultiRegimeSettings& settings,
                                  const ModelFactors& factors, double solid_fraction,
                                  double shear_rate) {
  const auto& p = settings.collisional_parameters;
  const auto c = model::collisional_coefficients(p, solid_fraction);
  double lambda = 0.0;
  if (settings.fluctuation_dissipation)  // Λ(T = 1) / ρ_p, Λ ∝ T (Koch & Sangani 1999)
    lambda = factors.fluctuation_dissipation *
             model::liquid_fluctuation_dissipation(settings.liquid_parameters, p.diameter,
                                                   solid_fraction, c.g0, 1.0) /
             p.particle_density;
  const double speed = p.correlation_length == model::CorrelationLengthKind::jenkins
                           ? model::jenkins_correlation_speed(p.correlation_length_constant, c.J,
                                                              c.epsilon, p.diameter, shear_rate)
                           : 0.0;
  return solve_sqrt_temperature(p.diameter, c.f2, c.f3, lambda, speed, shear_rate);
}

SteadyShearState steady_simple_shear(const continuum::MultiRegimeSettings& settings,
                                     const ModelFactors& factors, double shear_rate,
                                     double normal_stress) {
  if (!settings.collisional || settings.force_chains)
    throw std::invalid_argument(
        "calibration forward model: needs collisional.enabled and force_chains off (steady "
        "simple shear at imposed normal stress, as rev simple_shear constant_pressure)");
  const auto& p = settings.collisional_parameters;
  const double rho_p = p.particle_density, d = p.diameter;
  const double nu_max = model::maximum_solid_fraction(p);
  const auto pressure = [&](double nu) {
    const double s = steady_sqrt_temperature_at(settings, factors, nu, shear_rate);
    return rho_p * model::collisional_coefficients(p, nu).f1 * s * s;
  };
  SteadyShearState out;
  // Dense branch: from the minimum of p_COL(ν) (coarse scan) up to ν_max, where p_COL -> ∞.
  constexpr int scan = 100;
  double nu_lo = nu_max / scan, p_lo = pressure(nu_lo);
  for (int i = 2; i < scan; ++i) {
    const double nu = nu_max * i / scan;
    const double pv = pressure(nu);
    if (pv < p_lo) nu_lo = nu, p_lo = pv;
  }
  nu_lo = std::max(nu_lo - nu_max / scan, nu_max / scan);  // the minimum lies within one cell
  double nu_hi = nu_max * (1.0 - 1e-12);
  if (!(pressure(nu_lo) <= normal_stress)) {
    out.why =
        "normal stress below the smallest steady p_COL (inertial number above the largest "
        "steady I of kinetic theory)";
    return out;
  }
  if (!(pressure(nu_hi) >= normal_stress)) {
    out.why = "normal stress above p_COL at the jamming fraction (quasi-static)";
    return out;
  }
  for (int i = 0; i < 200; ++i) {  // bisection to the last representable bracket
    const double mid = 0.5 * (nu_lo + nu_hi);
    if (mid <= nu_lo || mid >= nu_hi) break;
    (pressure(mid) < normal_stress ? nu_lo : nu_hi) = mid;
  }
  const double nu = 0.5 * (nu_lo + nu_hi);
  const double s = steady_sqrt_temperature_at(settings, factors, nu, shear_rate);
  const auto c = model::collisional_coefficients(p, nu);
  const double p_col = rho_p * c.f1 * s * s;
  double tau = rho_p * d * c.f2 * s * shear_rate;  // τ_COL = η_COL γ̇
  if (settings.liquid) {
    if (nu >= model::maximum_mixture_solid_fraction(settings.liquid_parameters)) {
      out.why = "steady solid fraction above the maximum packing of η(ν)";
      return out;
    }
    tau += model::mixture_viscosity(settings.liquid_parameters, nu) * shear_rate;  // τ_L
    out.viscous_number = settings.liquid_parameters.viscosity * shear_rate / p_col;
  }
  out.ok = std::isfinite(tau) && std::isfinite(s);
  out.solid_fraction = nu;
  out.granular_temperature = s * s;
  out.scaled_temperature = s * s / (d * d * shear_rate * shear_rate);
  out.shear_stress = tau;
  out.friction = tau / p_col;
  out.inertial_number = shear_rate * d / std::sqrt(p_col / rho_p);
  if (!out.ok) out.why = "non-finite steady state";
  return out;
}

}  // namespace granflow::calibration
