// Dimensionless coefficients of (extended) kinetic theory for identical inelastic spheres, in the
// notation of Berzi, Jenkins & Vescovi (Jenkins & Berzi 2010, Granul. Matter 12, 151; Berzi,
// di Prisco & Vescovi 2011, Phys. Rev. E 84, 031301; Vescovi et al. 2013, IJNAMG; Berzi & Jenkins
// 2014, Acta Mech. 225, 2191). G = ν g0(ν), e_r = normal restitution, ε = effective restitution.
//   pressure      p   = ρ_p f1 T,               f1 = 4 ν G F,  F = (1+e_r)/2 + 1/(4G)
//   viscosity     η_c = ρ_p d f2 T^{1/2},       f2 = 8 ν G J / (5 √π)
//   dissipation   Γ   = ρ_p f3 T^{3/2} / L,     f3 = 12 ν G (1-ε²) / √π
//   conductivity  k_c = ρ_p d f4 T^{1/2},       f4 = 4 ν G M / √π
// J and M come from the Enskog-level Chapman-Enskog solution of Garzó & Dufty (1999), Phys.
// Rev. E 59, 5895, in the first Sonine approximation without the c* (fourth-cumulant)
// corrections; see docs/model/closures.md for the derivation of M and the checks.
#pragma once

#include <numbers>

namespace granflow::model {

// f1 = 4 ν G F = ν [1 + 2 (1+e_r) G]  (written without 1/G so that it is exact as ν -> 0).
inline double kinetic_f1(double solid_fraction, double G, double restitution) {
  return solid_fraction * (1.0 + 2.0 * (1.0 + restitution) * G);
}

// J = (1+e)/2 + (π/32) [5 + 2(1+e)(3e-1)G] [5 + 4(1+e)G] / {[24 - 6(1-e)² - 5(1-e²)] G²}
// (Berzi & Jenkins 2014; Vescovi et al. 2013). The denominator equals (1+e)(13-e) G², i.e.
// 24 (ν_η* - ζ*/2)/χ of Garzó & Dufty (1999); the first term is their bulk-like (3/5)γ* part.
inline double kinetic_J(double restitution, double G) {
  const double e = restitution;
  const double one_minus = 1.0 - e;
  const double denominator = (24.0 - 6.0 * one_minus * one_minus - 5.0 * (1.0 - e * e)) * G * G;
  return 0.5 * (1.0 + e) + (std::numbers::pi / 32.0) *
                               (5.0 + 2.0 * (1.0 + e) * (3.0 * e - 1.0) * G) *
                               (5.0 + 4.0 * (1.0 + e) * G) / denominator;
}

// f2 = 8 ν G J / (5 √π). Dilute elastic limit: (5 √π / 96), the Chapman-Enskog viscosity.
inline double kinetic_f2(double solid_fraction, double G, double J) {
  return 1.6 * solid_fraction * G * J * std::numbers::inv_sqrtpi;  // 8/5 = 1.6
}

// f3 = 12 ν G (1 - ε²) / √π (collisional rate of dissipation; Jenkins & Savage 1983 form with ε).
inline double kinetic_f3(double solid_fraction, double G, double effective_restitution) {
  return 12.0 * solid_fraction * G * (1.0 - effective_restitution * effective_restitution) *
         std::numbers::inv_sqrtpi;
}

// M = (1+e)/2 + (π/16) [5 + 3(1+e)²(2e-1)G] [5 + 6(1+e)G] / {(1+e)(9+7e) G²}
// from Garzó & Dufty (1999), d = 3, c* = 0: κ* = κ_k* [1 + (6/5)(1+e)φχ] + (256/25π)φ²χ(1+e),
// κ_k* = (2/3)[1 + (3/5)φχ(1+e)²(2e-1)] / (ν_κ* - 2ζ*), ν_κ* - 2ζ* = (1+e)χ(9+7e)/48, scaled by
// the elastic dilute conductivity (25 √π / 128) ρ_p d T^{1/2}: f4 = (25 √π/128) κ* = 4 ν G M / √π.
// Limits checked in tests/model: dilute elastic -> 25 √π/128 (Chapman-Enskog), dense elastic ->
// Enskog's (25 √π/128) [(1 + 12G/5)²/g0 + (512/25π) ν G].  (check: Berzi's own M not retrieved.)
inline double kinetic_M(double restitution, double G) {
  const double e = restitution;
  return 0.5 * (1.0 + e) + (std::numbers::pi / 16.0) *
                               (5.0 + 3.0 * (1.0 + e) * (1.0 + e) * (2.0 * e - 1.0) * G) *
                               (5.0 + 6.0 * (1.0 + e) * G) / ((1.0 + e) * (9.0 + 7.0 * e) * G * G);
}

// f4 = 4 ν G M / √π.
inline double kinetic_f4(double solid_fraction, double G, double M) {
  return 4.0 * solid_fraction * G * M * std::numbers::inv_sqrtpi;
}

}  // namespace granflow::model
