// Test support: the start of hand-written decks for the granflow-dem driver (tests/dem and
// tests/dem_fluid), from the same definition as the shear-deck writer
// (dem_coupling/deck/driver_parameters.hpp).
#pragma once

#include <string>

#include "dem_coupling/deck/driver_parameters.hpp"

namespace granflow::dem::testing {

// The gf_* variables the driver reads (no shear, no servo; sampling every `sample_every` of
// `total_steps` steps) and the granular atom setup with periodic boundaries in SI units. The
// test adds the box, atoms, contact law and computes.
inline std::string driver_deck_header(long total_steps, long sample_every, double particle_density,
                                      int profile_bins = 2) {
  DriverParameters p;
  p.total_steps = total_steps;
  p.sample_every = sample_every;
  p.servo_every = sample_every;
  p.profile_bins = profile_bins;
  p.particle_density = particle_density;
  return driver_parameter_lines(p) + granular_atom_setup();
}

}  // namespace granflow::dem::testing
