#include "continuum/rev/rev_kind.hpp"

#include <fmt/format.h>

#include <cmath>
#include <optional>

#include "continuum/rev/rev_columns.hpp"
#include "continuum/rev/simple_shear.hpp"
#include "continuum/sections/model_sections.hpp"
#include "core/sweep_scheduler.hpp"

namespace granflow::rev {

core::Schema simple_shear_schema() {
  core::Schema s = core::kind_header(
      "rev", "simple_shear",
      "Homogeneous simple shear of one material point at imposed shear rate, at constant volume "
      "or constant normal stress, integrated to steady state (docs/model/closures.md and "
      "multi_regime.md). With force_chains "
      "enabled the skeleton σ_FC works in parallel: all terms (at constant normal stress by "
      "mixed control of ε̇_yy, docs/model/multi_regime.md §4.1; initial.effective_pressure is then "
      "replaced by p - p_COL(ν0, T0)).");
  s.add(continuum::material_section());
  s.add(continuum::force_chains_section());
  s.add(continuum::collisional_section());
  s.add(continuum::liquid_section());
  auto& loading = s.section("loading", "imposed shear and volume/normal-stress control");
  loading
      .choice("control", {"constant_volume", "constant_pressure"},
              "constant_volume: e imposed; constant_pressure: p on the grains imposed, e evolves")
      .required();
  loading.number("shear_rate", "1/s", "imposed shear rate γ̇")
      .required()
      .greater_than(0)
      .sweepable();
  loading.number("void_ratio", "", "imposed void ratio e (constant_volume) or initial e")
      .greater_than(0)
      .sweepable();
  loading.number("normal_stress", "Pa", "imposed normal stress p on the grains (constant_pressure)")
      .greater_than(0)
      .sweepable();
  auto& initial = s.section("initial", "initial state");
  initial.number("granular_temperature", "m^2/s^2", "T at t = 0")
      .default_value("1.0e-6")
      .at_least(0);
  initial.number("effective_pressure", "Pa", "isotropic σ_FC = p'0 I at t = 0 (force chains on)")
      .default_value("50.0e3")
      .greater_than(0)
      .sweepable();
  initial.number("overconsolidation", "", "r_c0 / (√3 p'0) (force chains on)")
      .default_value("1")
      .at_least(1);
  auto& integration = s.section("integration", "accuracy controls of the time integration");
  integration.number("time_step_factor", "", "Δt = factor × min(1/γ̇, relaxation time of T)")
      .default_value("0.5")
      .greater_than(0);
  integration
      .number("steady_tolerance", "", "steady when T and ν change less than this per unit strain")
      .default_value("1.0e-10")
      .greater_than(0);
  integration.number("max_strain", "", "give up (not steady) beyond this shear strain")
      .default_value("1.0e4")
      .greater_than(0);
  integration.integer("max_steps", "give up beyond this number of steps")
      .default_value("1000000")
      .greater_than(0);
  integration
      .number("strain_increment", "", "largest shear strain increment per step with force chains")
      .default_value("1.0e-3")
      .greater_than(0)
      .at_most(0.05);
  return s;
}

namespace {

void check_simple_shear(const core::Case& c) {
  const auto settings = continuum::read_multi_regime_settings(c);
  const std::string control = c.string("loading.control");
  if (control == "constant_volume") {
    if (!c.has("loading.void_ratio"))
      c.fail("loading.void_ratio",
             "missing required key for constant_volume; expected a void ratio > 0");
    const double nu = 1.0 / (1.0 + c.number("loading.void_ratio"));
    if (settings.collisional &&
        nu >= model::maximum_solid_fraction(settings.collisional_parameters))
      c.fail("loading.void_ratio",
             fmt::format(
                 "solid fraction 1/(1+e) = {:.6g} is at or beyond the jamming fraction {:.6g}; "
                 "expected e > {:.6g}",
                 nu, model::maximum_solid_fraction(settings.collisional_parameters),
                 1.0 / model::maximum_solid_fraction(settings.collisional_parameters) - 1.0));
    if (settings.liquid && nu >= settings.liquid_parameters.maximum_packing &&
        settings.liquid_parameters.mixture_viscosity != model::MixtureViscosityKind::einstein)
      c.fail(
          "loading.void_ratio",
          fmt::format("solid fraction {:.6g} is at or beyond liquid.maximum_packing {:.6g} where "
                      "η(ν) diverges",
                      nu, settings.liquid_parameters.maximum_packing));
  } else {
    if (!c.has("loading.normal_stress"))
      c.fail("loading.normal_stress",
             "missing required key for constant_pressure; expected p > 0 [Pa]");
    if (!settings.collisional)
      c.fail("collisional.enabled", "constant_pressure needs the collisional term (it carries p)");
    // With force chains e evolves from loading.void_ratio (default 0.8): ν0 below jamming.
    const double nu0 =
        1.0 / (1.0 + (c.has("loading.void_ratio") ? c.number("loading.void_ratio") : 0.8));
    if (settings.force_chains &&
        nu0 >= model::maximum_solid_fraction(settings.collisional_parameters))
      c.fail(
          "loading.void_ratio",
          fmt::format("initial solid fraction 1/(1+e) = {:.6g} is at or beyond the jamming "
                      "fraction {:.6g}; expected e > {:.6g}",
                      nu0, model::maximum_solid_fraction(settings.collisional_parameters),
                      1.0 / model::maximum_solid_fraction(settings.collisional_parameters) - 1.0));
    // Dry kinetic theory has a dense steady state only below I_max (with liquid, Λ lowers T and
    // the bound moves, with force chains the skeleton can carry p: then detected at run time).
    if (!settings.liquid && !settings.force_chains &&
        settings.collisional_parameters.correlation_length ==
            model::CorrelationLengthKind::diameter) {
      const auto bound = maximum_steady_inertial_number(settings.collisional_parameters);
      const double I = c.number("loading.shear_rate") * settings.collisional_parameters.diameter /
                       std::sqrt(c.number("loading.normal_stress") /
                                 settings.collisional_parameters.particle_density);
      if (I >= bound.inertial_number)
        c.fail(
            "loading.shear_rate",
            fmt::format("inertial number I = γ̇ d / sqrt(p/ρ_p) = {:.4g} has no steady dense state "
                        "in kinetic theory with L = d; expected I < I_max = {:.4g} (reached at "
                        "ν = {:.4g}), i.e. γ̇ < {:.4g} 1/s",
                        I, bound.inertial_number, bound.solid_fraction,
                        c.number("loading.shear_rate") * bound.inertial_number / I));
    }
    // Under constant p the grains may compact up to the jamming fraction: η(ν) must stay finite.
    if (settings.liquid &&
        settings.liquid_parameters.mixture_viscosity != model::MixtureViscosityKind::einstein &&
        settings.liquid_parameters.maximum_packing <=
            model::maximum_solid_fraction(settings.collisional_parameters))
      c.fail("liquid.maximum_packing",
             fmt::format("η(ν) diverges at ν_m = {:g}, below the jamming fraction {:g} the "
                         "grains can reach under constant pressure; expected ν_m > "
                         "collisional.jamming_fraction",
                         settings.liquid_parameters.maximum_packing,
                         model::maximum_solid_fraction(settings.collisional_parameters)));
  }
}

SimpleShearControl read_control(const core::Case& c) {
  SimpleShearControl control;
  control.control = c.string("loading.control") == "constant_volume"
                        ? ShearControl::constant_volume
                        : ShearControl::constant_pressure;
  control.shear_rate = c.number("loading.shear_rate");
  if (c.has("loading.void_ratio")) control.void_ratio = c.number("loading.void_ratio");
  if (c.has("loading.normal_stress")) control.normal_stress = c.number("loading.normal_stress");
  control.initial_temperature = c.number("initial.granular_temperature");
  control.time_step_factor = c.number("integration.time_step_factor");
  control.steady_tolerance = c.number("integration.steady_tolerance");
  control.max_strain = c.number("integration.max_strain");
  control.max_steps = c.integer("integration.max_steps");
  control.effective_pressure = c.number("initial.effective_pressure");
  control.overconsolidation = c.number("initial.overconsolidation");
  control.strain_increment = c.number("integration.strain_increment");
  return control;
}

void write_series(core::ResultFile& out, const std::string& group, const SimpleShearSeries& s) {
  for (const RevSeriesColumn& c : rev_columns::simple_shear_series)
    out.write(group, c.column, s.*c.values);
}

int run_simple_shear_case(core::RunContext& ctx) {
  const auto conditions = ctx.run_case.expand_sweep();
  const bool sweep = ctx.run_case.is_sweep();
  std::vector<SimpleShearRow> rows;
  long total_steps = 0;
  double min_dt = INFINITY, max_dt = 0, max_explicit_ratio = 0;
  core::Progress progress(ctx.log, "conditions", static_cast<double>(conditions.size()));

  // One condition: the integration (any rank, core/sweep_scheduler.hpp), then its series, row,
  // summary keys and log lines (rank 0, in condition order: the files of a serial run).
  auto label_of = [&](std::size_t n) {
    std::string label = sweep ? fmt::format("condition {}", n) : std::string("simple shear");
    for (const auto& [key, value] : conditions[n].condition())
      label += fmt::format(" {}={:g}", key, value);
    return label;
  };
  auto compute = [&](const core::ConditionContext& cc) {
    const core::Case& c = conditions[cc.index];
    const continuum::MultiRegimePoint point(continuum::read_multi_regime_settings(c));
    const SimpleShearControl control = read_control(c);
    const std::string label = label_of(cc.index);
    cc.log->info("{}: {} at γ̇ = {:g} 1/s", label, c.string("loading.control"), control.shear_rate);
    core::Progress strain_progress(cc.log, label + " strain", control.max_strain);
    SimpleShearResult r;
    std::optional<core::NumericalFailure> failure;
    try {
      run_simple_shear(point, control, r, [&](double strain) { strain_progress.update(strain); });
    } catch (const core::NumericalFailure& e) {
      failure = e;  // what ran is kept (absorb writes it), then the failure stops the sweep
    }
    core::Packer packed;
    const auto& ts = r.series;
    // every series of the column table (rev_columns.hpp), in its order
    for (const auto& column : rev_columns::simple_shear_series) packed.numbers(ts.*column.values);
    const auto& st = r.steady;
    packed.integer(st.reached ? 1 : 0);
    for (double v : {st.strain,
                     st.void_ratio,
                     st.solid_fraction,
                     st.granular_temperature,
                     st.pressure,
                     st.effective_pressure,
                     st.force_chain_shear_stress,
                     st.locus_size,
                     st.shear_stress,
                     st.collisional_shear_stress,
                     st.liquid_shear_stress,
                     st.friction,
                     st.inertial_number,
                     st.viscous_number,
                     st.normal_stress,
                     st.force_chain_normal_stress,
                     st.collisional_normal_stress,
                     st.liquid_normal_stress,
                     st.share_tau_force_chains,
                     st.share_tau_collisional,
                     st.share_tau_liquid,
                     st.share_normal_force_chains,
                     st.share_normal_collisional,
                     st.share_normal_liquid,
                     r.min_time_step,
                     r.max_time_step,
                     r.max_explicit_ratio,
                     r.max_normal_stress_residual})
      packed.number(v);
    packed.integer(r.steps);
    packed.integer(r.solver_evaluations);
    packed.integer(st.fluidized ? 1 : 0);
    packed.integer(failure ? 1 : 0);
    if (failure) core::pack_numerical_failure(packed, *failure);
    return packed.take();
  };
  auto absorb = [&](std::size_t n, const std::string& bytes) {
    const core::Case& c = conditions[n];
    const auto settings = continuum::read_multi_regime_settings(c);
    const SimpleShearControl control = read_control(c);
    const std::string label = label_of(n);
    core::Unpacker packed(bytes);
    SimpleShearResult r;
    auto& ts = r.series;
    for (const auto& column : rev_columns::simple_shear_series)
      ts.*column.values = packed.numbers();
    auto& s = r.steady;
    s.reached = packed.integer() != 0;
    for (double* v : {&s.strain,
                      &s.void_ratio,
                      &s.solid_fraction,
                      &s.granular_temperature,
                      &s.pressure,
                      &s.effective_pressure,
                      &s.force_chain_shear_stress,
                      &s.locus_size,
                      &s.shear_stress,
                      &s.collisional_shear_stress,
                      &s.liquid_shear_stress,
                      &s.friction,
                      &s.inertial_number,
                      &s.viscous_number,
                      &s.normal_stress,
                      &s.force_chain_normal_stress,
                      &s.collisional_normal_stress,
                      &s.liquid_normal_stress,
                      &s.share_tau_force_chains,
                      &s.share_tau_collisional,
                      &s.share_tau_liquid,
                      &s.share_normal_force_chains,
                      &s.share_normal_collisional,
                      &s.share_normal_liquid,
                      &r.min_time_step,
                      &r.max_time_step,
                      &r.max_explicit_ratio,
                      &r.max_normal_stress_residual})
      *v = packed.number();
    r.steps = static_cast<long>(packed.integer());
    r.solver_evaluations = static_cast<long>(packed.integer());
    s.fluidized = packed.integer() != 0;
    const std::string group = sweep ? fmt::format("/conditions/{}", n) : std::string("/series");
    write_series(ctx.result, sweep ? group + "/series" : group, r.series);
    // A failed integration: what ran is written (above), then it stops the run as it always did.
    if (packed.integer() != 0) core::throw_numerical_failure(packed);
    if (sweep)
      for (const auto& [key, value] : c.condition()) ctx.result.attribute(group, key, value);
    ctx.result.flush();
    if (!s.reached)
      ctx.log->warn("{}: no steady state within strain {:g} / {} steps; the last state is reported",
                    label, s.strain, r.steps);
    const double alpha = c.number("liquid.trulsson_alpha");
    const double K = s.viscous_number + alpha * s.inertial_number * s.inertial_number;
    const double d_rate = c.number("material.diameter") * control.shear_rate;
    rows.push_back({control.shear_rate, s.void_ratio, s.solid_fraction, s.granular_temperature,
                    s.granular_temperature / (d_rate * d_rate), s.pressure, s.normal_stress,
                    s.shear_stress, s.collisional_shear_stress, s.liquid_shear_stress, s.friction,
                    s.inertial_number, s.viscous_number, K, s.strain, s.reached ? 1L : 0L});
    ctx.log->info(
        "{}: steady after strain {:.4g} ({} steps): e = {:.6g}, T = {:.6g} m²/s², "
        "p = {:.6g} Pa, τ = {:.6g} Pa, μ = {:.6g}, I = {:.6g}{}",
        label, s.strain, r.steps, s.void_ratio, s.granular_temperature, s.pressure, s.shear_stress,
        s.friction, s.inertial_number,
        settings.liquid ? fmt::format(", J = {:.6g}", s.viscous_number) : "");
    const std::string suffix = sweep ? fmt::format(".{}", n) : "";
    auto& sum = ctx.summary;
    sum.set("steady.mu" + suffix, s.friction);
    sum.set("steady.e" + suffix, s.void_ratio);
    sum.set("steady.phi" + suffix, s.solid_fraction);
    sum.set("steady.T" + suffix, s.granular_temperature);
    sum.set("steady.p" + suffix, s.pressure);
    sum.set("steady.tau" + suffix, s.shear_stress);
    sum.set("steady.I" + suffix, s.inertial_number);
    sum.set("steady.start_strain" + suffix, s.strain);
    sum.set("steady.reached" + suffix, s.reached ? 1 : 0);
    // Shares of τ and σ_yy carried by each term (each triple sums to 1).
    sum.set("steady.sigma_yy" + suffix, s.normal_stress);
    sum.set("steady.share.tau_fc" + suffix, s.share_tau_force_chains);
    sum.set("steady.share.tau_col" + suffix, s.share_tau_collisional);
    sum.set("steady.share.tau_liq" + suffix, s.share_tau_liquid);
    sum.set("steady.share.sigma_yy_fc" + suffix, s.share_normal_force_chains);
    sum.set("steady.share.sigma_yy_col" + suffix, s.share_normal_collisional);
    sum.set("steady.share.sigma_yy_liq" + suffix, s.share_normal_liquid);
    ctx.log->info(
        "{}: shares of τ: force chains {:.4f}, collisional {:.4f}, liquid {:.4f}; of σ_yy = "
        "{:.6g} Pa: force chains {:.4f}, collisional {:.4f}, liquid {:.4f}",
        label, s.share_tau_force_chains, s.share_tau_collisional, s.share_tau_liquid,
        s.normal_stress, s.share_normal_force_chains, s.share_normal_collisional,
        s.share_normal_liquid);
    if (settings.force_chains) {
      sum.set("steady.tau_fc" + suffix, s.force_chain_shear_stress);
      sum.set("steady.p_eff" + suffix, s.effective_pressure);
      sum.set("steady.sigma_yy_fc" + suffix, s.force_chain_normal_stress);
      sum.set("steady.fluidized" + suffix, s.fluidized ? 1 : 0);
      sum.set("final.r_c" + suffix, s.locus_size);
    }
    if (settings.force_chains && control.control == ShearControl::constant_pressure) {
      sum.set("accuracy.normal_stress_residual_max" + suffix, r.max_normal_stress_residual);
      sum.set("cost.solver_evaluations" + suffix, static_cast<double>(r.solver_evaluations));
      ctx.log->info(
          "{}: mixed control: max |σ_yy - p|/p = {:.3g} after a step, {} trial advances "
          "({:.3g} per step)",
          label, r.max_normal_stress_residual, r.solver_evaluations,
          static_cast<double>(r.solver_evaluations) / std::max(r.steps, 1L));
    }
    if (settings.liquid) {
      sum.set("steady.J" + suffix, s.viscous_number);
      sum.set("steady.K" + suffix, K);
    }
    // The closed form of docs/model/closures.md (no liquid, L = d): T = (f2/f3) d² γ̇², μ = sqrt(f2
    // f3)/f1.
    if (settings.collisional && !settings.liquid && !settings.force_chains &&
        settings.collisional_parameters.correlation_length ==
            model::CorrelationLengthKind::diameter) {
      const auto& p = settings.collisional_parameters;
      const auto k = model::collisional_coefficients(p, s.solid_fraction);
      const double T_closed =
          k.f2 / k.f3 * p.diameter * p.diameter * control.shear_rate * control.shear_rate;
      sum.set("closed_form.T" + suffix, T_closed);
      sum.set("closed_form.mu" + suffix, std::sqrt(k.f2 * k.f3) / k.f1);
      sum.set("closed_form.I" + suffix, 1.0 / std::sqrt(k.f1 * k.f2 / k.f3));
      sum.set("closed_form.T_rel_err" + suffix, std::abs(s.granular_temperature / T_closed - 1.0));
    }
    total_steps += r.steps;
    min_dt = std::min(min_dt, r.min_time_step);
    max_dt = std::max(max_dt, r.max_time_step);
    max_explicit_ratio = std::max(max_explicit_ratio, r.max_explicit_ratio);
    progress.update(static_cast<double>(n + 1));
  };
  if (!core::run_conditions(ctx, conditions.size(), compute, absorb))
    return core::exit_ok;  // another rank than 0: rank 0 writes the tables and plots

  // Steady table (one row per condition; rev_columns.hpp).
  auto& out = ctx.result;
  std::vector<std::string> column_names;
  for (const RevSteadyColumn& col : rev_columns::simple_shear_steady) {
    if (col.flag) {
      std::vector<long> v;
      for (const auto& row : rows) v.push_back(row.*col.flag);
      out.write("/steady", col.column, v);
    } else {
      std::vector<double> v;
      for (const auto& row : rows) v.push_back(row.*col.value);
      out.write("/steady", col.column, v);
    }
    column_names.push_back(col.column.name);
  }
  const auto& c0 = ctx.run_case;
  out.attribute("/steady", "columns", column_names);
  std::vector<std::string> sweep_keys;
  if (!conditions.empty())
    for (const auto& [key, value] : conditions.front().condition()) sweep_keys.push_back(key);
  out.attribute("/steady", "sweep_keys", sweep_keys);
  out.attribute("/steady", "diameter", c0.number("material.diameter"));
  out.attribute("/steady", "particle_density", c0.number("material.particle_density"));
  out.attribute("/steady", "liquid_enabled", c0.boolean("liquid.enabled") ? 1L : 0L);
  out.attribute("/steady", core::columns::liquid_viscosity.name, c0.number("liquid.viscosity"));

  const double wall = ctx.wall_seconds();
  ctx.summary.set("cost.steps", static_cast<double>(total_steps));
  ctx.summary.set("cost.updates_per_s", total_steps / std::max(wall, 1e-9));
  ctx.summary.set("accuracy.time_step_min", min_dt);
  ctx.summary.set("accuracy.time_step_max", max_dt);
  ctx.summary.set("accuracy.time_step_factor", c0.number("integration.time_step_factor"));
  ctx.summary.set("accuracy.steady_tolerance", c0.number("integration.steady_tolerance"));
  ctx.summary.set("accuracy.max_dt_over_explicit_limit", max_explicit_ratio);
  if (sweep) ctx.summary.set("sweep.count", static_cast<double>(conditions.size()));
  ctx.log->info(
      "cost: {} steps in {:.3f} s ({:.3g} point updates/s); accuracy: Δt in [{:.3g}, {:.3g}] s "
      "(factor {:g}, up to {:.3g}× the explicit Euler limit of the T equation), steady "
      "tolerance {:g} per unit strain",
      total_steps, wall, total_steps / std::max(wall, 1e-9), min_dt, max_dt,
      c0.number("integration.time_step_factor"), max_explicit_ratio,
      c0.number("integration.steady_tolerance"));
  ctx.plot("plot_rev.py");
  return core::exit_ok;
}

}  // namespace

void register_rev_kinds(core::KindRegistry& registry) {
  core::KindEntry entry{
      "rev",
      "simple_shear",
      "steady homogeneous simple shear of a material point (collisional + liquid)",
      simple_shear_schema(),
      check_simple_shear,
      run_simple_shear_case,
      "cases/rev/simple_shear_dry.yaml"};
  entry.distributes_conditions = true;
  registry.add(std::move(entry));
  register_element_test_kinds(registry);
}

}  // namespace granflow::rev
