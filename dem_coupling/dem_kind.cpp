#include "dem_coupling/dem_kind.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <span>

#include "continuum/sections/model_sections.hpp"
#include "core/file_io.hpp"
#include "core/interrupt.hpp"
#include "core/process.hpp"
#include "core/sweep_scheduler.hpp"
#include "dem_coupling/kind/dem_columns.hpp"
#include "dem_coupling/kind/dem_fits.hpp"
#include "dem_coupling/kind/launch.hpp"
#include "dem_coupling/kind/mixed_number_fit.hpp"
#include "dem_coupling/kind/point_analysis.hpp"
#include "dem_coupling/kind/prepare_kind.hpp"
#include "dem_coupling/kind/report_section.hpp"
#include "dem_coupling/kind/series_table.hpp"
#include "dem_coupling/kind/shear_start_keys.hpp"
#include "dem_coupling/kind/transient.hpp"
#include "statistics/steady_state.hpp"

namespace granflow::dem {

namespace {

// The run a case implies, from the Δt and step counts the deck will use (shear_deck_timing:
// no particles are placed, so this costs the same at any dem.particles): at most
// limits.max_steps time steps, and >= 100 samples for the batch-means error bars.
void check_run_length(const core::Case& c, const ShearDeckParams& p) {
  const ShearDeck timing = shear_deck_timing(p);
  // The run length key: strain.max with strain.target_error, else strain.total.
  const char* length_key = p.targets.any() ? "strain.max" : "strain.total";
  const double strain_per_step = p.shear_rate * timing.dt;
  const double steps = double(p.compression_steps) + p.total_strain / strain_per_step;
  const double max_steps = c.limit("max_steps");
  if (!(steps <= max_steps)) {
    // Blame strain.total when the run would fit at its default strain, else the shear rate.
    const double default_strain =
        std::stod(*c.schema().child("strain")->child("total")->default_text());
    const bool long_strain =
        p.total_strain > default_strain &&
        double(p.compression_steps) + default_strain / strain_per_step <= max_steps;
    c.fail(long_strain ? length_key : "shear_rate",
           fmt::format("the run would take {:.3g} time steps (dem.compression_steps {} + "
                       "{} {:g} / (shear_rate {:g} 1/s × Δt {:.3g} s, set by the {} "
                       "limit)); expected at most limits.max_steps = {:g} ({}, or raise "
                       "limits.max_steps to run it on purpose)",
                       steps, p.compression_steps, length_key, p.total_strain, p.shear_rate,
                       timing.dt, timing.dt_limit, max_steps,
                       long_strain ? fmt::format("a smaller {}", length_key)
                                   : std::string("a larger shear_rate")));
  }
  // At least a few samples per unit strain and a steady part long enough for batch means.
  const long samples = timing.total_steps / timing.sample_every;
  if (samples >= 100) return;
  if (p.total_strain / p.sample_strain < 100.0 * (1.0 - 1e-9))
    c.fail("strain.sample", fmt::format("at most {}/100 = {:g} (batch means need >= 100 samples)",
                                        length_key, p.total_strain / 100.0));
  // strain.sample is small enough, but a time step is a large strain at this rate: rounded to
  // whole steps, a sample interval holds more strain than asked and the run fewer samples.
  c.fail("shear_rate",
         fmt::format("a time step is γ̇ Δt = {:.3g} strain (Δt = {:.3g} s, set by the {} limit), "
                     "so strain.sample = {:g} takes {} steps = {:.3g} strain and {} = "
                     "{:g} holds {} samples; expected >= 100 samples for the batch-means error "
                     "bars (a lower shear_rate or dem.time_step_safety, or a larger {})",
                     strain_per_step, timing.dt, timing.dt_limit, p.sample_strain,
                     timing.sample_every, double(timing.sample_every) * strain_per_step, length_key,
                     p.total_strain, samples, length_key));
}

void check_shear(const core::Case& sweep_case) {
  for (const core::Case& c : sweep_case.expand_sweep()) {
    if (c.string("control.mode") == "constant_pressure" && !c.has("control.normal_stress"))
      c.fail("control.normal_stress",
             "missing required key for constant_pressure; expected σ_yy > 0 [Pa]");
    // Drained shear and rate steps are transients: from a prepared state, with its metrics.
    if (const std::string mode = c.string("control.mode");
        (mode == "drained" || mode == "damped_height") && !c.has("start.preparation"))
      c.fail("control.mode",
             "constant_volume or constant_pressure without start.preparation (a drained or "
             "damped shear starts from a prepared packing, docs/transient_dem.md)");
    if (c.has("rate_step.strain") && !c.has("start.preparation"))
      c.fail("rate_step.strain",
             "absent without start.preparation (a rate step is a transient from a prepared "
             "packing)");
    if (c.has("rate_step.strain") != c.has("rate_step.shear_rate"))
      c.fail(c.has("rate_step.strain") ? "rate_step.shear_rate" : "rate_step.strain",
             "missing: a rate step needs both rate_step.strain and rate_step.shear_rate");
    if (c.string("material.contact_law") == "hooke" && !c.has("material.normal_stiffness"))
      c.fail("material.normal_stiffness",
             "missing required key for contact_law: hooke; expected k_n > 0 [N/m]");
    // strain.target_error needs the largest run, strain.max, which means nothing without it.
    bool targets = false;
    for (const char* name : target_observables)
      targets = targets || c.has(std::string("strain.target_error.") + name);
    if (targets && !c.has("strain.max"))
      c.fail("strain.max",
             "missing required key with strain.target_error; expected the largest shear strain "
             "of the run (> 0)");
    if (!targets && c.has("strain.max"))
      c.fail("strain.max", "only with strain.target_error (the run length is strain.total)");
    // The stop's rows follow the shear's in the series: only the transient analysis splits them.
    if (c.number("stop.duration") > 0 && (!c.has("start.preparation") || targets))
      c.fail("stop.duration",
             "0 unless the shear starts from start.preparation, without strain.target_error "
             "(the stop follows a transient of fixed length)");
    const ShearDeckParams p = read_shear_params(c);
    if (targets && !(p.check_strain >= p.sample_strain))
      c.fail("strain.check", ">= strain.sample (the checks fall on samples)");
    const long seeds = c.integer("statistics.seeds");
    if (seeds > 1) {
      for (const auto& [key, value] : c.condition())
        if (key == "dem.seed")
          c.fail("statistics.seeds", "1 when dem.seed is swept (the sweep is the seeds already)");
      if (c.integer("dem.seed") > 2147483647L - (seeds - 1))
        c.fail("statistics.seeds", "dem.seed + statistics.seeds - 1 <= 2147483647");
    }
    for (const auto& [path, expected] : check_shear_params(p)) c.fail(path, expected);
    check_run_length(c, p);
  }
}

// summary.json holds numbers: the limit that sets Δt as an index (docs/dem_dataset.md).
double dt_limit_index(const std::string& name) {
  constexpr const char* names[] = {"contact", "drag", "rotational drag", "normal lubrication",
                                   "tangential lubrication"};
  for (std::size_t i = 0; i < std::size(names); ++i)
    if (name == names[i]) return double(i);
  return -1.0;
}

// strain.target_error: /steady columns strain_used, target_met and, per observable with a
// target, achieved_error_NAME and target_met_NAME (flags 0/1; a failed point NaN and 0).
void write_target_columns(const std::vector<PointResult>& results, core::ResultFile& out,
                          std::vector<std::string>& column_names) {
  auto column = [&](const std::string& key) {
    std::vector<double> v;
    for (const auto& r : results) {
      const auto it = r.run_length.find(key);
      v.push_back(it == r.run_length.end() ? std::numeric_limits<double>::quiet_NaN() : it->second);
    }
    return v;
  };
  auto flags = [&](const std::string& key) {
    std::vector<long> f;
    for (double x : column(key)) f.push_back(std::isfinite(x) ? std::lround(x) : 0L);
    return f;
  };
  bool any = false;
  for (const auto& r : results) any = any || !r.run_length.empty();
  if (!any) return;
  // Names, units and meanings from the run-length tables (kind/dem_columns.hpp).
  auto write = [&](const std::string& key, const DemColumn& row, const std::string& name) {
    if (row.integer)
      out.write("/steady/" + name, flags(key), row.column.unit, row.column.description);
    else
      out.write("/steady/" + name, column(key), row.column.unit, row.column.description);
    column_names.push_back(name);
  };
  for (const char* key : {"used", "target_met"})
    write(key, *find_dem_column(dem_columns::run_length, key), dem_run_length_name(key));
  for (const char* name : target_observables) {
    const std::string n = name;
    bool given = false;
    for (const auto& r : results) given = given || r.run_length.count("target_met." + n);
    if (!given) continue;
    for (const DemColumn& row : dem_columns::run_length_per_observable) {
      if (std::string_view(row.key) == "target_error.") continue;  // an input: on /conditions/N
      const std::string key = row.key + n;
      write(key, row, dem_run_length_name(key));
    }
  }
}

int run_shear(core::RunContext& ctx) {
  // statistics.seeds = N > 1: every condition of the case runs N times, with dem.seed + k
  // (k = 0 ... N - 1), as if dem.seed were swept last (point n N + k); `swept` holds each run's
  // swept keys, dem.seed included.
  const auto base = ctx.run_case.expand_sweep();
  const auto seeds = static_cast<std::size_t>(ctx.run_case.integer("statistics.seeds"));
  std::vector<core::Case> conditions;
  std::vector<Condition> swept;
  std::vector<long> seed_of;
  for (const core::Case& c : base)
    for (std::size_t k = 0; k < seeds; ++k) {
      conditions.push_back(c);
      swept.push_back(c.condition());
      seed_of.push_back(c.integer("dem.seed") + long(k));
      if (seeds > 1) swept.back().emplace_back("dem.seed", double(seed_of.back()));
    }
  TransientShear transient(ctx.run_case);  // start.preparation (kind/transient.hpp)
  auto params_of = [&](std::size_t n) {
    ShearDeckParams p = read_shear_params(conditions[n]);
    p.seed = static_cast<unsigned long>(seed_of[n]);
    transient.apply(conditions[n], p);
    return p;
  };
  const bool sweep = ctx.run_case.is_sweep() || seeds > 1;
  core::Progress progress(ctx.log, "DEM conditions", double(conditions.size()));
  std::vector<PointResult> results;
  double total_particle_steps = 0.0, total_dem_wall = 0.0;
  int code = core::exit_ok;
  // One condition: the deck and the LIGGGHTS run in RUN_DIR/point_N (any rank,
  // core/sweep_scheduler.hpp), then its analysis, result.h5 groups, summary keys and log lines
  // (rank 0, in condition order, reading point_N/: the files of a serial run).
  auto point_dir = [&](const std::filesystem::path& run_dir, std::size_t n) {
    return sweep ? run_dir / fmt::format("point_{}", n) : run_dir;
  };
  auto label_of = [&](std::size_t n) {
    std::string label = sweep ? fmt::format("point {}", n) : std::string("DEM shear");
    for (const auto& [key, value] : swept[n]) label += fmt::format(" {}={:g}", key, value);
    return label;
  };
  auto compute = [&](const core::ConditionContext& cc) {
    const core::Case& c = conditions[cc.index];
    const ShearDeckParams p = params_of(cc.index);
    const ShearDeck deck = make_shear_deck(p, "particles.data");
    const std::filesystem::path dir = point_dir(cc.run_directory, cc.index);
    std::filesystem::create_directories(dir);
    core::write_text_file(dir / "in.granflow", deck.deck);
    core::write_text_file(dir / "particles.data", deck.data);
    const int ranks = static_cast<int>(c.integer("dem.ranks"));
    const auto command = driver_command(ranks, "in.granflow");
    const std::string label = label_of(cc.index);
    const std::string contact_rule =
        p.material.contact_law == ContactLaw::hooke
            ? fmt::format("{:g} × t_c {:.4g} s (linear spring-dashpot, k_n {:g} N/m)", p.dt_safety,
                          deck.times.linear_spring, p.material.normal_stiffness)
            : fmt::format("{:g} × min(t_Rayleigh {:.4g} s, t_Hertz {:.4g} s at {:.3g} m/s)",
                          p.dt_safety, deck.times.rayleigh, deck.times.hertz,
                          deck.times.reference_speed);
    cc.log->info(
        "{}: {} particles, γ̇ = {:g} 1/s, Δt = {:.4g} s set by the {} limit; contact: {}; {} "
        "shear steps ({} per sample)",
        label, p.particles, p.shear_rate, deck.dt, deck.dt_limit, contact_rule, deck.total_steps,
        deck.sample_every);
    if (p.wet.enabled)
      cc.log->info(
          "{}: immersed, η0 = {:g} Pa s, St = ρ_p d² γ̇/η0 = {:.4g}; viscous time scales at ν = "
          "{:.3g}: drag {:.4g} s, rotation {:.4g} s, normal lubrication {:.4g} s, tangential "
          "{:.4g} s (Δt ≤ {:g} × these)",
          label, p.wet.viscosity,
          p.material.particle_density * deck.mean_diameter * deck.mean_diameter * p.shear_rate /
              p.wet.viscosity,
          deck.fluid_solid_fraction, deck.fluid_times.drag, deck.fluid_times.rotational_drag,
          deck.fluid_times.normal_lubrication, deck.fluid_times.tangential_lubrication,
          p.wet.viscous_safety);
    if (p.constant_pressure)
      cc.log->info(
          "{}: servo to σ_yy = {:g} Pa, gain {:g}, every {} steps (at most {:g} per update)", label,
          p.normal_stress, p.servo_gain, deck.servo_every, p.servo_max_strain);
    cc.log->info("{}: rerun by hand: cd {} && {} > liggghts.out 2>&1", label,
                 core::shell_quote(dir.string()), core::shell_line(command));
    if (ranks > 1 && core::launched_by_mpirun())
      cc.log->warn(
          "{}: dem.ranks = {} in a sweep distributed over MPI ranks: every point runs an mpirun "
          "of its own; prefer --set dem.ranks=1 (docs/parallel-runs.md)",
          label, ranks);
    core::Progress strain_progress(cc.log, label + " strain", p.total_strain, 10.0);
    const auto t0 = std::chrono::steady_clock::now();
    const int status = run_in_directory(command, dir, dir / "liggghts.out", [&] {
      const SeriesTable t = read_series_table(dir / "series.tsv");
      if (t.rows() > 0) strain_progress.update(t.at("strain").back());
    });
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return core::Packer().integer(status).number(wall).take();
  };
  auto absorb = [&](std::size_t n, const std::string& bytes) {
    const ShearDeckParams p = params_of(n);
    const ShearDeck deck = make_shear_deck(p, "particles.data");
    const std::filesystem::path dir = point_dir(ctx.directory.path(), n);
    const std::string label = label_of(n);
    core::Unpacker packed(bytes);
    const int status = static_cast<int>(packed.integer());
    const double wall = packed.number();
    const std::string group = fmt::format("/conditions/{}", n);  // also for a single point
    PointResult r = analyse_point(ctx, dir, group, p, deck);
    r.wall = wall;
    r.steps = double(deck.total_steps + deck.compression_steps);
    if (p.targets
            .any())  // the shear steps granflow-dem ran (driver_stats.tsv), fewer if it stopped
      if (const SeriesTable stats = read_series_table(dir / "driver_stats.tsv");
          stats.rows() == 1 && stats.columns.count("steps"))
        r.steps = stats.at("steps")[0] + double(deck.compression_steps);
    r.particle_steps_per_s = r.particles * r.steps / wall;
    if (sweep)
      for (const auto& [key, value] : swept[n]) ctx.result.attribute(group, key, value);
    if (status != 0 && core::interrupted()) {
      ctx.log->warn(
          "{}: stopped by {} (granflow-dem status {}); the samples written so far are "
          "in {}",
          label, core::interrupt_name(), status, (dir / "series.tsv").string());
      r.values.clear();
      results.push_back(r);
      return;
    }
    if (status != 0) {
      const std::string error = first_error_line(dir / "liggghts.out");
      ctx.log->error("{}: granflow-dem exited with status {}: {}", label, status,
                     error.empty() ? "(no ERROR line)" : error);
      ctx.log->error("{}: full output in {}; the samples written so far are in result.h5", label,
                     (dir / "liggghts.out").string());
      // The other points of a sweep still run; the exit code reports the failure.
      if (code == core::exit_ok) code = status == 3 ? core::exit_numerical : core::exit_external;
      r.values.clear();
      results.push_back(r);
      progress.update(double(n + 1));
      return;
    }
    const std::string suffix = sweep ? fmt::format(".{}", n) : "";
    for (const auto& [name, value] : r.values) ctx.summary.set("steady." + name + suffix, value);
    for (const auto& [name, value] : r.run_length)
      ctx.summary.set("strain." + name + suffix, value);
    transient.absorb(ctx, n, dir, group, p, suffix);
    ctx.summary.set("dem.particles" + suffix, r.particles);
    ctx.summary.set("dem.dt" + suffix, r.dt);
    ctx.summary.set("dem.dt_limit" + suffix, dt_limit_index(deck.dt_limit));
    ctx.summary.set("cost.point_wall_s" + suffix, wall);
    ctx.summary.set("cost.steps" + suffix, r.steps);
    if (sweep) ctx.summary.set("cost.particle_steps_per_s" + suffix, r.particle_steps_per_s);
    total_particle_steps += r.particles * r.steps;
    total_dem_wall += wall;
    for (const std::string& w : r.warnings) ctx.log->warn("{}: {}", label, w);
    for (const std::string& note : r.notes) ctx.log->info("{}: {}", label, note);
    if (!r.values.empty())
      ctx.log->info(
          "{}: {} from strain {:.3g}: μ = {:.4f} ± {:.4f}, φ = {:.4f} ± {:.4f}, "
          "σ_yy = {:.4g} ± {:.2g} Pa, T = {:.4g} m²/s², I = {:.4g}, Z = {:.3f}, <δ>/d = {:.3g}; "
          "{:.1f} s ({:.3g} particle-steps/s)",
          label, r.values["reached"] != 0.0 ? "steady" : "NOT steady (see the warnings)",
          r.values["start_strain"], r.values["mu"], r.values["mu_err"], r.values["phi"],
          r.values["phi_err"], r.values["p"], r.values["p_err"], r.values["T"], r.values["I"],
          r.values["Z"], r.values["overlap"], wall, r.particle_steps_per_s);
    results.push_back(r);
    progress.update(double(n + 1));
  };
  if (!core::run_conditions(ctx, conditions.size(), compute, absorb))
    return core::exit_ok;  // another rank than 0: rank 0 writes the tables and plots

  // Steady table, one row per condition (what calibration reads; docs/results.md): the columns
  // of kind/dem_columns.hpp, a failed point NaN (its flags 0).
  bool any_wet = false;
  for (const core::Case& c : conditions) any_wet = any_wet || c.boolean("liquid.enabled");
  auto& out = ctx.result;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::string> column_names;
  auto write_column = [&](const DemColumn& col) {
    auto values_of = [&](const std::string& key) {
      std::vector<double> v;
      for (const auto& r : results) {
        const auto it = r.values.find(key);
        v.push_back(it == r.values.end() ? nan : it->second);
      }
      return v;
    };
    const std::vector<double> v = values_of(col.key);
    if (col.integer) {
      std::vector<long> flags;
      for (double x : v) flags.push_back(std::isfinite(x) ? std::lround(x) : 0L);
      out.write("/steady", col.column, flags);
    } else {
      out.write("/steady", col.column, v);
    }
    column_names.push_back(col.column.name);
    if (!col.error) return;
    const std::string name = std::string(col.column.name) + "_err";
    out.write("/steady/" + name, values_of(std::string(col.key) + "_err"), col.column.unit,
              "standard error of " + std::string(col.column.name));
    column_names.push_back(name);
  };
  for (const DemColumn& col : dem_columns::steady) write_column(col);
  if (any_wet)
    for (const DemColumn& col : dem_columns::wet_steady) write_column(col);
  std::vector<double> rate, friction_p, target, dt, wall;
  for (std::size_t n = 0; n < results.size(); ++n) {
    const ShearDeckParams p = params_of(n);
    rate.push_back(p.shear_rate);
    friction_p.push_back(p.material.particle_friction);
    target.push_back(p.constant_pressure ? p.normal_stress : p.solid_fraction);
    dt.push_back(results[n].dt);
    wall.push_back(results[n].wall);
  }
  // The imposed target, in its own unit: σ_yy under constant_pressure, φ under constant_volume.
  const bool constant_pressure = ctx.run_case.string("control.mode") == "constant_pressure";
  for (const auto& [column, values] :
       {std::pair{dem_columns::shear_rate, &rate},
        {dem_columns::particle_friction, &friction_p},
        {constant_pressure ? dem_columns::normal_stress_target : dem_columns::solid_fraction_target,
         &target},
        {dem_columns::time_step, &dt},
        {dem_columns::wall_time, &wall}}) {
    out.write("/steady", column, *values);
    column_names.push_back(column.name);
  }
  write_target_columns(results, out, column_names);
  const auto& c0 = ctx.run_case;
  out.attribute("/steady", "diameter", c0.number("material.diameter"));
  out.attribute("/steady", "particle_density", c0.number("material.particle_density"));
  out.attribute("/steady", "restitution", c0.number("material.restitution"));
  out.attribute("/steady", "control", c0.string("control.mode"));
  // What Python reads instead of lists of its own: the columns in order and the swept keys.
  out.attribute("/steady", "columns", column_names);
  std::vector<std::string> sweep_keys;
  if (!swept.empty())
    for (const auto& [key, value] : swept.front()) sweep_keys.push_back(key);
  out.attribute("/steady", "sweep_keys", sweep_keys);
  out.flush();
  // A sweep over dem.seed: means over the seeds with between-seed errors (/seeds, seeds.*).
  write_seed_statistics(ctx, group_by_seed(swept), results);

  if (!results.empty()) {
    ctx.summary.set("cost.particle_steps_per_s",
                    total_particle_steps / std::max(total_dem_wall, 1e-9));
    if (!sweep) {
      ctx.summary.set("dem.particles", results[0].particles);
      ctx.summary.set("dem.dt", results[0].dt);
    }
  }
  if (sweep) ctx.summary.set("sweep.count", double(conditions.size()));
  // A failed condition (LIGGGHTS error, or too few samples) has no steady values: its /steady row
  // is NaN and summary.json flags it (sweep.failed.N = 1, sweep.failed_points); the exit code of
  // a LIGGGHTS failure is non-zero.
  auto get = [&](const PointResult& r, const char* key) {
    const auto it = r.values.find(key);
    return it == r.values.end() ? nan : it->second;
  };
  double failed = 0;
  for (std::size_t n = 0; n < results.size(); ++n)
    if (results[n].values.empty()) {
      ++failed;
      if (sweep) ctx.summary.set(fmt::format("sweep.failed.{}", n), 1.0);
    }
  if (sweep) ctx.summary.set("sweep.failed_points", failed);
  if (sweep) {
    // μ(I), φ(I) per μ_p (dry) or the mixed-number law and Boyer's split (wet): /fits and fit.*
    // (kind/dem_fits.hpp; `granflow report` re-derives the same from result.h5).
    DemSteadyTable table;
    table.wet = any_wet;
    table.particle_friction = friction_p;
    for (const auto& r : results) {
      table.inertial.push_back(get(r, "I"));
      table.inertial_err.push_back(get(r, "I_err"));
      table.friction.push_back(get(r, "mu"));
      table.friction_err.push_back(get(r, "mu_err"));
      table.solid_fraction.push_back(get(r, "phi"));
      table.solid_fraction_err.push_back(get(r, "phi_err"));
      if (!any_wet) continue;
      table.stokes.push_back(get(r, "St"));
      table.viscous.push_back(get(r, "J"));
      table.viscous_err.push_back(get(r, "J_err"));
      table.friction_contact.push_back(get(r, "mu_contact"));
      table.friction_contact_err.push_back(get(r, "mu_contact_err"));
      table.friction_lubrication.push_back(get(r, "mu_lub"));
      table.friction_lubrication_err.push_back(get(r, "mu_lub_err"));
    }
    const DemFits fits = compute_dem_fits(table);
    write_dem_fits(fits, table, out);
    for (const auto& [key, value] : dem_fit_summary(fits, table)) ctx.summary.set(key, value);
    for (const InertialLawFit& d : fits.dry) ctx.log->info("{}", dry_fit_log_line(d));
    if (any_wet) {
      const MixedNumberLawFit& m = fits.mixed;
      ctx.log->info(
          "μ(K), K = J + α I²: α = {:.4g} ± {:.2g}, μ_1 = {:.4f} ± {:.4f}, μ_2 = {:.4f} ± {:.4f}, "
          "K_0 = {:.4g} ± {:.2g} (χ²_red {:.3g}, {} points); viscous points: τ_contact/σ_yy − "
          "Boyer μ_c(J): Σ res²/n = {:.3g}, τ_lub/σ_yy = {:.2f} μ_h(J) on average",
          m.alpha(), m.alpha_err(), m.value(0), m.error(0), m.value(1), m.error(1), m.value(2),
          m.error(2), m.mu.chi2_red, m.viscous.size(), fits.split.contact_chi2_per_point,
          fits.split.lubrication_share_of_hydrodynamic);
      if (std::isfinite(m.alpha())) out.attribute("/steady", "fitted_alpha", m.alpha());
    }
    out.flush();
  }
  if (sweep && any_wet) {
    // For comparison: the one-parameter α on Boyer's law in K (kind/mixed_number_fit.hpp), biased
    // when the DEM's viscous constants differ from Boyer's (docs/dem_dataset.md).
    std::vector<double> j, i, mu, mu_err;
    for (const auto& r : results) {
      j.push_back(get(r, "J"));
      i.push_back(get(r, "I"));
      mu.push_back(get(r, "mu"));
      mu_err.push_back(get(r, "mu_err"));
    }
    const MixedNumberFit fit = fit_trulsson_alpha(j, i, mu, mu_err);
    if (fit.points >= 2) {
      ctx.summary.set("fit.alpha_boyer", fit.alpha);
      ctx.summary.set("fit.alpha_boyer_rms", fit.rms);
      ctx.summary.set("fit.alpha_boyer_chi2_per_dof", fit.chi2_per_dof);
      ctx.summary.set("fit.alpha_points", fit.points);
      ctx.log->info(
          "K = J + α I² on Boyer's law in K (only α free): α = {:.4g} (RMS {:.3g}, χ²/dof {:.3g}, "
          "{} points)",
          fit.alpha, fit.rms, fit.chi2_per_dof, fit.points);
    }
  }
  transient.finish(ctx, swept);
  if (code == core::exit_ok || failed < double(results.size())) ctx.plot("plot_dem.py");
  return code;
}

}  // namespace

void register_dem_kinds(core::KindRegistry& registry) {
  core::KindEntry entry{"dem",
                        "",
                        "Lees-Edwards periodic simple shear of dry or immersed spheres (LIGGGHTS)",
                        shear_schema(),
                        check_shear,
                        run_shear,
                        "cases/dem/dry_point.yaml"};
  entry.distributes_conditions = true;
  entry.report = dem_report_section;
  entry.check_inputs = check_preparation_inputs;
  entry.convergence_study = "analysis/dem_study.py";  // docs/speed-accuracy.md, section DEM
  registry.add(std::move(entry));
  register_prepare_kind(registry);
}

}  // namespace granflow::dem
