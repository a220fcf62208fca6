// Test support: the start of hand-written decks for the granflow-dem driver (tests/dem and
// tests/dem_fluid).
#pragma once

#include <fmt/format.h>

#include <string>

namespace granflow::dem::testing {

// The start of a hand-written deck for the driver: the gf_* variables it reads (no shear, no
// servo; sampling every `sample_every` of `total_steps` steps) and the granular atom setup with
// periodic boundaries in SI units. The test adds the box, atoms, contact law and computes.
inline std::string driver_deck_header(long total_steps, long sample_every, double particle_density,
                                      int profile_bins = 2) {
  return fmt::format(R"(variable gf_shear_rate equal 0
variable gf_total_steps equal {}
variable gf_sample_every equal {}
variable gf_constant_pressure equal 0
variable gf_normal_stress equal 0
variable gf_servo_gain equal 0
variable gf_servo_max_strain equal 0
variable gf_servo_every equal {}
variable gf_profile_bins equal {}
variable gf_particle_density equal {}
atom_style      granular
atom_modify     map array
boundary        p p p
newton          off
communicate     single vel yes
units           si
)",
                     total_steps, sample_every, sample_every, profile_bins, particle_density);
}

}  // namespace granflow::dem::testing
