// The start of every deck granflow-dem runs: the gf_* variables the driver reads after the deck
// (dem_coupling/driver/main.cpp: shear rate, run length, sampling, the normal-stress servo) and the
// granular atom setup (periodic, SI, the velocity communication pair styles need for
// lubrication). One definition, used by the shear-deck writer (shear_deck.cpp) and by the tests'
// hand-written decks, so a variable the driver reads cannot be missing from either.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace granflow::dem {

struct DriverParameters {
  double shear_rate = 0.0;       // gf_shear_rate, 1/s (0: no shear, the box is held)
  long total_steps = 0;          // gf_total_steps of the shear stage
  long sample_every = 1;         // gf_sample_every: steps per sample
  bool constant_pressure = false;  // gf_constant_pressure: the servo holds gf_normal_stress
  double normal_stress = 0.0;    // gf_normal_stress, Pa
  double servo_gain = 0.0;       // gf_servo_gain
  double servo_max_strain = 0.0;  // gf_servo_max_strain: largest height change per servo step
  long servo_every = 1;          // gf_servo_every: steps between servo updates
  std::optional<long> servo_move_every;  // gf_servo_move_every (immersed decks); unset: omitted
  int profile_bins = 2;          // gf_profile_bins: bins of the velocity profile across y
  double particle_density = 0.0;  // gf_particle_density, kg/m³
};

// "variable gf_<name> equal <value>" lines, reals with 17 significant digits (exact round trip).
std::string driver_parameter_lines(const DriverParameters& p);

// atom_style granular, map array, periodic boundaries, newton off, ghost velocities, SI units.
std::string granular_atom_setup();

// `granflow-dem --header NAME=VALUE ...`: DriverParameters from NAME=VALUE words (NAME a gf_*
// variable without its prefix: shear_rate, total_steps, sample_every, constant_pressure,
// normal_stress, servo_gain, servo_max_strain, servo_every, servo_move_every, profile_bins,
// particle_density); servo_every defaults to sample_every. Throws std::invalid_argument naming a
// word that is not NAME=VALUE with a known NAME and a number.
DriverParameters driver_parameters_from_words(const std::vector<std::string>& words);

}  // namespace granflow::dem
