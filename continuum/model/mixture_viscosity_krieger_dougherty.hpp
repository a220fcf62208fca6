// Effective viscosity of a concentrated suspension, Krieger & Dougherty (1959), Trans. Soc.
// Rheol. 3, 137, with the Einstein intrinsic viscosity [η] = 2.5:
//   η(ν) = η0 (1 - ν/ν_m)^{-2.5 ν_m},
// which reduces to Einstein η0 (1 + 2.5 ν) to first order in ν and diverges at ν_m
// (`maximum_packing` in the case file). Caller guarantees 0 ≤ ν < ν_m.
#pragma once

#include <cmath>

namespace granflow::model {

inline double mixture_viscosity_krieger_dougherty(double liquid_viscosity, double solid_fraction,
                                                  double maximum_packing) {
  return liquid_viscosity *
         std::pow(1.0 - solid_fraction / maximum_packing, -2.5 * maximum_packing);
}

}  // namespace granflow::model
