// LIGGGHTS input deck for Lees-Edwards simple shear, generated from case parameters.
// The deck (in.granflow) plus its particle file (particles.data) build the sample: spheres
// placed at random without overlap in a zero-tilt prism box at min(φ, 0.3) (initial_state.hpp),
// isotropic compression (fix deform ... remap x) to the target solid fraction, then the
// streaming profile (velocity ramp) and `fix deform 1 xy erate GD remap v` (Lees-Edwards). The
// shear stage itself (sampling, servo) is run by granflow-dem, which reads the gf_* variables of
// the deck and first adds the velocity fluctuations of gf_initial_temperature.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "dem_coupling/deck/contact_time.hpp"
#include "dem_coupling/deck/driver_parameters.hpp"
#include "dem_coupling/fixes/fluid_time_step.hpp"

namespace granflow::dem {

enum class SizeDistribution { monodisperse, bidisperse, uniform };

// Normal contact law (LIGGGHTS `pair_style gran model ...`, tangential history, Coulomb limit):
//   hertz: Hertz-Mindlin from E and ν, damping from e (LIGGGHTS `hertz`);
//   hooke: linear spring-dashpot with uniform stiffnesses k_n, k_t = ratio × k_n and the
//          damping rate that gives restitution e to a pair of mean-diameter spheres
//          (LIGGGHTS `hooke/stiffness`; Cundall & Strack 1979; k_t = 2/7 k_n as in Silbert et al.
//          2001 PRE 64 051302, the common soft-sphere setting).
enum class ContactLaw { hertz, hooke };

// Tangential dashpot γ_t of the contact, F_t = -(k_t ξ + γ_t v_t) within the Coulomb limit
// (docs/dem_dataset.md, "Tangential dashpot"):
//   liggghts:             LIGGGHTS' own setting (tangential_damping on). hooke/stiffness: γ_t =
//                         γ_n (the deck passes the same rate); hertz: γ_t = 2 √(5/6) β √(S_t m*),
//                         i.e. γ_t/γ_n = √(S_t/S_n) = √(2(1-ν)/(2-ν)) = 0.91 at ν = 0.3
//                         (LIGGGHTS normal_model_hertz.h; Tsuji et al. 1992);
//   lammps_hooke_history: γ_t = γ_n/2, LAMMPS pair gran/hooke/history's default (hooke only);
//   none:                 γ_t = 0 (LIGGGHTS `tangential_damping off`).
enum class TangentialDamping { liggghts, lammps_hooke_history, none };

struct DemMaterial {
  double diameter = 1e-3;          // number-mean diameter d, m
  double particle_density = 2500;  // rho_p, kg/m^3
  double restitution = 0.7;        // normal coefficient of restitution e_n
  double particle_friction = 0.5;  // Coulomb friction mu_p
  double youngs_modulus = 1e7;     // E, Pa
  double poisson_ratio = 0.3;      // nu
  SizeDistribution size = SizeDistribution::bidisperse;
  double size_ratio = 1.22;     // bidisperse: d_large / d_small
  double large_fraction = 0.5;  // bidisperse: number fraction of large particles
  double polydispersity = 0.1;  // uniform: d in d (1 -+ polydispersity)
  ContactLaw contact_law = ContactLaw::hertz;
  double normal_stiffness = 0.0;                  // hooke: k_n, N/m
  double tangential_stiffness_ratio = 2.0 / 7.0;  // hooke: k_t / k_n
  TangentialDamping tangential_damping = TangentialDamping::liggghts;
};

// γ_t/γ_n of `m` as the deck sets it (TangentialDamping).
double tangential_damping_ratio(const DemMaterial& m);

// LIGGGHTS commands that define the contact law of `m` (material properties + pair_style +
// pair_coeff) for one atom type; `mean_diameter` sets the hooke damping rate (see ContactLaw).
std::string contact_law_commands(const DemMaterial& m, double mean_diameter);

// Immersed shear: `fix gf_fluid all fluid/le ...` after the shear fix
// (docs/dem_fluid.md). Gaps are in units of the number-mean diameter d (material.diameter).
struct WetShear {
  bool enabled = false;
  double viscosity = 1e-3;                 // η0, Pa s
  std::string permeability = "seed_eq26";  // drag correlation, by the continuum's name
  double sphericity = 1.0;                 // A of the permeability
  bool lubrication = true;
  bool tangential_lubrication = true;
  bool rotational_drag = true;
  double maximum_gap = 0.05;    // h_max / d (must be < d_small / (2 d))
  double minimum_gap = 0.001;   // h_min / d
  double viscous_safety = 0.2;  // Δt <= viscous_safety × shortest viscous relaxation time
  double trulsson_alpha = 0.6;  // α of K = J + α I² (reporting)
};

struct ShearDeckParams {
  DemMaterial material;
  long particles = 1000;
  unsigned long seed = 1;
  bool constant_pressure = false;
  double solid_fraction = 0.55;  // constant volume: the imposed phi; constant pressure: start
  // Granular temperature of the velocity fluctuations the shear stage starts with, in units of
  // (d γ̇)²; negative: kinetic theory's steady value (initial_state.hpp): at φ for constant
  // volume, at the φ of kinetic theory's I for constant pressure.
  double initial_temperature = -1.0;
  double normal_stress = 100.0;  // constant pressure: imposed sigma_yy, Pa
  double servo_gain = 0.01;
  double servo_max_strain = 0.002;  // largest relative height change per servo update
  double servo_strain = 0.1;        // shear strain between servo updates
  double shear_rate = 20.0;         // 1/s
  double total_strain = 20.0;       // with targets: the largest run (strain.max)
  // After the shear: the shear stopped at constant volume for this long (s); 0: no stop stage.
  double stop_duration = 0.0;
  // Drained stop (immersed only): the stopped box compacts under stop_normal_stress as fast as
  // its liquid drains over stop_drainage_length (fix drainage); 0: held at constant volume.
  double stop_drainage_length = 0.0;  // m
  double stop_normal_stress = 0.0;    // Pa
  // Drained shear (control.mode drained, immersed only): the total σ_yy = normal_stress is held
  // during the shear while the liquid drains in or out over this length (fix drainage); 0: not.
  double drainage_length = 0.0;  // m
  // Damped height (control.mode damped_height, dry or immersed): the same law with k = 1/R,
  // R = control.height_resistance (Pa s); 0: not.
  double height_resistance = 0.0;
  // A step in the shear rate once the strain reaches rate_step_strain (0: no step).
  double rate_step_strain = 0.0;
  double rate_step_shear_rate = 0.0;  // 1/s after the step
  double sample_strain = 0.01;        // shear strain between samples
  // strain.target_error: granflow-dem stops once the steady window has been steady with its
  // errors within these at targets.confirm_checks consecutive checks (kind/steady_checks.hpp);
  // none: it runs total_strain.
  ErrorTargets targets;
  double check_strain = 0.5;  // shear strain between those checks (strain.check)
  double dt_safety = 0.1;     // dt = dt_safety * min(t_Rayleigh, t_Hertz) (hooke: * t_c linear)
  double impact_speed_factor = 3.0;  // reference impact speed = factor * shear_rate * d_max
  int profile_bins = 10;
  double snapshot_strain = 0.0;  // shear strain between particle snapshots; 0: none
  long compression_steps = 10000;
  WetShear wet;
  // Start from a prepared state (kind: dem_prepare, preparation_deck.hpp): the LIGGGHTS restart
  // file read instead of the random gas and its compression (the box and contact history come
  // from it; the friction is this material's); empty: the gas.
  std::string prepared_restart;
};

struct ShearDeck {
  std::string deck;  // text of in.granflow
  std::string data;  // text of the particle file
  std::vector<double> diameters;
  double small_diameter = 0, large_diameter = 0, mean_diameter = 0;
  ContactTimes times;
  double dt = 0;
  std::string dt_limit = "contact";  // the limit that sets dt (fluid_time_step.hpp names)
  FluidTimeScales fluid_times;       // wet: the time scales at the solid fraction below
  double fluid_solid_fraction = 0;   // wet: ν used for the drag time scale
  long sample_every = 0, servo_every = 0, total_steps = 0;
  long stop_steps = 0;  // steps of the stop stage, whole samples (0: none)
  // strain.target_error: steps between the checks of the targets, whole servo intervals (whole
  // samples at constant volume); 0 without targets.
  long check_every = 0;
  long snapshot_every = 0;  // steps between particle snapshots (0: none; extraction/snapshots.hpp)
  // Immersed, constant pressure: the height moves during the first servo_move_every steps of
  // each servo interval and is held for the rest, where the servo measures σ_yy (a viscous
  // suspension's σ_yy responds at once to the dilation rate); 2/5 of the interval in whole
  // samples (at least one moving and one held). 0: moves over the whole interval (dry).
  long servo_move_every = 0;
  // Rate step: the shear steps before it (whole samples); 0: none.
  long rate_step_steps = 0;
  // Steps of the isotropic compression: dem.compression_steps, rounded up to whole sample
  // intervals in dry decks (their fix ave/time windows end on multiples of sample_every).
  long compression_steps = 0;
  double initial_box_length = 0, box_length = 0;  // inserted box, compressed box (m)
  double insertion_solid_fraction = 0;            // φ of the random insertion
  double initial_temperature = 0;                 // T0 of the shear start, m²/s²
  double solid_volume = 0;                        // m^3
};

// Parameter problems that make the case impossible, as (key path, what is expected) pairs,
// checked before LIGGGHTS starts. Empty when the case can run.
std::vector<std::pair<std::string, std::string>> check_shear_params(const ShearDeckParams& p);

// Default gain of the constant-normal-stress servo (NormalStressServo): gain × k = loop gain,
// k = d ln σ_yy / d ln φ at the target state.
// Dry (loop gain 0.25): φ_c - φ ≈ a I, k ≈ 2.4 / I, gain = 0.1 I_target within [1e-4, 0.02]
// (I_target = γ̇ d / sqrt(σ_yy/ρ_p); 0.01 at I = 0.1 as in liggghts-study.md). Linear springs
// (contact_law hooke): at most 2 σ_yy d / k_n, the elastic limit (k ≈ k_n/(σ_yy d)), within
// [1e-6, 0.02]; such decks update the height every sample by default (read_shear_params).
// Immersed: the steady state follows φ = φ_m / (1 + √K), K = J + α I² (Boyer, Guazzelli & Pouliquen
// 2011, Phys. Rev. Lett. 107, 188301, φ(J) with J -> K; Trulsson et al. 2012, α = liquid.
// trulsson_alpha). At fixed γ̇ and η0 both J = η0 γ̇/σ and I² = ρ_p d² γ̇²/σ are ∝ 1/σ, so
// k = 2 (1 + √K)/√K at K_target: 8 at J = 0.1 (viscous, loose) against 50 at St = 100, 100 Pa
// (dense). gain = 0.125/k within [1e-4, 0.05] (loop gain 0.125: immersed decks move the height
// and then hold it, and the stress just after a move exceeds the steady response; measured in
// docs/dem_fluid.md). The dry rule alone (0.01 at I = 0.1) is 1.5x too small at J = 0.1.
double default_servo_gain(const ShearDeckParams& p);

// The ShearDeck fields make_shear_deck derives without the particles: small/large diameter,
// contact and fluid times, dt and the limit that sets it, sample/servo/total step counts (step
// counts saturate at 1e18). Cheap at any dem.particles: what the case check uses.
ShearDeck shear_deck_timing(const ShearDeckParams& p);

// T0 of the shear start in m²/s² (ShearDeckParams::initial_temperature, its default resolved).
double initial_temperature(const ShearDeckParams& p, double mean_diameter);

// Largest control.solid_fraction: 0.70, the range soft frictionless spheres compressed above
// random close packing (φ_J ≈ 0.64) reach at mean overlaps of a few % of d (O'Hern et al. 2003,
// Phys. Rev. E 68, 011306: φ - φ_J ∝ overlap); beyond, the contact laws leave their small-strain
// range. Above 0.64 the sample is compressed from a looser random packing (docs/dem_dataset.md).
constexpr double max_solid_fraction = 0.70;

// Builds the deck; `data_file_name` is the particle file name as the deck refers to it.
ShearDeck make_shear_deck(const ShearDeckParams& p, const std::string& data_file_name);

}  // namespace granflow::dem
