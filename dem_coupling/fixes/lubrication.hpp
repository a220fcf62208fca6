// Pairwise lubrication resistances of two nearly touching spheres in a Newtonian liquid of
// viscosity η, radii r_i, r_j, surface gap h (leading terms of the near-field asymptotics).
//
// Normal (squeeze) mode, Reynolds lubrication between spheres (Kim & Karrila 1991, §9.3; Ball &
// Melrose 1997, Adv. Colloid Interface Sci. 59, 19; Jeffrey & Onishi 1984, J. Fluid Mech. 139,
// 261, X^A_11 = β²/(1+β)² ξ⁻¹ + ...):
//   F_n = -c_n v_n,   c_n = 6π η a² / h,   a = r_i r_j / (r_i + r_j)  (reduced radius).
// Tangential (shear) mode, the log(1/ξ) term of Y^A_11 (Jeffrey & Onishi 1984; Kim & Karrila
// 1991, §11.3; written for unequal spheres as in LAMMPS COLLOID pair lubricate/poly,
// a_sh = 6π η r_i 4β(2+β+2β²)/(15(1+β)³) ln(1/ξ), β = r_j / r_i):
//   F_t = -c_t v_t,   c_t = 6π η a (4/15) (2 + β + 2β²)/(1 + β)² ln(1/ξ),  ξ = 2h/(r_i + r_j).
// In terms of the reduced radius the prefactor 6π η r_i 4β(2+β+2β²)/(15(1+β)³) is exactly
// 6π η a (4/15)(2+β+2β²)/(1+β)² and is symmetric in i, j; the gap is scaled with the mean radius
// (Jeffrey & Onishi's ξ = s - 2, s = 2r/(r_i + r_j)), so the force is symmetric too (LAMMPS
// scales by r_i, which differs only in the O(1) term that the asymptotics leave out). For equal
// spheres of radius R this is Ball & Melrose's c_t = 6π η R (1/6) ln(R/h).
// Both use max(h, h_min): below h_min (and for overlapping spheres, where contact forces act)
// the resistance is held at its h_min value, the usual regularisation (surface roughness).
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

namespace granflow::dem {

// a = r_i r_j / (r_i + r_j), m.
inline double reduced_radius(double radius_i, double radius_j) {
  return radius_i * radius_j / (radius_i + radius_j);
}

// c_n = 6π η a² / max(h, h_min), N s/m.
inline double normal_lubrication_resistance(double viscosity, double radius_i, double radius_j,
                                            double gap, double minimum_gap) {
  const double a = reduced_radius(radius_i, radius_j);
  return 6.0 * std::numbers::pi * viscosity * a * a / std::max(gap, minimum_gap);
}

// (2 + β + 2β²)/(1 + β)², β = r_j / r_i: 5/4 for equal spheres, -> 2 for very unequal ones.
inline double tangential_lubrication_size_factor(double radius_i, double radius_j) {
  const double beta = radius_j / radius_i;
  return (2.0 + beta + 2.0 * beta * beta) / ((1.0 + beta) * (1.0 + beta));
}

// c_t = 6π η a (4/15) (2+β+2β²)/(1+β)² ln((r_i + r_j) / (2 max(h, h_min))), N s/m.
// Needs max(h, h_min) < (r_i + r_j)/2 (the log is positive); the fix enforces h_max < r_min.
inline double tangential_lubrication_resistance(double viscosity, double radius_i, double radius_j,
                                                double gap, double minimum_gap) {
  const double a = reduced_radius(radius_i, radius_j);
  const double xi = 2.0 * std::max(gap, minimum_gap) / (radius_i + radius_j);
  return 6.0 * std::numbers::pi * viscosity * a * (4.0 / 15.0) *
         tangential_lubrication_size_factor(radius_i, radius_j) * std::log(1.0 / xi);
}

// Both resistances of one pair at once (reference form of the pair loop's evaluation below):
// three divisions and one log instead of the six divisions of the two functions above (same
// formulas; the size factor is written as (2 r_i² + r_i r_j + 2 r_j²)/(r_i + r_j)², equal to
// (2 + β + 2β²)/(1 + β)²).
struct PairLubrication {
  double normal;      // c_n, N s/m
  double tangential;  // c_t, N s/m (0 when not requested)
};

inline PairLubrication pair_lubrication(double viscosity, double radius_i, double radius_j,
                                        double gap, double minimum_gap, bool tangential) {
  const double sum = radius_i + radius_j;
  const double inverse_sum = 1.0 / sum;
  const double a = radius_i * radius_j * inverse_sum;
  const double inverse_gap = 1.0 / std::max(gap, minimum_gap);
  const double six_pi_eta_a = 6.0 * std::numbers::pi * viscosity * a;
  PairLubrication c{six_pi_eta_a * a * inverse_gap, 0.0};
  if (tangential) {
    const double size_factor =
        (2.0 * radius_i * radius_i + radius_i * radius_j + 2.0 * radius_j * radius_j) *
        inverse_sum * inverse_sum;
    c.tangential = six_pi_eta_a * (4.0 / 15.0) * size_factor * std::log(0.5 * sum * inverse_gap);
  }
  return c;
}

// The pair loop's evaluation (fix fluid/le), from the centre distance r instead of the gap, with
// the log left to the caller so that a loop can run the logs of all pairs back to back:
//   g = max(r - r_i - r_j, h_min),  a = r_i r_j / (r_i + r_j),
//   c_n = 6π η a² / g,
//   c_t = tangential_prefactor × ln(log_argument),
//   tangential_prefactor = 6π η a (4/15) (2 - 3 a / (r_i + r_j)),   log_argument = (r_i + r_j) /
//   (2g)
// (the size factor (2 r_i² + r_i r_j + 2 r_j²)/(r_i + r_j)² = 2 - 3 r_i r_j/(r_i + r_j)²). One
// division q = 1/(r (r_i + r_j) g) gives 1/r, 1/(r_i + r_j) and 1/g by multiplications. Needs
// r > 0 (the unit normal is (x_i - x_j)/r). Same values as pair_lubrication to round-off
// (tests/dem_fluid/test_dem_fluid_time_step.cpp).
struct PairLubricationTerms {
  double inverse_distance;      // 1/r, 1/m
  double normal;                // c_n, N s/m
  double tangential_prefactor;  // c_t / ln(log_argument), N s/m
  double log_argument;          // (r_i + r_j) / (2 max(h, h_min)) = 1/ξ
};

inline PairLubricationTerms pair_lubrication_terms(double viscosity, double radius_i,
                                                   double radius_j, double distance,
                                                   double minimum_gap) {
  const double sum = radius_i + radius_j;
  const double gap = std::max(distance - sum, minimum_gap);
  const double q = 1.0 / (distance * sum * gap);
  const double inverse_sum = q * distance * gap;
  const double inverse_gap = q * distance * sum;
  const double a = radius_i * radius_j * inverse_sum;
  const double six_pi_eta_a = 6.0 * std::numbers::pi * viscosity * a;
  return {q * sum * gap, six_pi_eta_a * a * inverse_gap,
          six_pi_eta_a * (4.0 / 15.0) * (2.0 - 3.0 * a * inverse_sum), 0.5 * sum * inverse_gap};
}

}  // namespace granflow::dem
