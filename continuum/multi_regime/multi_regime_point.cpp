#include "continuum/multi_regime/multi_regime_point.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "continuum/model/force_chains/critical_state_lade_duncan.hpp"

namespace granflow::continuum {

MultiRegimePoint::MultiRegimePoint(MultiRegimeSettings settings) : settings_(std::move(settings)) {
  if (!settings_.liquid) settings_.fluctuation_dissipation = false;
  if (settings_.force_chains) force_chain_model_.emplace(settings_.force_chain_parameters);
  if (settings_.collisional)
    effective_restitution_ = model::effective_restitution(settings_.collisional_parameters);
  // Plane strain, isochoric flow coaxial with D (cos 3θ = 0): τ/σ_yy = M(θ = 0)/√3 on the
  // Lade-Duncan critical state locus.
  if (settings_.inertial_contact_friction > 0.0)
    inertial_contact_friction_ = settings_.inertial_contact_friction;
  else if (contact_stress_on(settings_))
    inertial_contact_friction_ =
        model::force_chains::CriticalStateLadeDuncan(settings_.force_chain_parameters)
            .stress_ratio(0.0) /
        std::sqrt(3.0);
}

PointState MultiRegimePoint::initial_state(double void_ratio, double effective_pressure, double ocr,
                                           double granular_temperature) const {
  PointState state;
  state.solid_fraction = 1.0 / (1.0 + void_ratio);
  state.granular_temperature = granular_temperature;
  if (force_chain_model_)
    state.force_chains = force_chain_model_->isotropic_state(effective_pressure, void_ratio, ocr);
  state.force_chains.void_ratio = void_ratio;
  return state;
}

StressParts MultiRegimePoint::advance(PointState& state, const Eigen::Matrix3d& strain_rate,
                                      double dt) const {
  // 1. mass balance: ν (1+e) = 1, 1+e ∝ exp(-ε_v) with compression-positive ε_v
  state.solid_fraction *= std::exp(strain_rate.trace() * dt);
  return advance_mass_balanced(state, strain_rate, dt);
}

StressParts MultiRegimePoint::advance_mass_balanced(PointState& state,
                                                    const Eigen::Matrix3d& strain_rate, double dt,
                                                    double volume_factor) const {
  const double T_start = state.granular_temperature;
  // 2. force chains (rate independent: the increment is ε̇ dt)
  model::force_chains::UpdateInfo info;
  if (force_chain_model_) {
    info = force_chain_model_->update(state.force_chains, strain_rate * dt, dt, T_start,
                                      volume_factor);
  }
  state.force_chains.void_ratio = 1.0 / state.solid_fraction - 1.0;
  // 3.-4. T over dt at the new ν, then the rate-dependent parts
  StressParts parts = update(state, strain_rate, dt);
  parts.force_chain = state.force_chains.stress;
  parts.force_chain_update = info;
  return parts;
}

bool contact_stress_on(const MultiRegimeSettings& s) {
  return s.inertial_contact != 0.0 || (s.liquid && s.viscous_contact != 0.0);
}

double contact_pressure(const MultiRegimeSettings& s, double solid_fraction, double shear_rate) {
  if (!contact_stress_on(s)) return 0.0;
  const auto& p = s.collisional_parameters;
  const double gap = model::maximum_solid_fraction(p) - solid_fraction;
  if (!(gap > 0))
    throw std::domain_error("contacts' dense-flow stress: solid fraction at or above jamming");
  const double scale = s.inertial_contact * p.diameter * shear_rate;
  // inertial scale ρ_p (a_c d γ̇)², viscous scale b_v η0 γ̇ (Trulsson et al. 2012: K = J + α I²)
  const double viscous =
      s.liquid ? s.viscous_contact * s.liquid_parameters.viscosity * shear_rate : 0.0;
  return (p.particle_density * scale * scale + viscous) * std::pow(gap, -s.inertial_contact_power);
}

double MultiRegimePoint::solid_fraction_limit() const {
  double limit = 1.0;
  if (settings_.collisional)
    limit = std::min(limit, model::maximum_solid_fraction(settings_.collisional_parameters));
  if (settings_.liquid)
    limit = std::min(limit, model::maximum_mixture_solid_fraction(settings_.liquid_parameters));
  return limit * (1.0 - 1e-9);
}

double MultiRegimePoint::inertial_contact_pressure(double solid_fraction, double shear_rate) const {
  return contact_pressure(settings_, solid_fraction, shear_rate);
}

double MultiRegimePoint::shear_rate(const Eigen::Matrix3d& strain_rate) {
  const Eigen::Matrix3d deviator =
      strain_rate - strain_rate.trace() / 3.0 * Eigen::Matrix3d::Identity();
  // γ̇ = sqrt(2 ε̇':ε̇'): in simple shear ε̇_xy = ε̇_yx = γ̇/2 gives ε̇':ε̇' = γ̇²/2.
  return std::sqrt(2.0 * deviator.cwiseProduct(deviator).sum());
}

StressParts MultiRegimePoint::evaluate(const PointState& state,
                                       const Eigen::Matrix3d& strain_rate) const {
  model::CollisionalCoefficients c;
  double lambda_over_T = 0.0;
  if (settings_.collisional) {
    c = coefficients(state.solid_fraction);
    lambda_over_T = liquid_dissipation_per_temperature(state.solid_fraction, c.g0);
  }
  return evaluate(state, strain_rate, c, lambda_over_T);
}

model::CollisionalCoefficients MultiRegimePoint::coefficients(double nu) const {
  return model::collisional_coefficients(settings_.collisional_parameters, nu,
                                         effective_restitution_);
}

double MultiRegimePoint::liquid_dissipation_per_temperature(double nu, double g0) const {
  if (!settings_.fluctuation_dissipation) return 0.0;
  return model::liquid_fluctuation_dissipation(
      settings_.liquid_parameters, settings_.collisional_parameters.diameter, nu, g0, 1.0);
}

RiccatiCoefficients MultiRegimePoint::temperature_equation(const PointState& state,
                                                           const Eigen::Matrix3d& strain_rate,
                                                           const model::CollisionalCoefficients& c,
                                                           double lambda_over_T) const {
  // The coefficients of evaluate() below, without the stresses.
  const Eigen::Matrix3d deviator =
      strain_rate - strain_rate.trace() / 3.0 * Eigen::Matrix3d::Identity();
  const double deviator_norm2 = deviator.cwiseProduct(deviator).sum();  // ε̇':ε̇'
  const double gamma_dot = std::sqrt(2.0 * deviator_norm2);
  const double L = model::correlation_length(settings_.collisional_parameters, c, gamma_dot,
                                             state.granular_temperature);
  return riccati(state.solid_fraction, deviator_norm2, strain_rate.trace(), c, L, lambda_over_T);
}

RiccatiCoefficients MultiRegimePoint::riccati(double nu, double deviator_norm2, double trace,
                                              const model::CollisionalCoefficients& c,
                                              double correlation_length,
                                              double lambda_over_T) const {
  // Coefficients of ds/dt (granular_temperature_update.hpp), divided through by (3/2) ρ_p ν and 2s.
  const auto& p = settings_.collisional_parameters;
  RiccatiCoefficients k;
  const double inv_3nu = 1.0 / (3.0 * nu);  // (one division for the three coefficients)
  k.a = 2.0 * p.diameter * c.f2 * deviator_norm2 * inv_3nu;
  k.b = c.f3 * inv_3nu / correlation_length;
  k.c = -c.f1 * trace * inv_3nu;  // compaction (tr ε̇ > 0) heats
  if (settings_.fluctuation_dissipation) {
    // Λ = 54 ν η0 R_diss T / d² -> c += 54 ν η0 R_diss / (3 ν ρ_p d²) ... written via Λ/T
    k.c += lambda_over_T * inv_3nu / p.particle_density;
  }
  return k;
}

StressParts MultiRegimePoint::evaluate(const PointState& state, const Eigen::Matrix3d& strain_rate,
                                       const model::CollisionalCoefficients& c,
                                       double lambda_over_T) const {
  StressParts parts;
  if (settings_.force_chains) parts.force_chain = state.force_chains.stress;
  const double nu = state.solid_fraction;
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d deviator = strain_rate - strain_rate.trace() / 3.0 * identity;
  const double deviator_norm2 = deviator.cwiseProduct(deviator).sum();  // ε̇':ε̇'

  if (settings_.collisional) {
    const auto& p = settings_.collisional_parameters;
    parts.coefficients = c;
    const double T = state.granular_temperature;
    const double gamma_dot = std::sqrt(2.0 * deviator_norm2);
    parts.collisional_pressure = model::collisional_pressure(p, c, T);
    parts.collisional_viscosity = model::collisional_viscosity(p, c, T);
    parts.correlation_length = model::correlation_length(p, c, gamma_dot, T);
    parts.collisional_dissipation =
        model::collisional_dissipation(p, c, T, parts.correlation_length);
    // σ_COL = p_COL I + 2 η_COL ε̇' (compression-positive; Berzi et al. 2011, no bulk viscosity)
    parts.collisional =
        parts.collisional_pressure * identity + 2.0 * parts.collisional_viscosity * deviator;
    parts.collisional_power = parts.collisional_pressure * strain_rate.trace() +
                              2.0 * parts.collisional_viscosity * deviator_norm2;
    parts.temperature_equation = riccati(nu, deviator_norm2, strain_rate.trace(), c,
                                         parts.correlation_length, lambda_over_T);
    // Λ = (Λ/T) T: linear in T (model::liquid_fluctuation_dissipation)
    if (settings_.fluctuation_dissipation) parts.liquid_dissipation = lambda_over_T * T;
  }
  if (contact_stress_on(settings_)) {
    // σ_IC = p_IC I + 2 η_IC ε̇', η_IC = μ_IC p_IC / γ̇ (in simple shear τ_IC = μ_IC p_IC); its
    // work is dissipated by the contacts and does not feed T.
    const double gamma_dot = std::sqrt(2.0 * deviator_norm2);
    parts.inertial_contact_pressure = inertial_contact_pressure(nu, gamma_dot);
    parts.inertial_contact = parts.inertial_contact_pressure * identity;
    if (gamma_dot > 0)
      parts.inertial_contact +=
          2.0 * inertial_contact_friction_ * parts.inertial_contact_pressure / gamma_dot * deviator;
  }
  if (settings_.liquid) {
    // σ_L deviator = 2 η(ν) dev(ε̇_L) (seed Eq. 27); the pore pressure u_w is the driver's.
    parts.mixture_viscosity = model::mixture_viscosity(settings_.liquid_parameters, nu);
    parts.liquid = 2.0 * parts.mixture_viscosity * deviator;
  }
  return parts;
}

StressParts MultiRegimePoint::update(PointState& state, const Eigen::Matrix3d& strain_rate,
                                     double dt, double heat_capacity_factor) const {
  // ν is frozen over the T update, so the collisional coefficients (g0, f1..f4 of ν:
  // docs/model/closures.md) and Λ/T are evaluated once and serve the Riccati coefficients at the
  // start and the stresses at the end (bit for bit the two evaluations they replace; the
  // diagnostic Λ = (Λ/T) T differs from Λ evaluated at T by round-off).
  model::CollisionalCoefficients c;
  double lambda_over_T = 0.0;
  if (settings_.collisional) {
    c = coefficients(state.solid_fraction);
    lambda_over_T = liquid_dissipation_per_temperature(state.solid_fraction, c.g0);
    RiccatiCoefficients k = temperature_equation(state, strain_rate, c, lambda_over_T);
    if (heat_capacity_factor != 1.0) {  // (x / 1 = x: three divisions saved per point)
      k.a /= heat_capacity_factor;
      k.b /= heat_capacity_factor;
      k.c /= heat_capacity_factor;
    }
    const double s0 = std::sqrt(std::max(state.granular_temperature, 0.0));
    const double s1 = advance_sqrt_temperature(s0, k, dt);
    state.granular_temperature = s1 * s1;
  }
  return evaluate(state, strain_rate, c, lambda_over_T);
}

}  // namespace granflow::continuum
