// Closed-form solutions the verification cases are checked against.
#pragma once

namespace granflow::mpm::analytic {

// Terzaghi 1D consolidation of a layer of height H drained at the top (depth d = 0) and
// impermeable at the base, under a total load applied at t = 0 that leaves the initial excess
// pore pressure p0 (Terzaghi 1943; e.g. Verruijt, Soil Mechanics, ch. 15):
//   p(d, t) = Σ_k (2 p0 / M_k) sin(M_k d / H) exp(-M_k² T_v),  M_k = π (2k + 1) / 2,
//   T_v = c_v t / H².
// With a compressible liquid (bulk modulus K_w, porosity n) and incompressible grains the storage
// is 1/M + n/K_w, so c_v = k_D / (γ_w (1/M + n/K_w)) and p0 = q / (1 + n M / K_w).
double consolidation_coefficient(double hydraulic_conductivity, double unit_weight_liquid,
                                 double constrained_modulus, double porosity, double bulk_modulus);
double undrained_pressure(double load, double constrained_modulus, double porosity,
                          double bulk_modulus);
double terzaghi_pressure(double depth, double time, double height, double cv, double p0);
// Downward displacement since t = 0 of the point at depth d: u = (1/M) ∫_d^H (p0 - p) dz
//   = (1/M) [p0 (H - d) - Σ_k (2 p0 H / M_k²) cos(M_k d / H) exp(-M_k² T_v)].
double terzaghi_displacement(double depth, double time, double height, double cv, double p0,
                             double constrained_modulus);
// Average degree of consolidation U(T_v) = 1 - Σ 2/M_k² exp(-M_k² T_v).
double terzaghi_degree(double time, double height, double cv);

// Steady Couette flow between a fixed inner cylinder (r = R1) and an outer one (r = R2) moving at
// v_θ = V: v_θ(r) = A r + B / r with A = V R2 / (R2² - R1²), B = -A R1² (any Newtonian viscosity).
double couette_velocity(double r, double r_inner, double r_outer, double v_outer);

// Elastic column of height H under gravity g at rest: σ_yy(y) = -ρ g (H - y) (tension-positive).
inline double column_vertical_stress(double y, double height, double density, double gravity) {
  return -density * gravity * (height - y);
}

}  // namespace granflow::mpm::analytic
