// The multi-regime material of the seed's section 4 as the MPM tests use it: all terms on,
// d = 2.3 mm, ρ_p = 2650 kg/m³, e = 0.8, ν_c = ν_m = 0.64, water (η0 = 1e-3 Pa s).
#pragma once

#include "continuum/multi_regime/multi_regime_point.hpp"

namespace granflow::testing {

inline continuum::MultiRegimeSettings section4_settings() {
  continuum::MultiRegimeSettings s;
  s.force_chains = true;
  s.collisional = true;
  s.liquid = true;
  s.fluctuation_dissipation = true;
  s.collisional_parameters.diameter = 2.3e-3;
  s.collisional_parameters.particle_density = 2650;
  s.collisional_parameters.restitution = 0.8;
  s.collisional_parameters.jamming_fraction = 0.64;
  s.liquid_parameters.viscosity = 1e-3;
  s.liquid_parameters.maximum_packing = 0.64;
  return s;
}

}  // namespace granflow::testing
