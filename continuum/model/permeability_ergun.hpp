// Ergun (1952), Chem. Eng. Prog. 48, 89, for a bed of spheres of diameter d, sphericity A and
// porosity n = 1 - ν, with superficial (Darcy) velocity q = n (u_L - u_G):
//   -∇p = 150 η0 ν² q / (A² d² n³) + 1.75 ρ_L ν |q| q / (A d n³).
// The closure API is Darcy-like (κ), so the viscous part is returned as the permeability
//   κ = A² d² n³ / (150 ν²),
// and the inertial (Forchheimer) part as a separate coefficient
//   c_F = 1.75 ρ_L ν / (A d n³)   (kg/m⁴),   -∇p = (η0/κ) q + c_F |q| q.
// drag_coefficient() returns only the Darcy part; drag_coefficient_with_inertia() adds c_F |q|.
#pragma once

namespace granflow::model {

// 1/(κ ν) = 150 ν / (A² d² n³)  (m⁻²).
inline double inverse_permeability_per_solid_fraction_ergun(double sphericity, double diameter,
                                                            double solid_fraction) {
  const double porosity = 1.0 - solid_fraction;
  return 150.0 * solid_fraction /
         (sphericity * sphericity * diameter * diameter * porosity * porosity * porosity);
}

// c_F = 1.75 ρ_L ν / (A d n³)  (kg/m⁴).
inline double forchheimer_coefficient_ergun(double liquid_density, double sphericity,
                                            double diameter, double solid_fraction) {
  const double porosity = 1.0 - solid_fraction;
  return 1.75 * liquid_density * solid_fraction /
         (sphericity * diameter * porosity * porosity * porosity);
}

}  // namespace granflow::model
