// Effective viscosity of a dilute suspension of rigid spheres, Einstein (1906, 1911):
//   η(ν) = η0 (1 + 2.5 ν).
// Used here as the liquid-phase viscosity η of seed Eq. 27 (docs/model/closures.md). Not singular.
#pragma once

namespace granflow::model {

inline double mixture_viscosity_einstein(double liquid_viscosity, double solid_fraction) {
  return liquid_viscosity * (1.0 + 2.5 * solid_fraction);
}

}  // namespace granflow::model
