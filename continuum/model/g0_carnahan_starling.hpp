// Radial distribution function at contact, Carnahan & Starling (1969), J. Chem. Phys. 51, 635:
//   g0(ν) = (2 - ν) / (2 (1 - ν)³) = (1 - ν/2) / (1 - ν)³.
// Exact published value: g0(0.5) = 1.5 / (2 · 0.125) = 6. Finite up to ν = 1, but the
// granflow model is not meant beyond jamming, so collisional_coefficients() refuses ν ≥ ν_c
// for this option too (see docs/model/closures.md).
#pragma once

namespace granflow::model {

inline double g0_carnahan_starling(double solid_fraction) {
  const double one_minus = 1.0 - solid_fraction;
  return (1.0 - 0.5 * solid_fraction) / (one_minus * one_minus * one_minus);
}

}  // namespace granflow::model
