// The multi-regime material of the seed's section 4 as the MPM tests use it: all terms on,
// d = 2.3 mm, ρ_p = 2650 kg/m³, e = 0.8, ν_c = ν_m = 0.64, water (η0 = 1e-3 Pa s).
#pragma once

#include "continuum/mpm/rheometer.hpp"
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

// A small annulus (3 × 24 cells) of that material, saturated with water and coupled by the
// closure drag, on one thread, with the smoothed liquid and the material's T conductivity: the
// restart tests run it through the skeleton's collapse in a few hundred steps.
inline mpm::RheometerSpec section4_small_rheometer() {
  mpm::RheometerSpec spec;
  spec.cells_r = 3;
  spec.cells_theta = 24;
  spec.model = section4_settings();
  spec.liquid.bulk_modulus = 2.2e9;
  spec.liquid.viscosity = 1e-3;
  spec.liquid.drag_law = mpm::DragLaw::closure;
  spec.liquid.closure = spec.model.liquid_parameters;
  spec.liquid.grain_diameter = spec.model.collisional_parameters.diameter;
  spec.options.threads = 1;
  spec.options.liquid_volumetric_smoothing = true;
  spec.options.material_conductivity = true;
  return spec;
}

}  // namespace granflow::testing
