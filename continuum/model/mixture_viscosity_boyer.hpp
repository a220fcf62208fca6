// Hydrodynamic part of the suspension viscosity of Boyer, Guazzelli & Pouliquen (2011), Phys. Rev.
// Lett. 107, 188301. Their μ(J), φ(J) laws give η_s = τ/(η0 γ̇) = μ/J with
//   μ(J) = μ_c(J) + J + (5/2) φ_m J^{1/2},   φ = φ_m / (1 + J^{1/2}),
// whose hydrodynamic terms, rewritten with J^{1/2} = φ_m/φ - 1, are
//   η(ν) = η0 [1 + (5/2) ν (1 - ν/ν_m)^{-1}].
// (docs/model/closures.md writes 2.5 ν_m instead of 2.5 ν; that would not reduce to η0 at ν = 0 nor
// to Einstein at first order, so the form above, which follows from Boyer's Eqs., is used.) The
// contact part μ_c(J)/J is NOT added: σ_FC and σ_COL carry it. Singular at ν_m.
#pragma once

namespace granflow::model {

inline double mixture_viscosity_boyer(double liquid_viscosity, double solid_fraction,
                                      double maximum_packing) {
  return liquid_viscosity * (1.0 + 2.5 * solid_fraction / (1.0 - solid_fraction / maximum_packing));
}

}  // namespace granflow::model
