// Inline definitions of the closure interface declared in closures.hpp: the per-option formulas
// live in their own headers (one closure per file); this file only dispatches on the enums.
// Included at the end of closures.hpp; do not include it directly.
#pragma once

#include <algorithm>
#include <cmath>

#include "continuum/model/closures.hpp"
#include "continuum/model/correlation_length_jenkins.hpp"
#include "continuum/model/correlation_length_toward_jamming.hpp"
#include "continuum/model/dissipation_resistance.hpp"
#include "continuum/model/effective_restitution.hpp"
#include "continuum/model/g0_carnahan_starling.hpp"
#include "continuum/model/g0_chialvo_sundaresan.hpp"
#include "continuum/model/g0_torquato.hpp"
#include "continuum/model/kinetic_theory_coefficients.hpp"
#include "continuum/model/mixture_viscosity_boyer.hpp"
#include "continuum/model/mixture_viscosity_einstein.hpp"
#include "continuum/model/mixture_viscosity_krieger_dougherty.hpp"
#include "continuum/model/permeability_ergun.hpp"
#include "continuum/model/permeability_kozeny_carman.hpp"
#include "continuum/model/permeability_seed_eq26.hpp"

namespace granflow::model {

// ---- collisional ------------------------------------------------------------------------------

inline double maximum_solid_fraction(const CollisionalParameters& p) {
  const double nu_c = p.jamming_fraction;
  if (!(nu_c > 0.0 && nu_c < 1.0)) detail::throw_bad_jamming_fraction("jamming_fraction", nu_c);
  if (p.radial_distribution == RadialDistributionKind::torquato &&
      !(nu_c > torquato_freezing_fraction)) {
    detail::throw_bad_jamming_fraction("torquato", nu_c);
  }
  return nu_c;
}

inline double effective_restitution(const CollisionalParameters& p) {
  switch (p.effective_restitution) {
    case EffectiveRestitutionKind::chialvo_sundaresan:
      return effective_restitution_chialvo_sundaresan(p.restitution, p.particle_friction);
    case EffectiveRestitutionKind::restitution:
      break;
  }
  return p.restitution;
}

// g0(ν) of the chosen option; ν already checked against (0, ν_c).
inline double radial_distribution(const CollisionalParameters& p, double nu) {
  switch (p.radial_distribution) {
    case RadialDistributionKind::torquato:
      return g0_torquato(nu, p.jamming_fraction);
    case RadialDistributionKind::chialvo_sundaresan:
      return g0_chialvo_sundaresan(nu, p.jamming_fraction);
    case RadialDistributionKind::carnahan_starling:
      break;
  }
  return g0_carnahan_starling(nu);
}

inline CollisionalCoefficients collisional_coefficients(const CollisionalParameters& p, double nu) {
  return collisional_coefficients(p, nu, effective_restitution(p));
}

inline CollisionalCoefficients collisional_coefficients(const CollisionalParameters& p, double nu,
                                                        double epsilon) {
  const double nu_max = maximum_solid_fraction(p);
  if (!(nu > 0.0 && nu < nu_max)) {
    detail::throw_solid_fraction_out_of_range("collisional_coefficients", nu, 0.0, nu_max);
  }
  CollisionalCoefficients c;
  c.nu = nu;
  c.g0 = radial_distribution(p, nu);
  c.G = nu * c.g0;
  c.epsilon = epsilon;
  c.f1 = kinetic_f1(nu, c.G, p.restitution);
  c.J = kinetic_J(p.restitution, c.G);
  c.f2 = kinetic_f2(nu, c.G, c.J);
  c.f3 = kinetic_f3(nu, c.G, c.epsilon);
  c.f4 = kinetic_f4(nu, c.G, kinetic_M(p.restitution, c.G));
  return c;
}

inline double correlation_length(const CollisionalParameters& p, const CollisionalCoefficients& c,
                                 double shear_rate, double T) {
  switch (p.correlation_length) {
    case CorrelationLengthKind::jenkins:
      return correlation_length_jenkins(p.correlation_length_constant, c.J, c.epsilon, p.diameter,
                                        shear_rate, T);
    case CorrelationLengthKind::toward_jamming:
      return p.diameter * correlation_length_ratio_toward_jamming(
                              p.correlation_length_constant, p.correlation_length_onset,
                              p.correlation_length_exponent, p.jamming_fraction, c.nu);
    case CorrelationLengthKind::diameter:
      break;
  }
  return p.diameter;
}

// p_COL = ρ_p f1 T (docs/model/closures.md).
inline double collisional_pressure(const CollisionalParameters& p, const CollisionalCoefficients& c,
                                   double T) {
  return p.particle_density * c.f1 * T;
}

// η_COL = ρ_p d f2 T^{1/2}.
inline double collisional_viscosity(const CollisionalParameters& p,
                                    const CollisionalCoefficients& c, double T) {
  return p.particle_density * p.diameter * c.f2 * std::sqrt(T);
}

// Γ = ρ_p f3 T^{3/2} / L.
inline double collisional_dissipation(const CollisionalParameters& p,
                                      const CollisionalCoefficients& c, double T, double L) {
  return p.particle_density * c.f3 * T * std::sqrt(T) / L;
}

// Γ = ρ_p f3 T^{3/2} / L(γ̇, T) = ρ_p f3 T² / (d max(T^{1/2}, a)).
inline double collisional_dissipation_at_shear_rate(const CollisionalParameters& p,
                                                    const CollisionalCoefficients& c,
                                                    double shear_rate, double T) {
  const double sqrt_T = std::sqrt(T);
  double speed = 0.0;  // a of correlation_length_jenkins.hpp; 0 for L independent of T
  double ratio = 1.0;  // L/d of a length independent of T
  switch (p.correlation_length) {
    case CorrelationLengthKind::jenkins:
      speed = jenkins_correlation_speed(p.correlation_length_constant, c.J, c.epsilon, p.diameter,
                                        shear_rate);
      break;
    case CorrelationLengthKind::toward_jamming:
      ratio = correlation_length_ratio_toward_jamming(
          p.correlation_length_constant, p.correlation_length_onset, p.correlation_length_exponent,
          p.jamming_fraction, c.nu);
      break;
    case CorrelationLengthKind::diameter:
      break;
  }
  const double scale = std::max(sqrt_T, speed);
  if (scale == 0.0) return 0.0;  // T = 0 and γ̇ = 0 (or L = d and T = 0)
  return p.particle_density * c.f3 * T * T / (p.diameter * ratio * scale);
}

// k_COL = ρ_p d f4 T^{1/2}.
inline double collisional_conductivity(const CollisionalParameters& p,
                                       const CollisionalCoefficients& c, double T) {
  return p.particle_density * p.diameter * c.f4 * std::sqrt(T);
}

// ---- liquid -----------------------------------------------------------------------------------

inline double maximum_mixture_solid_fraction(const LiquidParameters& l) {
  switch (l.mixture_viscosity) {
    case MixtureViscosityKind::krieger_dougherty:
    case MixtureViscosityKind::boyer:
      return l.maximum_packing;
    case MixtureViscosityKind::einstein:
      break;
  }
  return 1.0;
}

inline double mixture_viscosity(const LiquidParameters& l, double nu) {
  const double nu_max = maximum_mixture_solid_fraction(l);
  if (!(nu >= 0.0 && nu < nu_max)) {
    detail::throw_solid_fraction_out_of_range("mixture_viscosity", nu, 0.0, nu_max);
  }
  switch (l.mixture_viscosity) {
    case MixtureViscosityKind::krieger_dougherty:
      return mixture_viscosity_krieger_dougherty(l.viscosity, nu, l.maximum_packing);
    case MixtureViscosityKind::boyer:
      return mixture_viscosity_boyer(l.viscosity, nu, l.maximum_packing);
    case MixtureViscosityKind::einstein:
      break;
  }
  return mixture_viscosity_einstein(l.viscosity, nu);
}

// 1/(κ ν), finite for 0 ≤ ν < 1 (no range check: callers check).
inline double inverse_permeability_per_solid_fraction(const LiquidParameters& l, double diameter,
                                                      double nu) {
  switch (l.permeability) {
    case PermeabilityKind::kozeny_carman:
      return inverse_permeability_per_solid_fraction_kozeny_carman(l.sphericity, diameter, nu);
    case PermeabilityKind::ergun:
      return inverse_permeability_per_solid_fraction_ergun(l.sphericity, diameter, nu);
    case PermeabilityKind::seed_eq26:
      break;
  }
  return inverse_permeability_per_solid_fraction_seed_eq26(l.sphericity, diameter, nu);
}

inline double inverse_permeability(const LiquidParameters& l, double diameter, double nu) {
  if (!(nu >= 0.0 && nu < 1.0)) {
    detail::throw_solid_fraction_out_of_range("inverse_permeability", nu, 0.0, 1.0);
  }
  return nu * inverse_permeability_per_solid_fraction(l, diameter, nu);
}

inline double permeability(const LiquidParameters& l, double diameter, double nu) {
  if (!(nu > 0.0 && nu < 1.0)) {
    detail::throw_solid_fraction_out_of_range("permeability", nu, 0.0, 1.0);
  }
  return 1.0 / (nu * inverse_permeability_per_solid_fraction(l, diameter, nu));
}

inline double forchheimer_coefficient(const LiquidParameters& l, double diameter, double nu) {
  if (!(nu >= 0.0 && nu < 1.0)) {
    detail::throw_solid_fraction_out_of_range("forchheimer_coefficient", nu, 0.0, 1.0);
  }
  if (l.permeability != PermeabilityKind::ergun) return 0.0;
  return forchheimer_coefficient_ergun(l.density, l.sphericity, diameter, nu);
}

// β = η0 n / κ (seed Eq. 25).
inline double drag_coefficient(const LiquidParameters& l, double diameter, double nu) {
  return l.viscosity * (1.0 - nu) * inverse_permeability(l, diameter, nu);
}

// β + c_F n |q|, |q| = n |u_L - u_G|.
inline double drag_coefficient_with_inertia(const LiquidParameters& l, double diameter, double nu,
                                            double relative_speed) {
  const double porosity = 1.0 - nu;
  return drag_coefficient(l, diameter, nu) +
         forchheimer_coefficient(l, diameter, nu) * porosity * porosity * std::fabs(relative_speed);
}

// c_p = β π d³ / (6 ν) = η0 n (π d³/6) / (κ ν); seed_eq26: 3π η0 d n F(ν) / A².
inline double particle_drag_coefficient(const LiquidParameters& l, double diameter, double nu) {
  if (!(nu >= 0.0 && nu < 1.0)) {
    detail::throw_solid_fraction_out_of_range("particle_drag_coefficient", nu, 0.0, 1.0);
  }
  constexpr double sphere_volume_factor = 0.52359877559829887;  // π/6
  return l.viscosity * (1.0 - nu) * sphere_volume_factor * diameter * diameter * diameter *
         inverse_permeability_per_solid_fraction(l, diameter, nu);
}

inline double dissipation_resistance(double nu, double g0) {
  return dissipation_resistance_koch_sangani(nu, g0);
}

// Λ = 54 ν η0 R_diss T / d², R_diss with `g0`, or with the liquid's own
// dissipation_radial_distribution at ν when it has one.
inline double liquid_fluctuation_dissipation(const LiquidParameters& l, double diameter, double nu,
                                             double g0, double T) {
  if (l.dissipation_radial_distribution) {
    CollisionalParameters structure;
    structure.radial_distribution = *l.dissipation_radial_distribution;
    structure.jamming_fraction = l.dissipation_jamming_fraction;
    g0 = radial_distribution(structure, nu);
  }
  return 54.0 * nu * l.viscosity * dissipation_resistance(nu, g0) * T / (diameter * diameter);
}

}  // namespace granflow::model
