// Kozeny-Carman permeability (Carman 1937, 1956) of a bed of spheres of diameter d and
// sphericity A, porosity n = 1 - ν:
//   κ = A² d² n³ / (180 (1 - n)²) = A² d² n³ / (180 ν²).
// Valid for packed beds; it is not a dilute-suspension law (κ ν -> ∞ as ν -> 0, so the
// per-particle drag tends to 0, not to Stokes drag).
#pragma once

namespace granflow::model {

// 1/(κ ν) = 180 ν / (A² d² n³)  (m⁻²).
inline double inverse_permeability_per_solid_fraction_kozeny_carman(double sphericity,
                                                                    double diameter,
                                                                    double solid_fraction) {
  const double porosity = 1.0 - solid_fraction;
  return 180.0 * solid_fraction /
         (sphericity * sphericity * diameter * diameter * porosity * porosity * porosity);
}

}  // namespace granflow::model
