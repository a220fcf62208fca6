// `kind: dem`: the case schema (every key with its unit, bounds and default) and the reading of
// one expanded case into the deck parameters (dem_kind.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include "continuum/sections/model_sections.hpp"
#include "core/file_io.hpp"
#include "dem_coupling/dem_kind.hpp"
#include "dem_coupling/kind/dem_fits.hpp"
#include "dem_coupling/kind/mixed_number_fit.hpp"
#include "dem_coupling/kind/shear_start_keys.hpp"

namespace granflow::dem {

core::Schema shear_schema() {
  core::Schema s = core::kind_header(
      "dem", "",
      "Periodic (Lees-Edwards) simple shear of dry or immersed (liquid.enabled: drag, "
      "lubrication) spheres in LIGGGHTS 3.8.0 via granflow-dem, at constant volume or constant "
      "normal stress; steady μ, φ, T, I, Z (wet: J, K, St, stress split) with error bars.");
  // The continuum's material section (one description for both), with DEM-only keys added and
  // the friction made sweepable (frictional vs frictionless sweeps).
  core::Field material = continuum::material_section();
  material.number("particle_friction", "", "interparticle friction coefficient μ_p")
      .default_value("0.5")
      .at_least(0)
      .sweepable();
  material
      .choice("size_distribution", {"monodisperse", "bidisperse", "uniform"},
              "particle sizes (number-mean diameter = material.diameter)")
      .default_value("bidisperse");
  material.number("size_ratio", "", "bidisperse: d_large / d_small")
      .default_value("1.22")
      .at_least(1);
  material.number("large_fraction", "", "bidisperse: number fraction of large particles")
      .default_value("0.5")
      .at_least(0)
      .at_most(1);
  material.number("polydispersity", "", "uniform: d uniform in d (1 ± polydispersity)")
      .default_value("0.1")
      .at_least(0)
      .less_than(1);
  material
      .choice("contact_law", {"hertz", "hooke"},
              "normal contact: hertz (Hertz-Mindlin from E, ν) or hooke (linear spring-dashpot "
              "k_n, k_t, as in Silbert et al. 2001); tangential history "
              "spring with Coulomb limit and damping from e in both")
      .default_value("hertz");
  add_tangential_damping_key(material);
  material.number("normal_stiffness", "N/m", "hooke: normal spring k_n (required for hooke)")
      .greater_than(0);
  material.number("tangential_stiffness_ratio", "", "hooke: k_t / k_n")
      .default_value("0.2857142857142857")
      .greater_than(0);
  s.add(std::move(material));
  // Immersed runs: the continuum's liquid section (enabled, viscosity, permeability,
  // sphericity, trulsson_alpha are read; the other keys are the continuum's) plus DEM-only keys.
  // The viscosity is made sweepable here (St = ρ_p d² γ̇/η0 at fixed γ̇ and σ_yy): the section is
  // rebuilt from the continuum's fields, a copy of liquid.viscosity marked sweepable.
  const core::Field continuum_liquid = continuum::liquid_section();
  core::Field liquid(continuum_liquid.key(), continuum_liquid.type(), continuum_liquid.unit(),
                     continuum_liquid.doc());
  for (core::Field child : continuum_liquid.children()) {
    if (child.key() == "viscosity") child.sweepable();
    liquid.add(std::move(child));
  }
  s.add(std::move(liquid));
  auto& wet = s.section(
      "dem_liquid", "DEM fluid forces of fix fluid/le (with liquid.enabled; docs/dem_fluid.md)");
  wet.boolean("lubrication", "pair lubrication (normal squeeze, Reynolds)").default_value("true");
  wet.number("maximum_gap", "", "h_max / d: lubrication acts for gaps h < h_max (< d_small/(2d))")
      .default_value("0.05")
      .greater_than(0);
  wet.number("minimum_gap", "",
             "h_min / d: resistance held at h_min below it (~0.01 at the viscous end, since "
             "the lubrication time step ∝ h_min)")
      .default_value("0.001")
      .greater_than(0);
  wet.boolean("tangential_lubrication", "the log(1/h) shear mode of lubrication")
      .default_value("true");
  wet.boolean("rotational_drag", "Stokes rotlet torque -π η d³ (ω - Ω)").default_value("true");
  wet.number("viscous_time_step_safety", "",
             "Δt <= safety × shortest viscous relaxation time (drag, rotation, lubrication)")
      .default_value("0.2")
      .greater_than(0)
      .at_most(1);
  auto& dem = s.section("dem", "DEM run settings");
  dem.integer("particles", "number of spheres")
      .default_value("1000")
      .greater_than(0)
      .limited_by("max_particles");
  dem.integer("seed",
              "random seed of the initial packing and sizes (sweep it for the sample-to-sample "
              "scatter the batch-means error bars leave out); a positive int (1 to 2147483647), "
              "as LIGGGHTS' own random seeds")
      .default_value("1")
      .at_least(1)
      .sweepable();
  dem.integer("ranks", "MPI ranks (mpirun -np) for granflow-dem")
      .default_value("1")
      .at_least(1)
      .limited_by("max_ranks");
  dem.number("time_step_safety", "",
             "Δt = safety × min(Rayleigh time, Hertz contact time); hooke: safety × t_c of the "
             "linear spring-dashpot")
      .default_value("0.1")
      .greater_than(0)
      .at_most(0.5);
  dem.number("impact_speed_factor", "", "Hertz time at impact speed = factor × γ̇ × d_max")
      .default_value("3")
      .greater_than(0);
  dem.integer("compression_steps", "steps of the isotropic compression before shearing")
      .default_value("10000")
      .greater_than(0);
  auto& control = s.section("control", "volume or normal-stress control");
  control
      .choice("mode", {"constant_volume", "constant_pressure", "drained", "damped_height"},
              "constant_volume: φ imposed; constant_pressure: σ_yy imposed by a servo on L_y; "
              "drained (immersed): the total σ_yy = control.normal_stress held step by step "
              "while the liquid drains in or out over control.drainage_length, ε̇_yy = "
              "κ(φ)/(η0 H²) (σ_n − σ_yy) (fix drainage); damped_height (dry or immersed): "
              "the same with ε̇_yy = (σ_n − σ_yy)/R, R = control.height_resistance")
      .required();
  control.number("solid_fraction", "", "φ (constant_volume), initial φ (constant_pressure)")
      .default_value("0.55")
      .greater_than(0)
      .less_than(1)
      .sweepable();
  add_initial_temperature_key(control);
  control
      .number("normal_stress", "Pa",
              "imposed normal stress σ_yy (constant_pressure), total σ_n (drained; default the "
              "prepared p0)")
      .greater_than(0)
      .sweepable();
  control
      .number("drainage_length", "m",
              "drainage length H of a drained shear (the liquid's path in or out of the sample)")
      .default_value("0.01")
      .greater_than(0);
  control
      .number("height_resistance", "Pa s",
              "R of control.mode damped_height: the box height moves at ε̇_yy = (σ_n − σ_yy)/R "
              "(a viscous piston; R/M is its response time, M = dσ_yy/dε_yy of the packing)")
      .default_value("100")
      .greater_than(0);
  control
      .number(
          "servo_gain", "",
          "relative height change per relative stress error; default: loop gain "
          "gain × d ln σ/d ln φ ≈ 0.25 at the target, i.e. dry 0.1 × I_target (I_target = "
          "γ̇ d / sqrt(σ_yy/ρ_p)) within [1e-4, 0.02], immersed 0.0625 √K/(1 + √K) (K = J + "
          "α I² at the target, φ = φ_m/(1 + √K); loop gain 0.125) within [1e-4, 0.05]; dry with "
          "contact_law hooke at most 2 σ_yy d/k_n (the elastic limit)")
      .greater_than(0);
  control.number("servo_max_strain", "", "largest relative height change per servo update")
      .default_value("0.002")
      .greater_than(0)
      .at_most(0.05);
  control
      .number("servo_strain", "",
              "shear strain between servo updates; default 0.1, or strain.sample with "
              "contact_law hooke (its small elastic gain needs frequent updates to converge)")
      .greater_than(0);
  s.number("shear_rate", "1/s", "imposed shear rate γ̇").required().greater_than(0).sweepable();
  auto& rate_step =
      s.section("rate_step",
                "a step in the shear rate during the run (constant_volume, drained "
                "or damped_height): the affine profile's change added to every sphere");
  rate_step.number("strain", "", "shear strain at which the rate steps").greater_than(0);
  rate_step.number("shear_rate", "1/s", "the shear rate after the step").greater_than(0);
  auto& strain = s.section("strain", "shear strain to run and sample");
  strain.number("total", "", "shear strain of the run").default_value("20").greater_than(0);
  strain.number("sample", "", "shear strain between samples").default_value("0.01").greater_than(0);
  auto& targets = strain.section(
      "target_error",
      "error-targeted run length (docs/dem_dataset.md): the run goes on until the steady "
      "window is steady and the standard error of each observable listed here is at most its "
      "target (checked every strain.check), or until strain.max; strain.total is then unused. "
      "summary.json: strain.used, strain.target_met, strain.achieved_error.NAME, "
      "strain.target_met.NAME");
  targets.number("friction", "", "largest relative standard error se(μ)/μ of the friction")
      .greater_than(0);
  targets
      .number("solid_fraction", "", "largest absolute standard error se(φ) of the solid fraction")
      .greater_than(0);
  targets
      .number("temperature", "",
              "largest relative standard error se(T)/T of the granular temperature")
      .greater_than(0);
  strain
      .number("max", "",
              "largest shear strain of a run with strain.target_error (required with it, unused "
              "without)")
      .greater_than(0);
  strain
      .number("check", "",
              "shear strain between the checks of strain.target_error (rounded to whole servo "
              "intervals)")
      .default_value("0.5")
      .greater_than(0);
  strain
      .integer("confirm_checks",
               "consecutive checks at which the targets of strain.target_error must hold before "
               "the run stops (1: the first check that meets them, whose errors are optimistic; "
               "docs/dem_dataset.md)")
      .default_value(std::to_string(default_confirm_checks))
      .at_least(1);
  auto& statistics = s.section("statistics", "error bars that include the sample variability");
  statistics
      .integer("seeds",
               "runs every condition with dem.seed, dem.seed + 1, ..., dem.seed + N - 1 and "
               "reports the mean over the seeds with its between-seed standard error (seeds.* in "
               "summary.json, /seeds in result.h5; as a sweep over dem.seed); 1: one run")
      .default_value("1")
      .at_least(1)
      .at_most(64);
  auto& start = s.section("start", "the state the shear starts from (docs/transient_dem.md)");
  start.string("preparation",
               "a kind: dem_prepare run directory: seed S starts from its seed_S packing at rest "
               "(box, φ0, p0, contacts; friction switched to material.particle_friction; T0 = 0 "
               "unless control.initial_temperature; control.solid_fraction, dem.particles and "
               "dem.compression_steps unused); absent: the random gas compressed to φ");
  auto& transient = s.section("transient", "metrics of a run started from a prepared state");
  transient
      .number("liquefaction_fraction", "",
              "liquefied where p' = tr(σ)/3 < fraction × p0 (p0 the prepared mean stress)")
      .default_value("0.05")
      .greater_than(0)
      .less_than(1);
  transient
      .number("residual_fraction", "",
              "residual τ and p': means over the last fraction of the strain")
      .default_value("0.2")
      .greater_than(0)
      .at_most(1);
  auto& stop =
      s.section("stop",
                "after the shear, the shear stopped (the streaming flow taken out): the box "
                "held, or drained under a normal stress; the agitation decays "
                "(docs/transient_dem.md)");
  stop.number("duration", "s", "how long the stopped sample is followed; 0: no stop stage")
      .default_value("0")
      .at_least(0);
  stop.number("cooling_fraction", "",
              "cooling time: the time after the stop at which T first falls below this fraction "
              "of the flowing T (its mean over the residual window of the shear)")
      .default_value("0.1")
      .greater_than(0)
      .less_than(1);
  stop.number("drainage_length", "m",
              "drained stop (immersed only): the stopped sample compacts under stop.normal_stress "
              "as fast as its liquid drains over this length, ε̇_yy = κ(φ)/(η0 H²) (σ_n − σ_yy) "
              "(fix drainage); 0: the volume is held")
      .default_value("0")
      .at_least(0);
  stop.number("normal_stress", "Pa",
              "total normal stress σ_n of a drained stop (default: the prepared p0)")
      .greater_than(0);
  stop.number("reconsolidation_fraction", "",
              "reconsolidation time of a drained stop: the first time σ_yy reaches this fraction "
              "of stop.normal_stress (the excess pore pressure below 1 − fraction of it)")
      .default_value("0.9")
      .greater_than(0)
      .less_than(1);
  auto& output = s.section("output", "what is written");
  output.integer("profile_bins", "y bins of the mean velocity profile")
      .default_value("10")
      .at_least(1);
  output
      .number("snapshot_strain", "",
              "shear strain between particle snapshots: snapshot_<step>.vtu for ParaView (indexed "
              "by strain in snapshots.pvd) and snapshot_<step>.dump, a LAMMPS text dump of the "
              "same spheres, for OVITO (File > Load File, snapshot_*.dump); 0: none")
      .default_value("0")
      .at_least(0);
  return s;
}

DemMaterial read_dem_material(const core::Case& c, double particle_friction) {
  DemMaterial m;
  m.diameter = c.number("material.diameter");
  m.particle_density = c.number("material.particle_density");
  m.restitution = c.number("material.restitution");
  m.particle_friction = particle_friction;
  m.youngs_modulus = c.number("material.youngs_modulus");
  m.poisson_ratio = c.number("material.poisson_ratio");
  const std::string size = c.string("material.size_distribution");
  m.size = size == "bidisperse" ? SizeDistribution::bidisperse
           : size == "uniform"  ? SizeDistribution::uniform
                                : SizeDistribution::monodisperse;
  m.size_ratio = c.number("material.size_ratio");
  m.large_fraction = c.number("material.large_fraction");
  m.polydispersity = c.number("material.polydispersity");
  m.contact_law =
      c.string("material.contact_law") == "hooke" ? ContactLaw::hooke : ContactLaw::hertz;
  if (c.has("material.normal_stiffness"))
    m.normal_stiffness = c.number("material.normal_stiffness");
  m.tangential_stiffness_ratio = c.number("material.tangential_stiffness_ratio");
  const std::string damping = c.string("material.tangential_damping");
  m.tangential_damping = damping == "none" ? TangentialDamping::none
                         : damping == "lammps_hooke_history"
                             ? TangentialDamping::lammps_hooke_history
                             : TangentialDamping::liggghts;
  return m;
}

ShearDeckParams read_shear_params(const core::Case& c) {
  ShearDeckParams p;
  p.material = read_dem_material(c, c.number("material.particle_friction"));
  const DemMaterial& m = p.material;
  read_shear_start_keys(c, p);
  p.particles = c.integer("dem.particles");
  p.seed = static_cast<unsigned long>(c.integer("dem.seed"));
  p.dt_safety = c.number("dem.time_step_safety");
  p.impact_speed_factor = c.number("dem.impact_speed_factor");
  p.compression_steps = c.integer("dem.compression_steps");
  p.constant_pressure = c.string("control.mode") == "constant_pressure";
  p.solid_fraction = c.number("control.solid_fraction");
  p.shear_rate = c.number("shear_rate");  // before the servo gain, which depends on it
  if (c.has("control.normal_stress")) p.normal_stress = c.number("control.normal_stress");
  if (c.has("control.servo_gain")) p.servo_gain = c.number("control.servo_gain");
  p.servo_max_strain = c.number("control.servo_max_strain");
  p.servo_strain = c.has("control.servo_strain")        ? c.number("control.servo_strain")
                   : m.contact_law == ContactLaw::hooke ? c.number("strain.sample")
                                                        : 0.1;
  p.total_strain = c.number("strain.total");
  p.stop_duration = c.number("stop.duration");
  p.stop_drainage_length = c.number("stop.drainage_length");
  if (c.string("control.mode") == "drained")
    p.drainage_length = c.number("control.drainage_length");
  if (c.string("control.mode") == "damped_height")
    p.height_resistance = c.number("control.height_resistance");
  if (c.has("rate_step.strain") || c.has("rate_step.shear_rate")) {
    p.rate_step_strain = c.has("rate_step.strain") ? c.number("rate_step.strain") : 0.0;
    p.rate_step_shear_rate = c.has("rate_step.shear_rate") ? c.number("rate_step.shear_rate") : 0.0;
  }
  if (c.has("stop.normal_stress")) p.stop_normal_stress = c.number("stop.normal_stress");
  p.sample_strain = c.number("strain.sample");
  // strain.target_error: the observables of target_observables (deck/driver_parameters.hpp);
  // the run is then at most strain.max long (dem_kind.cpp checks that it is given).
  for (std::size_t k = 0; k < target_observables.size(); ++k)
    if (const std::string key = std::string("strain.target_error.") + target_observables[k];
        c.has(key))
      p.targets.error[k] = c.number(key);
  p.check_strain = c.number("strain.check");
  p.targets.confirm_checks = static_cast<int>(c.integer("strain.confirm_checks"));
  if (p.targets.any() && c.has("strain.max")) p.total_strain = c.number("strain.max");
  p.profile_bins = static_cast<int>(c.integer("output.profile_bins"));
  p.snapshot_strain = c.number("output.snapshot_strain");
  WetShear& w = p.wet;
  w.enabled = c.boolean("liquid.enabled");
  w.viscosity = c.number("liquid.viscosity");
  w.permeability = c.string("liquid.permeability");
  w.sphericity = c.number("liquid.sphericity");
  w.trulsson_alpha = c.number("liquid.trulsson_alpha");
  w.lubrication = c.boolean("dem_liquid.lubrication");
  w.maximum_gap = c.number("dem_liquid.maximum_gap");
  w.minimum_gap = c.number("dem_liquid.minimum_gap");
  w.tangential_lubrication = c.boolean("dem_liquid.tangential_lubrication");
  w.rotational_drag = c.boolean("dem_liquid.rotational_drag");
  w.viscous_safety = c.number("dem_liquid.viscous_time_step_safety");
  // Servo gain default (needs the liquid): from d ln σ/d ln φ at the target, dry from I (loop
  // gain 0.25), immersed from K = J + α I² (0.125; shear_deck.hpp, default_servo_gain; 0.01 at
  // I = 0.01 made sigma_yy oscillate at twice the target).
  if (!c.has("control.servo_gain") && p.constant_pressure) p.servo_gain = default_servo_gain(p);
  return p;
}

}  // namespace granflow::dem
