// DEM-scale spheres with force chains (cases/rev/simple_shear_force_chains_pressure.yaml): d = 1 mm,
// ρ_p = 2500 kg/m³, e_r = 0.7 (collisional defaults), a critical state line about 100 Pa that the
// skeleton reaches below the jamming fraction ν_c = 0.587. Shared by the REV and the two-path tests.
#pragma once

#include "continuum/multi_regime/multi_regime_point.hpp"

namespace granflow::testing {

inline continuum::MultiRegimeSettings dem_sphere_settings(double M_c = 0.70) {
  continuum::MultiRegimeSettings s;
  s.force_chains = true;
  s.collisional_parameters.jamming_fraction = 0.587;
  auto& f = s.force_chain_parameters;
  f.bulk_modulus_ref = 1e5;
  f.reference_pressure = 100;
  f.pressure_floor = 1;
  f.M_c = M_c;
  f.e_Gamma = 0.74;  // looser than the collisional jamming e = 1/0.587 - 1 = 0.7036
  f.lambda_c = 0.01;
  f.xi_c = 0.5;
  f.atmospheric_pressure = 100;
  f.e_min = 0.5625;
  f.e_max = 1.0;
  f.fluidization_size = 1;
  f.resolidification_size = 2;
  f.regrowth_modulus = 5e3;
  return s;
}

}  // namespace granflow::testing
