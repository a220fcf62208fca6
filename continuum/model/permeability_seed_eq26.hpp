// Intrinsic permeability of seed Eq. 26 (Marveggio, Zerbi & di Prisco, attributed there to
// Ergun 1952), with A the sphericity and e the void ratio:
//   κ = A² d² [180/e² + 18 e²/(1+e)³ (1 + 1.5 (1/(1+e))^{1/2})]^{-1}.
// With ν = 1/(1+e) (so 1/e = ν/(1-ν), e/(1+e) = 1-ν) this is exactly
//   κ = A² d² / (18 ν F(ν)),  F(ν) = 10 ν/(1-ν)² + (1-ν)² (1 + 1.5 ν^{1/2}),
// F being the low-Reynolds drag correlation of van der Hoef, Beetstra & Kuipers (2005), J. Fluid
// Mech. 528, 233 / Beetstra et al. (2007), AIChE J. 53, 489 (drag normalised by Stokes drag).
// The hot path uses the ν form; the void-ratio form is kept as written for the tests.
#pragma once

#include <cmath>

namespace granflow::model {

// F(ν) of van der Hoef et al. (2005); F(0) = 1 (Stokes drag).
inline double van_der_hoef_drag_factor(double solid_fraction) {
  const double porosity = 1.0 - solid_fraction;
  return 10.0 * solid_fraction / (porosity * porosity) +
         porosity * porosity * (1.0 + 1.5 * std::sqrt(solid_fraction));
}

// 1/(κ ν) = 18 F(ν) / (A² d²)  (m⁻²), finite as ν -> 0.
inline double inverse_permeability_per_solid_fraction_seed_eq26(double sphericity, double diameter,
                                                                double solid_fraction) {
  return 18.0 * van_der_hoef_drag_factor(solid_fraction) /
         (sphericity * sphericity * diameter * diameter);
}

// Seed Eq. 26 exactly as printed, in terms of the void ratio e (m²).
inline double permeability_seed_eq26_void_ratio(double sphericity, double diameter,
                                                double void_ratio) {
  const double e = void_ratio;
  const double bracket = 180.0 / (e * e) + 18.0 * e * e / ((1.0 + e) * (1.0 + e) * (1.0 + e)) *
                                               (1.0 + 1.5 * std::sqrt(1.0 / (1.0 + e)));
  return sphericity * sphericity * diameter * diameter / bracket;
}

}  // namespace granflow::model
