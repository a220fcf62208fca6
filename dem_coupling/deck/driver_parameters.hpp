// The start of every deck granflow-dem runs: the gf_* variables the driver reads after the deck
// (dem_coupling/driver/main.cpp: shear rate, run length, sampling, the normal-stress servo) and the
// granular atom setup (periodic, SI, the velocity communication pair styles need for
// lubrication). One definition, used by the shear-deck writer (shear_deck.cpp) and by the tests'
// hand-written decks, so a variable the driver reads cannot be missing from either.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace granflow::dem {

// strain.target_error (docs/dem_dataset.md, "Error-targeted run length"): the observables whose
// standard error in the steady window may end a run, in this order, and how each is measured:
//   friction        se(μ)/μ  relative (μ 0.1-0.6: a relative error reads the same at every I)
//   solid_fraction  se(φ)    absolute (φ 0.5-0.64; φ(I) fits and φ_c are compared in absolute
//                            units, e.g. the 0.0037 offset of docs/dem_dataset.md)
//   temperature     se(T)/T  relative (T spans decades over a sweep)
inline constexpr std::array<const char*, 3> target_observables{"friction", "solid_fraction",
                                                               "temperature"};

// strain.confirm_checks: the run stops only once the targets have held at this many consecutive
// checks (kind/steady_checks.hpp, TargetConfirmation). Stopping at the first check that meets them
// (1) selects runs whose error estimate happens to be low: on a synthetic AR(1) μ their true error
// is 1.46x the reported one, with 3 checks 1.18x (tests/dem/test_target_error.cpp). The one default
// of the key (kind/shear_schema.cpp) and of ErrorTargets.
inline constexpr int default_confirm_checks = 3;

struct ErrorTargets {
  std::array<double, 3> error{};  // target of each observable above; 0: no target for it
  int confirm_checks = default_confirm_checks;  // consecutive checks that must meet the targets
  bool any() const {
    for (double e : error)
      if (e > 0.0) return true;
    return false;
  }
};

struct DriverParameters {
  double shear_rate = 0.0;         // gf_shear_rate, 1/s (0: no shear, the box is held)
  long total_steps = 0;            // gf_total_steps of the shear stage
  long sample_every = 1;           // gf_sample_every: steps per sample
  bool constant_pressure = false;  // gf_constant_pressure: the servo holds gf_normal_stress
  double normal_stress = 0.0;      // gf_normal_stress, Pa
  double servo_gain = 0.0;         // gf_servo_gain
  double servo_max_strain = 0.0;   // gf_servo_max_strain: largest height change per servo step
  long servo_every = 1;            // gf_servo_every: steps between servo updates
  std::optional<long> servo_move_every;  // gf_servo_move_every (immersed decks); unset: omitted
  int profile_bins = 2;                  // gf_profile_bins: bins of the velocity profile across y
  double particle_density = 0.0;         // gf_particle_density, kg/m³
  // Error-targeted run length, written only when targets.any() (a deck without them runs
  // total_steps, unchanged): gf_target_<observable> (0: none), gf_check_every (steps between the
  // checks, a multiple of the servo interval), gf_confirm_checks (targets.confirm_checks),
  // gf_temperature_scale ((d γ̇)², m²/s², of the frozen check). total_steps is then the largest
  // run (strain.max).
  ErrorTargets targets;
  long check_every = 0;
  double temperature_scale = 0.0;
  // gf_stop_steps, written only when > 0: after the shear, the shear stopped at constant volume
  // for this many steps (driver/shear_stop.hpp).
  long stop_steps = 0;
  // gf_stop_drainage_length and gf_stop_normal_stress, written only with a stop stage and a
  // length > 0: the stopped box compacts under the normal stress as its liquid drains over this
  // length (fix drainage, fixes/fix_drainage.hpp) instead of being held.
  double stop_drainage_length = 0.0;  // m
  double stop_normal_stress = 0.0;    // Pa
  // gf_drainage_length, written only when > 0: a drained shear. fix drainage holds the total
  // σ_yy at gf_normal_stress during the shear while the liquid drains in or out over this length
  // (fixes/fix_drainage.hpp); the box height follows and fix gf_shear is reissued every sample.
  double drainage_length = 0.0;  // m
  // gf_height_resistance, written only when > 0: the same law with k = 1/R for a dry deck (a
  // damped height, control.mode damped_height), R in Pa s.
  double height_resistance = 0.0;
  // gf_rate_step_steps and gf_rate_step_shear_rate, written only when rate_step_steps > 0: after
  // this many shear steps (a multiple of sample_every) the shear rate steps to the second value
  // (the affine profile's change added to every sphere's v_x; driver/shear_schedule.hpp).
  long rate_step_steps = 0;
  double rate_step_shear_rate = 0.0;  // 1/s
};

// "variable gf_<name> equal <value>" lines, reals with 17 significant digits (exact round trip).
std::string driver_parameter_lines(const DriverParameters& p);

// atom_style granular, map array, periodic boundaries, newton off, ghost velocities, SI units.
std::string granular_atom_setup();

// `granflow-dem --header NAME=VALUE ...`: DriverParameters from NAME=VALUE words (NAME a gf_*
// variable without its prefix: shear_rate, total_steps, sample_every, constant_pressure,
// normal_stress, servo_gain, servo_max_strain, servo_every, servo_move_every, profile_bins,
// particle_density, target_friction, target_solid_fraction, target_temperature, check_every,
// stop_steps, stop_drainage_length, stop_normal_stress, drainage_length, height_resistance,
// rate_step_steps, rate_step_shear_rate, confirm_checks, temperature_scale);
// servo_every defaults to sample_every. Throws std::invalid_argument naming a word that is not
// NAME=VALUE with a known NAME and a number.
DriverParameters driver_parameters_from_words(const std::vector<std::string>& words);

}  // namespace granflow::dem
