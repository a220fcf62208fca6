#include "dem_coupling/deck/shear_deck.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <numeric>
#include <random>
#include <stdexcept>

#include "dem_coupling/deck/driver_parameters.hpp"
#include "dem_coupling/deck/initial_state.hpp"
#include "dem_coupling/extraction/snapshots.hpp"

namespace granflow::dem {

namespace {

// Uniform double in [0, 1) from the 53 high bits; mt19937_64 is fully specified by the C++
// standard, so a seed gives the same sample on every platform.
double uniform(std::mt19937_64& rng) { return double(rng() >> 11) * 0x1.0p-53; }

struct SizeRange {
  double small, large;
};

SizeRange size_range(const DemMaterial& m) {
  switch (m.size) {
    case SizeDistribution::bidisperse: {
      // number mean d = (1 - f) d_s + f r d_s
      const double small = m.diameter / (1.0 - m.large_fraction + m.large_fraction * m.size_ratio);
      return {small, small * m.size_ratio};
    }
    case SizeDistribution::uniform:
      return {m.diameter * (1.0 - m.polydispersity), m.diameter * (1.0 + m.polydispersity)};
    case SizeDistribution::monodisperse:
      break;
  }
  return {m.diameter, m.diameter};
}

double sphere_mass(double diameter, double particle_density) {
  return particle_density * std::numbers::pi / 6.0 * diameter * diameter * diameter;
}

// Whole steps for `strain` at γ̇ Δt per step, at least 1; saturated at 1e18 (no overflow when a
// case asks for more: the case check refuses such runs, limits.max_steps).
long steps_for(double strain, double shear_rate, double dt) {
  const double steps = strain / (shear_rate * dt);
  return std::max(1L, std::lround(steps < 1e18 ? steps : 1e18));
}

// The larger of the shear rate and the rate step's: the time step and the sampling interval are
// set for it (impacts are fastest there; the slower stage is sampled more finely in strain).
double fastest_shear_rate(const ShearDeckParams& p) {
  return p.rate_step_strain > 0.0 ? std::max(p.shear_rate, p.rate_step_shear_rate) : p.shear_rate;
}

// The fluid time-step input of an immersed deck (fluid_time_step.hpp).
FluidTimeStepInput fluid_step_input(const ShearDeckParams& p, const ShearDeck& timing) {
  const DemMaterial& m = p.material;
  FluidTimeStepInput in;
  in.fluid.liquid.viscosity = p.wet.viscosity;
  in.fluid.liquid.permeability = model::parse_permeability(p.wet.permeability);
  in.fluid.liquid.sphericity = p.wet.sphericity;
  in.fluid.rotational_drag = p.wet.rotational_drag;
  in.fluid.lubrication = p.wet.lubrication;
  in.fluid.tangential_lubrication = p.wet.tangential_lubrication;
  in.fluid.maximum_gap = p.wet.maximum_gap * m.diameter;
  in.fluid.minimum_gap = p.wet.minimum_gap * m.diameter;
  in.contact_time = timing.times.shortest();
  in.particle_density = m.particle_density;
  in.smallest_radius = 0.5 * timing.small_diameter;
  in.largest_radius = 0.5 * timing.large_diameter;
  in.solid_fraction = timing.fluid_solid_fraction;
  return in;
}

}  // namespace

double tangential_damping_ratio(const DemMaterial& m) {
  switch (m.tangential_damping) {
    case TangentialDamping::none:
      return 0.0;
    case TangentialDamping::lammps_hooke_history:
      return 0.5;
    case TangentialDamping::liggghts:
      break;
  }
  if (m.contact_law == ContactLaw::hooke) return 1.0;
  // hertz: γ_t/γ_n = √(S_t/S_n), S_t/S_n = 8 G* / (2 E*) = 2 (1-ν)/(2-ν) for like spheres
  // (G* = E / (4 (2-ν)(1+ν)), E* = E / (2 (1-ν²)); normal_model_hertz.h of LIGGGHTS 3.8.0)
  const double nu = m.poisson_ratio;
  return std::sqrt(2.0 * (1.0 - nu) / (2.0 - nu));
}

std::string contact_law_commands(const DemMaterial& m, double mean_diameter) {
  const std::string friction =
      fmt::format("fix m4 all property/global coefficientFriction peratomtypepair 1 {:.17g}\n",
                  m.particle_friction);
  const bool damping_off = m.tangential_damping == TangentialDamping::none;
  if (m.contact_law == ContactLaw::hertz)
    return fmt::format(
        "fix m1 all property/global youngsModulus peratomtype {:.17g}\n"
        "fix m2 all property/global poissonsRatio peratomtype {:.17g}\n"
        "fix m3 all property/global coefficientRestitution peratomtypepair 1 {:.17g}\n{}"
        "# tangential dashpot: {} (gamma_t/gamma_n = {:.4g})\n"
        "pair_style      gran model hertz tangential history{}\npair_coeff      * *\n",
        m.youngs_modulus, m.poisson_ratio, m.restitution, friction,
        damping_off ? "none" : "liggghts", tangential_damping_ratio(m),
        damping_off ? " tangential_damping off" : "");
  // hooke/stiffness without absolute_damping: the damping forces are m* gamman v_n and
  // m* gammat v_t, so gamman is the damping rate γ_n/m* (1/s) of a pair of mean-diameter spheres
  // (contact_time.hpp) and gammat = (γ_t/γ_n) gamman (TangentialDamping).
  const double rate = linear_spring_damping_rate(
      0.5 * sphere_mass(mean_diameter, m.particle_density), m.normal_stiffness, m.restitution);
  const double ratio = tangential_damping_ratio(m);
  const char* convention = m.tangential_damping == TangentialDamping::none ? "none"
                           : m.tangential_damping == TangentialDamping::lammps_hooke_history
                               ? "lammps_hooke_history"
                               : "liggghts";
  return fmt::format(
      "# linear spring-dashpot: k_n = {0:.6g} N/m, k_t = {1:.6g} k_n, restitution {2:.6g} for a "
      "pair of d = {3:.6g} m\n"
      "# tangential dashpot: {8} (gamma_t/gamma_n = {7:.4g})\n"
      "fix m1 all property/global kn peratomtypepair 1 {0:.17g}\n"
      "fix m2 all property/global kt peratomtypepair 1 {4:.17g}\n"
      "fix m3 all property/global gamman peratomtypepair 1 {5:.17g}\n"
      "fix m5 all property/global gammat peratomtypepair 1 {9:.17g}\n{6}"
      "pair_style      gran model hooke/stiffness tangential history absolute_damping off{10}\n"
      "pair_coeff      * *\n",
      m.normal_stiffness, m.tangential_stiffness_ratio, m.restitution, mean_diameter,
      m.tangential_stiffness_ratio * m.normal_stiffness, rate, friction, ratio, convention,
      ratio * rate, damping_off ? " tangential_damping off" : "");
}

std::vector<std::pair<std::string, std::string>> check_shear_params(const ShearDeckParams& p) {
  std::vector<std::pair<std::string, std::string>> issues;
  const DemMaterial& m = p.material;
  if (m.size == SizeDistribution::bidisperse && !(m.size_ratio >= 1.0))
    issues.emplace_back("material.size_ratio", ">= 1 (d_large / d_small)");
  if (m.size == SizeDistribution::uniform && !(m.polydispersity >= 0 && m.polydispersity < 1))
    issues.emplace_back("material.polydispersity", "in [0, 1)");
  if (!(m.poisson_ratio > -1.0 && m.poisson_ratio < 0.5))
    issues.emplace_back("material.poisson_ratio", "in (-1, 0.5)");
  if (!(m.restitution > 0.0 && m.restitution <= 1.0))
    issues.emplace_back("material.restitution", "in (0, 1] (the contact damping needs e > 0)");
  // LIGGGHTS' own bounds on the material of its hertz model (global_properties.cpp, SI units:
  // "0.05 < coefficientRestitution <= 1", "youngsModulus >= 5e6", "<= 1e9", "0 <= poissonsRatio
  // <= 0.5 required"), checked here instead of stopping LIGGGHTS after launch; hooke decks pass
  // stiffnesses and a damping rate instead.
  else if (m.contact_law == ContactLaw::hertz && !(m.restitution > 0.05))
    issues.emplace_back("material.restitution",
                        "> 0.05 with contact_law hertz (LIGGGHTS refuses coefficientRestitution "
                        "<= 0.05); contact_law hooke takes smaller values");
  if (m.contact_law == ContactLaw::hertz && !(m.youngs_modulus >= 5e6 && m.youngs_modulus <= 1e9))
    issues.emplace_back("material.youngs_modulus",
                        "in [5e6, 1e9] Pa with contact_law hertz (LIGGGHTS' bounds for SI units); "
                        "contact_law hooke sets the stiffness directly");
  if (m.contact_law == ContactLaw::hertz && !(m.poisson_ratio >= 0.0))
    issues.emplace_back("material.poisson_ratio", ">= 0 with contact_law hertz (LIGGGHTS' bound)");
  if (m.contact_law == ContactLaw::hooke) {
    if (!(m.normal_stiffness > 0.0))
      issues.emplace_back("material.normal_stiffness", "k_n > 0 [N/m] for contact_law: hooke");
    if (!(m.tangential_stiffness_ratio > 0.0))
      issues.emplace_back("material.tangential_stiffness_ratio", "k_t / k_n > 0");
  }
  if (!(p.solid_fraction > 0.0 && p.solid_fraction <= max_solid_fraction))
    issues.emplace_back("control.solid_fraction",
                        fmt::format("in (0, {}] (soft spheres compressed above random close "
                                    "packing, docs/dem_dataset.md)",
                                    max_solid_fraction));
  if (m.contact_law == ContactLaw::hertz &&
      m.tangential_damping == TangentialDamping::lammps_hooke_history)
    issues.emplace_back("material.tangential_damping",
                        "liggghts or none with contact_law hertz (LIGGGHTS' hertz model sets "
                        "γ_t from the tangential stiffness, on or off only)");
  if (!(p.initial_temperature < 0.0 || std::isfinite(p.initial_temperature)))
    issues.emplace_back("control.initial_temperature", "a finite T0/(d γ̇)² >= 0");
  if (p.particles < 8) issues.emplace_back("dem.particles", ">= 8");
  if (!(p.sample_strain < p.total_strain))
    issues.emplace_back("strain.sample", p.targets.any() ? "< strain.max" : "< strain.total");
  if (p.wet.enabled) {
    const SizeRange s = size_range(m);
    // fix fluid/le refuses h_max >= smallest radius (a lubricated pair must not skip a sphere).
    if (!(p.wet.maximum_gap * m.diameter < 0.5 * s.small))
      issues.emplace_back("dem_liquid.maximum_gap",
                          fmt::format("< d_small / (2 d) = {:.4g}", 0.5 * s.small / m.diameter));
    if (!(p.wet.minimum_gap < p.wet.maximum_gap))
      issues.emplace_back("dem_liquid.minimum_gap", "< dem_liquid.maximum_gap");
    try {
      (void)model::parse_permeability(p.wet.permeability);
    } catch (const std::exception& e) {
      issues.emplace_back("liquid.permeability", e.what());
    }
  }
  if (p.constant_pressure && !(p.servo_strain >= p.sample_strain))
    issues.emplace_back("control.servo_strain", ">= strain.sample");
  if (p.constant_pressure && p.stop_duration > 0.0)
    issues.emplace_back("stop.duration",
                        "0 under control.mode constant_pressure (the stop holds "
                        "the volume)");
  if (p.drainage_length > 0.0 && !p.wet.enabled)
    issues.emplace_back("control.mode",
                        "constant_volume, constant_pressure or damped_height without a liquid "
                        "(drained needs liquid.enabled: true)");
  if (p.rate_step_strain > 0.0) {
    if (!(p.rate_step_strain < p.total_strain))
      issues.emplace_back("rate_step.strain", "< strain.total");
    if (!(p.rate_step_shear_rate > 0.0)) issues.emplace_back("rate_step.shear_rate", "> 0 (1/s)");
    if (p.constant_pressure)
      issues.emplace_back("rate_step.strain",
                          "absent under control.mode constant_pressure (the servo's segments "
                          "run at one rate; drained holds σ_yy step by step)");
    if (p.targets.any())
      issues.emplace_back("rate_step.strain", "absent with strain.target_error (a fixed run)");
    if (p.snapshot_strain > 0.0)
      issues.emplace_back("output.snapshot_strain",
                          "0 with a rate step (snapshots are indexed at one rate)");
  }
  if (p.stop_drainage_length > 0.0 && !p.wet.enabled)
    issues.emplace_back("stop.drainage_length",
                        "0 without a liquid (liquid.enabled: true; a dry sample has nothing "
                        "to drain)");
  if (issues.empty()) {
    // The compressed periodic box must hold a few of the largest particles across, or the
    // ghost shell (cutoff d_max + skin) would wrap onto itself.
    const SizeRange s = size_range(m);
    const double vs = p.particles * std::numbers::pi / 6.0 * m.diameter * m.diameter * m.diameter;
    const double box = std::cbrt(vs / p.solid_fraction);
    if (box < 4.0 * s.large)
      issues.emplace_back("dem.particles",
                          fmt::format("enough particles for a box of >= 4 largest diameters (box "
                                      "would be {:.3g} d_max)",
                                      box / s.large));
    if (p.profile_bins < 1 || box / p.profile_bins < 0.5 * m.diameter)
      issues.emplace_back("output.profile_bins",
                          fmt::format("between 1 and {} (bins at least d/2 high)",
                                      std::max(1L, std::lround(2.0 * box / m.diameter))));
  }
  return issues;
}

double default_servo_gain(const ShearDeckParams& p) {
  const DemMaterial& m = p.material;
  const double inertial_number =
      p.shear_rate * m.diameter / std::sqrt(p.normal_stress / m.particle_density);
  if (!p.wet.enabled) {
    if (m.contact_law == ContactLaw::hooke && m.normal_stiffness > 0.0) {
      // Linear springs answer a height change first elastically, d ln σ/d ln φ ≈ k_n/(σ_yy d)
      // (affine compression of contacts carrying ~0.6 σ_yy d², force/k_n overlap): 1e4 at
      // k_n/(σ_yy d) = 1e4, so 0.1 I would be a loop gain of ~20 at I = 0.02 (measured: σ_yy
      // swinging 5-800 Pa, mean +10-13 %). 2 σ_yy d/k_n holds it (94-101 Pa with updates every
      // 0.01 strain; docs/dem_dataset.md, linear springs).
      const double elastic_gain = 2.0 * p.normal_stress * m.diameter / m.normal_stiffness;
      return std::clamp(std::min(0.1 * inertial_number, elastic_gain), 1e-6, 0.02);
    }
    return std::clamp(0.1 * inertial_number, 1e-4, 0.02);
  }
  const double viscous_number = p.wet.viscosity * p.shear_rate / p.normal_stress;
  const double root_mixed_number =
      std::sqrt(viscous_number + p.wet.trulsson_alpha * inertial_number * inertial_number);
  const double stress_sensitivity = 2.0 * (1.0 + root_mixed_number) / root_mixed_number;
  // 0.125, half the dry design: with move-then-hold the contact network's stress just after a
  // fast move exceeds its steady response, and 0.25 locked St 1-100 points at 25 Pa into a
  // period-2 cycle (held σ_yy alternating ~75 and ~0 Pa, docs/dem_fluid.md, servo)
  constexpr double loop_gain = 0.125;
  return std::clamp(loop_gain / stress_sensitivity, 1e-4, 0.05);
}

ShearDeck shear_deck_timing(const ShearDeckParams& p) {
  ShearDeck out;
  const DemMaterial& m = p.material;
  const SizeRange range = size_range(m);
  out.small_diameter = range.small;
  out.large_diameter = range.large;
  // --- time step from the contact time of the smallest particle
  const double reference_speed = p.impact_speed_factor * fastest_shear_rate(p) * range.large;
  out.times = contact_times(0.5 * range.small, m.particle_density, m.youngs_modulus,
                            m.poisson_ratio, reference_speed);
  if (m.contact_law == ContactLaw::hooke)  // two of the smallest spheres: m* = m_small / 2
    out.times.linear_spring = linear_spring_contact_time(
        0.5 * sphere_mass(range.small, m.particle_density), m.normal_stiffness, m.restitution);
  out.dt = p.dt_safety * out.times.shortest();
  if (p.wet.enabled) {
    // Immersed: dt = min(dt_safety t_contact, viscous_safety min(τ_drag, τ_rot, τ_n, τ_t))
    // (fluid_time_step.hpp). The drag time scale shortens with ν; the fix re-checks dt against
    // the current ν at every setup, so take the target φ, or max(φ0, 0.6) when a servo or the
    // drainage sets it.
    out.fluid_solid_fraction =
        p.constant_pressure || p.drainage_length > 0.0 || p.height_resistance > 0.0
            ? std::max(p.solid_fraction, 0.6)
            : p.solid_fraction;
    out.fluid_times = fluid_time_scales(fluid_step_input(p, out));
    const FluidTimeStep step =
        stable_fluid_time_step(out.fluid_times, p.dt_safety, p.wet.viscous_safety);
    out.dt = step.dt;
    out.dt_limit = step.limited_by;
  }
  out.sample_every = steps_for(p.sample_strain, fastest_shear_rate(p), out.dt);
  out.snapshot_every =
      p.snapshot_strain > 0.0 ? steps_for(p.snapshot_strain, p.shear_rate, out.dt) : 0;
  out.servo_every =
      p.constant_pressure
          ? std::max(1L, std::lround(double(steps_for(p.servo_strain, p.shear_rate, out.dt)) /
                                     double(out.sample_every))) *
                out.sample_every
          : out.sample_every;
  // Dry decks average the virial over sample intervals ending on multiples of sample_every
  // (fix ave/time, make_shear_deck): the shear must start on one.
  out.compression_steps = p.wet.enabled ? p.compression_steps
                                        : (p.compression_steps + out.sample_every - 1) /
                                              out.sample_every * out.sample_every;
  const long samples_per_update = out.servo_every / out.sample_every;
  if (p.wet.enabled && p.constant_pressure && samples_per_update >= 2)
    out.servo_move_every =
        std::clamp(std::lround(0.4 * double(samples_per_update)), 1L, samples_per_update - 1) *
        out.sample_every;
  const long block = p.constant_pressure ? out.servo_every : out.sample_every;
  // whole blocks; with a rate step, the strain before it at γ̇ and the rest at the step's rate
  const auto blocks = [&](double strain, double rate) {
    return std::max(1L, std::lround(double(steps_for(strain, rate, out.dt)) / block)) * block;
  };
  if (p.rate_step_strain > 0.0) {
    out.rate_step_steps = blocks(p.rate_step_strain, p.shear_rate);
    out.total_steps =
        out.rate_step_steps + blocks(p.total_strain - p.rate_step_strain, p.rate_step_shear_rate);
  } else {
    out.total_steps = blocks(p.total_strain, p.shear_rate);
  }
  // The stop stage: whole samples, at least one.
  if (p.stop_duration > 0.0)
    out.stop_steps =
        std::max(1L, std::lround(p.stop_duration / out.dt / double(out.sample_every))) *
        out.sample_every;
  // The checks of strain.target_error end on whole blocks, so a run stopped there is the first
  // part of a fixed run of that length, step for step (the servo's segments are the same).
  if (p.targets.any())
    out.check_every =
        std::max(1L, std::lround(double(steps_for(p.check_strain, p.shear_rate, out.dt)) / block)) *
        block;
  return out;
}

double initial_temperature(const ShearDeckParams& p, double mean_diameter) {
  const double scale = mean_diameter * p.shear_rate * mean_diameter * p.shear_rate;  // (d γ̇)²
  if (p.initial_temperature >= 0.0) return p.initial_temperature * scale;
  const DemMaterial& m = p.material;
  double phi = p.solid_fraction;
  if (p.constant_pressure)  // the φ whose kinetic-theory I is the imposed one
    phi = kinetic_solid_fraction_at(
        p.shear_rate * mean_diameter / std::sqrt(p.normal_stress / m.particle_density),
        m.restitution, m.particle_friction);
  return kinetic_shear_temperature(phi, m.restitution, m.particle_friction) * scale;
}

ShearDeck make_shear_deck(const ShearDeckParams& p, const std::string& data_file_name) {
  ShearDeck out = shear_deck_timing(p);
  const DemMaterial& m = p.material;
  const SizeRange range = size_range(m);
  const double reference_speed = p.impact_speed_factor * fastest_shear_rate(p) * range.large;

  // --- diameters (seeded)
  std::mt19937_64 rng(p.seed);
  const long n = p.particles;
  out.diameters.assign(n, m.diameter);
  if (m.size == SizeDistribution::bidisperse) {
    const long n_large = std::lround(m.large_fraction * double(n));
    for (long i = 0; i < n; ++i) out.diameters[i] = i < n_large ? range.large : range.small;
  } else if (m.size == SizeDistribution::uniform) {
    for (auto& d : out.diameters) d = range.small + (range.large - range.small) * uniform(rng);
  }
  out.mean_diameter = std::accumulate(out.diameters.begin(), out.diameters.end(), 0.0) / n;
  out.solid_volume = 0.0;
  for (double d : out.diameters) out.solid_volume += std::numbers::pi / 6.0 * d * d * d;

  // --- random sequential addition at φ_insert = min(φ, 0.3), then compression (stage 1) to φ
  // (initial_state.hpp): never an expansion of a denser packing.
  out.insertion_solid_fraction = std::min(p.solid_fraction, insertion_solid_fraction);
  const RandomPacking packing = random_packing(out.diameters, out.insertion_solid_fraction, rng());
  out.initial_box_length = packing.box_length;
  std::string atoms;
  for (long i = 0; i < n; ++i)
    atoms += fmt::format("{} 1 {:.17g} {:.17g} {:.17g} {:.17g} {:.17g}\n", i + 1, out.diameters[i],
                         m.particle_density, packing.positions[3 * i], packing.positions[3 * i + 1],
                         packing.positions[3 * i + 2]);
  out.data = fmt::format(
      "LIGGGHTS data file written by granflow: {} spheres, seed {}\n\n{} atoms\n1 atom types\n\n"
      "0 {:.17g} xlo xhi\n0 {:.17g} ylo yhi\n0 {:.17g} zlo zhi\n0 0 0 xy xz yz\n\n"
      "Atoms\n\n{}",
      n, p.seed, n, out.initial_box_length, out.initial_box_length, out.initial_box_length, atoms);

  std::string fluid_fix;
  if (p.wet.enabled) {
    const FluidTimeStepInput in = fluid_step_input(p, out);
    const FluidTimeStep step =
        stable_fluid_time_step(out.fluid_times, p.dt_safety, p.wet.viscous_safety);
    const auto yes_no = [](bool b) { return b ? "yes" : "no"; };
    fluid_fix = fmt::format(
        "\n# ---- immersed: drag, rotational drag, lubrication about the Lees-Edwards flow "
        "(docs/dem_fluid.md)\n# dt set by the {} limit (time scale {:.6g} s); the stress "
        "split is formed only on the steps granflow-dem samples (sums sampled)\n"
        "variable gf_viscosity equal {:.17g}\n"
        "fix gf_fluid all fluid/le viscosity {:.17g} permeability {} sphericity {:.17g} drag yes "
        "rotation {}{} sums sampled\n",
        step.limited_by, step.limit_time, p.wet.viscosity, p.wet.viscosity, p.wet.permeability,
        p.wet.sphericity, yes_no(p.wet.rotational_drag),
        p.wet.lubrication
            ? fmt::format(" lubrication {:.17g} {:.17g} tangential {}", in.fluid.maximum_gap,
                          in.fluid.minimum_gap, yes_no(p.wet.tangential_lubrication))
            : std::string());
  }
  out.box_length = std::cbrt(out.solid_volume / p.solid_fraction);
  out.initial_temperature = initial_temperature(p, out.mean_diameter);

  // Dry decks: the contact virial averaged over every step of each sample interval,
  //   <P^vir>_k = (1/n) sum_{j=1..n} P^vir(t_{k-1} + j dt),  n = gf_sample_every,
  // by `fix ave/time 1 n n` (LAMMPS/LIGGGHTS fix ave/time: Nevery 1, Nrepeat n, Nfreq n), which
  // granflow-dem reads instead of the instant: in collisional flows an instant either catches a
  // stiff contact or not (samples jumping 100x), and a servo fed such instants holds the median,
  // not the mean. ave/time ends its windows on multiples of n, so the compression is rounded up
  // to whole sample intervals (shear_deck_timing). Immersed decks keep instants: the
  // stress split of fix fluid/le is formed on the sampled steps only and must add up with them.
  const long compression = out.compression_steps;
  const std::string stress_average =
      p.wet.enabled ? std::string()
                    : fmt::format(
                          "# contact virial averaged over every step of each sample interval "
                          "(read by granflow-dem)\n"
                          "fix             gf_stress all ave/time 1 {0} {0} c_gf_virial[1] "
                          "c_gf_virial[2] c_gf_virial[3] c_gf_virial[4] c_gf_virial[5] "
                          "c_gf_virial[6]\n",
                          out.sample_every);

  DriverParameters driver;
  driver.shear_rate = p.shear_rate;
  driver.total_steps = out.total_steps;
  driver.sample_every = out.sample_every;
  driver.constant_pressure = p.constant_pressure;
  driver.normal_stress = p.normal_stress;
  driver.servo_gain = p.servo_gain;
  driver.servo_max_strain = p.servo_max_strain;
  driver.servo_every = out.servo_every;
  driver.servo_move_every = out.servo_move_every;
  driver.profile_bins = p.profile_bins;
  driver.particle_density = m.particle_density;
  driver.targets = p.targets;
  driver.check_every = out.check_every;
  driver.stop_steps = out.stop_steps;
  driver.stop_drainage_length = p.stop_drainage_length;
  driver.stop_normal_stress = p.stop_normal_stress;
  driver.drainage_length = p.drainage_length;
  driver.height_resistance = p.height_resistance;
  if (driver.drainage_length > 0.0 || driver.height_resistance > 0.0)
    driver.normal_stress = p.normal_stress;  // the total σ_yy held every step
  driver.rate_step_steps = out.rate_step_steps;
  driver.rate_step_shear_rate = p.rate_step_shear_rate;
  // (d γ̇)² as point_analysis.cpp forms it, so the frozen check is the same number
  driver.temperature_scale = out.mean_diameter * p.shear_rate * out.mean_diameter * p.shear_rate;
  const double skin = 0.2 * out.mean_diameter;
  const double top_speed = p.shear_rate * out.box_length;
  // The start: the random gas compressed to φ (stage 1), or a prepared state read whole.
  const bool prepared = !p.prepared_restart.empty();
  const std::string start_commands =
      prepared ? fmt::format(
                     "# prepared state (kind: dem_prepare): atoms, box, contact history\n"
                     "read_restart    {}\ncommunicate     single vel yes",
                     p.prepared_restart)
               : fmt::format("read_data       {}", data_file_name);
  const std::string stage1 =
      prepared
          ? std::string(
                "# ---- stage 1: none, the prepared state is at rest at its p0 (after a\n"
                "# restart LIGGGHTS wants reset_timestep right before a run)\n"
                "reset_timestep  0\nrun             0\n")
          : fmt::format(
                "# ---- stage 1: isotropic compression from the random insertion at phi = "
                "{0:.6g} to phi =\n# {1:.6g} (box edge {2:.6g} m -> {3:.6g} m)\n"
                "fix             gf_compress all deform 1 x final 0 {3:.17g} y final 0 {3:.17g} "
                "z final 0 {3:.17g} remap x\nrun             {4}\nunfix           gf_compress\n",
                out.insertion_solid_fraction, p.solid_fraction, out.initial_box_length,
                out.box_length, compression);
  const std::string ramp =
      prepared ? fmt::format(
                     "variable        gf_ylo equal ylo\nvariable        gf_yhi equal yhi\n"
                     "variable        gf_vtop equal {:.17g}*ly\n"
                     "velocity        all ramp vx 0 ${{gf_vtop}} y ${{gf_ylo}} ${{gf_yhi}} "
                     "units box sum yes",
                     p.shear_rate)
               : fmt::format("velocity        all ramp vx 0 {:.17g} y 0 {:.17g} units box sum yes",
                             top_speed, out.box_length);
  out.deck = fmt::format(
      R"(# granflow DEM deck: Lees-Edwards periodic simple shear, LIGGGHTS 3.8.0 (Debian).
# Run it with the granflow-dem driver, NOT plain liggghts: the driver repairs the triclinic
# bug of LIGGGHTS-PUBLIC 3.8.0 (domain.cpp:144-145, prd_lamda = 0) and runs the shear stage
# (sampling every gf_sample_every steps, constant-normal-stress servo) after this file:
#   granflow-dem in.granflow            or   mpirun -np 2 granflow-dem in.granflow
# {dt_rule}

# ---- parameters read by granflow-dem
{driver_parameters}# shear start: granflow-dem adds Gaussian velocity fluctuations of granular temperature
# gf_initial_temperature (m^2/s^2, = {t0_scaled:.6g} (d gd)^2{t0_rule}) to the streaming profile,
# zero total momentum, seeded by gf_velocity_seed and the atom id (docs/dem_dataset.md)
variable gf_initial_temperature equal {t0:.17g}
variable gf_velocity_seed equal {vseed}

{atom_setup}# fix deform flips the box only at re-neighbouring, so |xy| may exceed Lx/2 for a few steps;
# allow that when the servo's change_box re-checks the box (error otherwise)
box             tilt large
{read}
neighbor        {skin:.17g} bin
neigh_modify    delay 0

{contact}timestep        {dt:.17g}
fix             integr all nve/sphere

# contact (pair + fix) virial; the kinetic part about the streaming profile is added by the driver
compute         gf_virial all pressure thermo_temp virial
thermo_style    custom step atoms ke c_gf_virial[2] c_gf_virial[4]
thermo_modify   norm no lost error
thermo          {thermo_comp}

{stage1}
# ---- stage 2: Lees-Edwards simple shear u_x = gd (y - ylo): streaming profile + tilt rate
{ramp}
fix             gf_shear all deform 1 xy erate {gd:.17g} remap v
thermo          0                            # thermo (and the virial) at the end of each sampled chunk
{stress_average})",
      fmt::arg(
          "dt_rule",
          m.contact_law == ContactLaw::hooke
              ? fmt::format("dt = {} * t_c = {:.6g} s (linear spring-dashpot, smallest pair)",
                            p.dt_safety, out.times.linear_spring)
              : fmt::format("dt = {} * min(t_Rayleigh = {:.6g} s, t_Hertz = {:.6g} s at "
                            "{:.4g} m/s)",
                            p.dt_safety, out.times.rayleigh, out.times.hertz, reference_speed)),
      fmt::arg("gd", p.shear_rate), fmt::arg("driver_parameters", driver_parameter_lines(driver)),
      fmt::arg("atom_setup", granular_atom_setup()), fmt::arg("read", start_commands),
      fmt::arg("stage1", stage1), fmt::arg("ramp", ramp), fmt::arg("skin", skin),
      fmt::arg("contact", contact_law_commands(m, out.mean_diameter)), fmt::arg("dt", out.dt),
      fmt::arg("thermo_comp", std::max(1L, p.compression_steps / 5)),
      fmt::arg("t0", out.initial_temperature),
      fmt::arg("t0_scaled", out.initial_temperature / (out.mean_diameter * p.shear_rate *
                                                       out.mean_diameter * p.shear_rate)),
      fmt::arg("t0_rule", p.initial_temperature >= 0.0 ? ", control.initial_temperature"
                          : p.constant_pressure
                              ? ", kinetic theory's homogeneous shear at the imposed I"
                              : ", kinetic theory's homogeneous shear f2/f3 at phi"),
      fmt::arg("vseed", p.seed % 2147483647UL), fmt::arg("stress_average", stress_average));
  out.deck += fluid_fix;
  // The shear starts after the compression, or at timestep 0 of a prepared state (its deck
  // resets the step count).
  out.deck += snapshot_commands(out.snapshot_every, prepared ? 0 : compression, p.shear_rate);
  return out;
}

}  // namespace granflow::dem
