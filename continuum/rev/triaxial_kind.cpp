// `kind: rev` element tests with all terms: `test: triaxial` (drained / undrained triaxial
// compression at imposed ε̇_d, optional reconsolidation stage) and `test: isotropic_compression`.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "continuum/sections/model_sections.hpp"
#include "continuum/rev/element_test.hpp"
#include "continuum/rev/rev_kind.hpp"
#include "core/interrupt.hpp"
#include "core/result_columns.hpp"

namespace granflow::rev {

namespace {

void add_model_sections(core::Schema& s) {
  s.add(continuum::material_section());
  s.add(continuum::force_chains_section());
  s.add(continuum::collisional_section());
  s.add(continuum::liquid_section());
}

void add_initial_section(core::Schema& s) {
  auto& initial = s.section("initial", "isotropic initial state (compression positive)");
  initial.number("void_ratio", "", "initial void ratio e0").required().greater_than(0).sweepable();
  initial.number("effective_pressure", "Pa", "initial effective pressure p'0 (σ_FC = p'0 I)")
      .required()
      .greater_than(0)
      .sweepable();
  initial.number("overconsolidation", "", "r_c0 / (√3 p'0): 1 = normally consolidated")
      .default_value("1")
      .at_least(1);
  initial.number("pore_pressure", "Pa", "initial pore pressure u_w0 (= back pressure)")
      .default_value("0")
      .sweepable();
  initial.number("granular_temperature", "m^2/s^2", "T at t = 0").default_value("0").at_least(0);
}

}  // namespace

core::Schema triaxial_schema() {
  core::Schema s = core::kind_header(
      "rev", "triaxial",
      "Axisymmetric triaxial compression of one material point with all terms (σ_FC + σ_COL + "
      "σ_L) at imposed deviatoric strain rate and constant cell (total radial) stress, drained or "
      "undrained (liquid of bulk modulus K_w), with an optional reconsolidation stage "
      "(docs/model/multi_regime.md).");
  add_model_sections(s);
  add_initial_section(s);
  auto& loading = s.section("loading", "shearing stage");
  loading
      .choice("drainage", {"drained", "undrained"},
              "drained: u_w = u_w0; undrained: Δu_w = (K_w/n) Δε_v (mixture volume changes only "
              "by the liquid's compression)")
      .required();
  loading.number("deviatoric_strain_rate", "1/s", "imposed ε̇_d = (2/3)(ε̇_a - ε̇_r)")
      .required()
      .greater_than(0)
      .sweepable();
  loading.number("final_deviatoric_strain", "", "stop the shearing stage at this ε_d")
      .required()
      .greater_than(0)
      .at_most(2);
  loading.integer("steps", "equal steps of the shearing stage (Δε_d = final/steps)")
      .default_value("2000")
      .at_least(10);
  loading
      .number("steady_tolerance", "1",
              "run on past final_deviatoric_strain (same Δε_d) until the residual is steady: "
              "the drifts d ln T/dε_d and d ln q/dε_d over the residual window (the last 10 % of "
              "`steps`) both within ± this; 0: stop at final_deviatoric_strain (the residual may "
              "be a transient)")
      .default_value("0.01")
      .at_least(0);
  loading
      .number("max_deviatoric_strain", "",
              "running on until steady stops here at the latest (summary residual.steady = 0 and "
              "a warning), at most 100 × final_deviatoric_strain; 0: 10 × final_deviatoric_strain")
      .default_value("0")
      .at_least(0)
      .at_most(20);
  auto& recon = s.section("reconsolidation",
                          "optional second stage: the shear rate drops and the sample drains "
                          "towards u_w0 through a drainage length (lumped Darcy outflow)");
  recon.boolean("enabled", "run the reconsolidation stage").default_value("false");
  recon.number("deviatoric_strain_rate", "1/s", "ε̇_d during the stage")
      .default_value("0")
      .at_least(0);
  recon.number("duration", "s", "length of the stage").default_value("1").greater_than(0);
  recon.integer("steps", "time steps of the stage").default_value("2000").at_least(10);
  recon
      .number("first_time_step", "s",
              "first time step; the steps grow geometrically to fill the duration (0: equal "
              "steps)")
      .default_value("1.0e-6")
      .at_least(0);
  recon.number("drainage_length", "m", "drainage length H: outflow κ/(η0 H²) (u_w - u_w0)")
      .default_value("0.05")
      .greater_than(0);
  auto& integration = s.section("integration", "accuracy controls");
  integration.number("stress_tolerance", "", "|σ_r - σ_cell| accepted, relative to σ_cell")
      .default_value("1.0e-9")
      .greater_than(0)
      .less_than(1e-2);
  return s;
}

core::Schema isotropic_compression_schema() {
  core::Schema s = core::kind_header(
      "rev", "isotropic_compression",
      "Drained isotropic compression of one material point at imposed volumetric strain rate "
      "(all terms; u_w constant).");
  add_model_sections(s);
  add_initial_section(s);
  auto& loading = s.section("loading", "imposed volumetric strain");
  loading.number("volumetric_strain_rate", "1/s", "ε̇_v (> 0 compaction)")
      .required()
      .greater_than(0);
  loading.number("final_volumetric_strain", "", "stop at this ε_v")
      .required()
      .greater_than(0)
      .less_than(0.5);
  loading.integer("steps", "equal steps").default_value("200").at_least(1);
  return s;
}

namespace {

void check_common(const core::Case& c) {
  const auto settings = continuum::read_multi_regime_settings(c);
  const double nu = 1.0 / (1.0 + c.number("initial.void_ratio"));
  if (settings.collisional && nu >= model::maximum_solid_fraction(settings.collisional_parameters))
    c.fail(
        "initial.void_ratio",
        fmt::format("solid fraction 1/(1+e0) = {:.6g} is at or beyond collisional."
                    "jamming_fraction {:.6g} where g0 diverges; expected e0 > {:.6g} or a larger "
                    "jamming fraction",
                    nu, settings.collisional_parameters.jamming_fraction,
                    1.0 / settings.collisional_parameters.jamming_fraction - 1.0));
  if (settings.liquid && nu >= model::maximum_mixture_solid_fraction(settings.liquid_parameters))
    c.fail("initial.void_ratio",
           fmt::format("solid fraction {:.6g} is at or beyond liquid.maximum_packing {:.6g} where "
                       "η(ν) diverges",
                       nu, settings.liquid_parameters.maximum_packing));
  if (!settings.force_chains)
    c.fail("force_chains.enabled",
           "element tests start from a skeleton carrying p'0: expected "
           "force_chains.enabled: true");
}

void check_triaxial(const core::Case& c) {
  check_common(c);
  const auto settings = continuum::read_multi_regime_settings(c);
  if (c.string("loading.drainage") == "undrained" && !settings.liquid)
    c.fail("loading.drainage", "undrained needs the liquid (liquid.enabled: true: K_w, η)");
  const double max_strain = c.number("loading.max_deviatoric_strain");
  const double final_strain = c.number("loading.final_deviatoric_strain");
  if (max_strain > 0 && max_strain < final_strain)
    c.fail("loading.max_deviatoric_strain",
           fmt::format("{:g} is below loading.final_deviatoric_strain {:g}: expected 0 or a "
                       "strain at least as large",
                       max_strain, final_strain));
  // the series keeps every step: running on is bounded to 100 × the nominal stage
  if (max_strain > 100 * final_strain)
    c.fail("loading.max_deviatoric_strain",
           fmt::format("{:g} is more than 100 × loading.final_deviatoric_strain {:g} (every step "
                       "is kept in the series): expected at most {:g}",
                       max_strain, final_strain, 100 * final_strain));
  if (c.boolean("reconsolidation.enabled") && !settings.liquid)
    c.fail("reconsolidation.enabled", "reconsolidation drains the liquid: liquid.enabled: true");
}

}  // namespace

TriaxialControl read_triaxial_control(const core::Case& c) {
  TriaxialControl t;
  t.void_ratio = c.number("initial.void_ratio");
  t.effective_pressure = c.number("initial.effective_pressure");
  t.overconsolidation = c.number("initial.overconsolidation");
  t.pore_pressure = c.number("initial.pore_pressure");
  t.initial_temperature = c.number("initial.granular_temperature");
  t.stress_tolerance = c.number("integration.stress_tolerance");
  TriaxialStage shear;
  shear.drainage =
      c.string("loading.drainage") == "drained" ? Drainage::drained : Drainage::undrained;
  shear.deviatoric_strain_rate = c.number("loading.deviatoric_strain_rate");
  shear.duration = c.number("loading.final_deviatoric_strain") / shear.deviatoric_strain_rate;
  shear.steps = static_cast<int>(c.integer("loading.steps"));
  shear.steady_tolerance = c.number("loading.steady_tolerance");
  const double final_strain = c.number("loading.final_deviatoric_strain");
  const double max_strain = c.number("loading.max_deviatoric_strain") > 0
                                ? c.number("loading.max_deviatoric_strain")
                                : 10.0 * final_strain;
  shear.max_steps = static_cast<int>(std::ceil(shear.steps * max_strain / final_strain - 1e-9));
  t.stages.push_back(shear);
  if (c.boolean("reconsolidation.enabled")) {
    TriaxialStage recon;
    recon.drainage = Drainage::consolidating;
    recon.deviatoric_strain_rate = c.number("reconsolidation.deviatoric_strain_rate");
    recon.duration = c.number("reconsolidation.duration");
    recon.steps = static_cast<int>(c.integer("reconsolidation.steps"));
    recon.drainage_length = c.number("reconsolidation.drainage_length");
    recon.first_time_step = c.number("reconsolidation.first_time_step");
    t.stages.push_back(recon);
  }
  return t;
}

namespace {

void write_series(core::ResultFile& out, const std::string& g, const ElementSeries& s) {
  out.write(g + "/time", s.time, "s", "time");
  out.write(g + "/deviatoric_strain", s.deviatoric_strain, "1", "ε_d = (2/3)(ε_a - ε_r)");
  out.write(g + "/volumetric_strain", s.volumetric_strain, "1", "ε_v = ε_a + 2ε_r (compaction +)");
  out.write(g + "/axial_strain", s.axial_strain, "1", "ε_a");
  out.write(g + "/q", s.q, "Pa", "deviator stress q = σ_a - σ_r (total)");
  out.write(g + "/q_force_chain", s.q_force_chain, "Pa", "q of σ_FC");
  out.write(g + "/q_collisional", s.q_collisional, "Pa", "q of σ_COL");
  out.write(g + "/q_liquid", s.q_liquid, "Pa", "q of σ_L");
  out.write(g, core::columns::described(core::columns::mean_stress, "total mean stress p = tr(σ)/3"),
            s.mean_stress);
  out.write(g + "/effective_pressure", s.effective_pressure, "Pa", "p' = p_FC");
  out.write(g + "/collisional_pressure", s.collisional_pressure, "Pa", "p_COL");
  out.write(g + "/pore_pressure", s.pore_pressure, "Pa", "u_w");
  out.write(g, core::columns::granular_temperature, s.granular_temperature);
  out.write(g, core::columns::locus_size, s.locus_size);
  out.write(g, core::columns::void_ratio, s.void_ratio);
  // Flags as integers.
  auto integers = [](const std::vector<double>& v) { return std::vector<long>(v.begin(), v.end()); };
  out.write(g + "/fluidized", integers(s.fluidized), "1", "1 when σ_FC = 0 (r_c = 0)");
  out.write(g + "/yield_value", s.yield_value, "1",
            "f at the end of the step (<= FTOL when solid)");
  out.write(g + "/stage", integers(s.stage), "1", "0 = shearing, 1 = reconsolidation");
  out.write(g + "/collisional_dissipation", s.collisional_dissipation, "W/m^3",
            "Γ, collisional dissipation of T");
  out.write(g + "/liquid_dissipation", s.liquid_dissipation, "W/m^3",
            "Λ, dissipation of T by the liquid");
}

// Mean of v over the `window` entries before `end` (the residual window: the last 10 % of the
// shearing stage's nominal steps, ending where the stage ended).
double tail_mean(const std::vector<double>& v, std::size_t window, std::size_t end) {
  const std::size_t first = end - window;
  double sum = 0;
  for (std::size_t i = first; i < end; ++i) sum += v[i];
  return sum / static_cast<double>(end - first);
}

// Least-squares slope of log y against log x.
double log_slope(const std::vector<double>& x, const std::vector<double>& y) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double lx = std::log(x[i]), ly = std::log(std::abs(y[i]));
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

int run_triaxial_case(core::RunContext& ctx) {
  const auto conditions = ctx.run_case.expand_sweep();
  const bool sweep = ctx.run_case.is_sweep();
  core::Progress progress(ctx.log, "conditions", static_cast<double>(conditions.size()));
  std::vector<double> rates, residual_q, residual_q_col, residual_q_liq, lambda_share, steady;
  long total_steps = 0, total_evaluations = 0;
  double max_residual = 0;
  for (std::size_t n = 0; n < conditions.size() && !core::interrupted(); ++n) {
    const core::Case& c = conditions[n];
    const continuum::MultiRegimePoint point(continuum::read_multi_regime_settings(c));
    const TriaxialControl control = read_triaxial_control(c);
    std::string label = sweep ? fmt::format("condition {}", n) : std::string("triaxial");
    for (const auto& [key, value] : c.condition()) label += fmt::format(" {}={:g}", key, value);
    const std::string group = sweep ? fmt::format("/conditions/{}/series", n) : "/series";
    ctx.log->info("{}: {} triaxial, e0 = {:g}, p'0 = {:g} Pa, u_w0 = {:g} Pa, ε̇_d = {:g} 1/s",
                  label, c.string("loading.drainage"), control.void_ratio,
                  control.effective_pressure, control.pore_pressure,
                  control.stages[0].deviatoric_strain_rate);
    core::Progress time_progress(ctx.log, label + " time fraction", 1.0);
    ElementResult r;
    try {
      run_triaxial(point, control, r, [&](double f) { time_progress.update(f); });
    } catch (const core::NumericalFailure&) {
      write_series(ctx.result, group, r.series);
      throw;
    }
    write_series(ctx.result, group, r.series);
    if (sweep)
      for (const auto& [key, value] : c.condition())
        ctx.result.attribute(fmt::format("/conditions/{}", n), key, value);
    ctx.result.flush();

    const auto& s = r.series;
    // The shearing stage ends where it became steady (or at its nominal/maximum strain); the
    // residual is the mean over its last 10 % of nominal steps.
    const StageEnd shear = r.stage_ends.empty() ? StageEnd{} : r.stage_ends[0];
    const std::size_t shear_end = shear.last + 1;
    const std::size_t window =
        std::clamp<std::size_t>(static_cast<std::size_t>(control.stages[0].steps / 10), 1,
                                std::max<std::size_t>(1, shear.last));
    const std::size_t last = s.time.size() - 1;
    const std::string suffix = sweep ? fmt::format(".{}", n) : "";
    auto& sum = ctx.summary;
    if (r.liquefaction_strain >= 0) sum.set("liquefaction.eps_d" + suffix, r.liquefaction_strain);
    const double q_res = tail_mean(s.q, window, shear_end);
    sum.set("residual.q" + suffix, q_res);
    sum.set("residual.q_fc" + suffix, tail_mean(s.q_force_chain, window, shear_end));
    sum.set("residual.q_col" + suffix, tail_mean(s.q_collisional, window, shear_end));
    sum.set("residual.q_liq" + suffix, tail_mean(s.q_liquid, window, shear_end));
    sum.set("residual.T" + suffix, tail_mean(s.granular_temperature, window, shear_end));
    const double gamma_res = tail_mean(s.collisional_dissipation, window, shear_end);
    const double lambda_res = tail_mean(s.liquid_dissipation, window, shear_end);
    if (gamma_res + lambda_res > 0)
      sum.set("residual.liquid_dissipation_share" + suffix, lambda_res / (gamma_res + lambda_res));
    sum.set("residual.eps_d" + suffix, s.deviatoric_strain[shear.last]);
    if (shear.steady_checked) {
      sum.set("residual.steady" + suffix, shear.steady ? 1.0 : 0.0);
      sum.set("residual.drift_T" + suffix, shear.drift_temperature);
      sum.set("residual.drift_q" + suffix, shear.drift_q);
      if (shear.steady && shear.extra_steps > 0)
        ctx.log->info(
            "{}: ran on to ε_d = {:.4g} ({} steps past the final strain) until steady: "
            "d ln T/dε_d = {:.3g}, d ln q/dε_d = {:.3g}",
            label, s.deviatoric_strain[shear.last], shear.extra_steps, shear.drift_temperature,
            shear.drift_q);
      if (!shear.steady)
        ctx.log->warn(
            "{}: the residual is not steady at ε_d = {:.4g} (loading.max_deviatoric_strain): "
            "d ln T/dε_d = {:.3g}, d ln q/dε_d = {:.3g} above loading.steady_tolerance {:g}; the "
            "reported residual is a transient",
            label, s.deviatoric_strain[shear.last], shear.drift_temperature, shear.drift_q,
            control.stages[0].steady_tolerance);
    }
    sum.set("peak.q" + suffix, *std::max_element(s.q.begin(), s.q.begin() + shear_end));
    sum.set("final.r_c" + suffix, s.locus_size[last]);
    sum.set("final.T" + suffix, s.granular_temperature[last]);
    sum.set("final.e" + suffix, s.void_ratio[last]);
    sum.set("final.p_eff" + suffix, s.effective_pressure[last]);
    sum.set("final.q" + suffix, s.q[last]);
    sum.set("final.q_fc" + suffix, s.q_force_chain[last]);
    sum.set("final.u_w" + suffix, s.pore_pressure[last]);
    sum.set("final.eps_v" + suffix, s.volumetric_strain[last]);
    sum.set("final.eps_d" + suffix, s.deviatoric_strain[last]);
    if (s.effective_pressure[last] > 0) {
      sum.set("final.stress_ratio" + suffix, s.q_force_chain[last] / s.effective_pressure[last]);
      sum.set("final.e_cs" + suffix,
              point.force_chain_model()->critical_state().critical_void_ratio(
                  s.effective_pressure[last]));
    }
    if (control.stages.size() > 1) {
      sum.set("shear_end.T" + suffix, s.granular_temperature[shear_end - 1]);
      sum.set("shear_end.r_c" + suffix, s.locus_size[shear_end - 1]);
      sum.set("shear_end.u_w" + suffix, s.pore_pressure[shear_end - 1]);
      if (r.resolidification_time >= 0)
        sum.set("reconsolidation.time" + suffix, r.resolidification_time - s.time[shear_end - 1]);
    }
    sum.set("check.max_radial_residual" + suffix, r.max_radial_residual);
    rates.push_back(control.stages[0].deviatoric_strain_rate);
    residual_q.push_back(q_res);
    residual_q_col.push_back(tail_mean(s.q_collisional, window, shear_end));
    residual_q_liq.push_back(tail_mean(s.q_liquid, window, shear_end));
    lambda_share.push_back(gamma_res + lambda_res > 0 ? lambda_res / (gamma_res + lambda_res) : 0);
    steady.push_back(shear.steady_checked ? (shear.steady ? 1.0 : 0.0) : -1.0);
    if (sweep) sum.set("rate" + suffix, control.stages[0].deviatoric_strain_rate);
    ctx.log->info(
        "{}: {} steps, {} point updates; liquefaction at ε_d = {}; residual q = {:.4g} Pa "
        "(FC {:.4g}, COL {:.4g}, L {:.4g}); final e = {:.5g}, p' = {:.5g} Pa, u_w = {:.6g} Pa, "
        "T = {:.3g} m²/s², r_c = {:.4g} Pa",
        label, r.steps, r.solver_evaluations,
        r.liquefaction_strain >= 0 ? fmt::format("{:.4g}", r.liquefaction_strain) : "never", q_res,
        tail_mean(s.q_force_chain, window, shear_end),
        tail_mean(s.q_collisional, window, shear_end), tail_mean(s.q_liquid, window, shear_end),
        s.void_ratio[last], s.effective_pressure[last], s.pore_pressure[last],
        s.granular_temperature[last], s.locus_size[last]);
    total_steps += r.steps;
    total_evaluations += r.solver_evaluations;
    max_residual = std::max(max_residual, r.max_radial_residual);
    progress.update(static_cast<double>(n + 1));
  }
  // Rate sweep: slopes of log residual q against log ε̇_d over the 3 lowest and 3 highest rates.
  const auto& keys = ctx.run_case.sweep_keys();
  if (sweep && keys.size() == 1 && keys[0] == "loading.deviatoric_strain_rate" &&
      rates.size() >= 4) {
    std::vector<std::size_t> order(rates.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](auto a, auto b) { return rates[a] < rates[b]; });
    auto slope_of = [&](std::size_t from) {
      std::vector<double> x, y;
      for (std::size_t i = from; i < from + 3; ++i) {
        x.push_back(rates[order[i]]);
        y.push_back(residual_q[order[i]]);
      }
      return log_slope(x, y);
    };
    ctx.summary.set("slope.low", slope_of(0));
    ctx.summary.set("slope.high", slope_of(rates.size() - 3));
    ctx.result.write("/sweep/rate", rates, "1/s", "imposed ε̇_d");
    ctx.result.write("/sweep/residual_q", residual_q, "Pa", "residual q (last 10 % of shearing)");
    ctx.result.write("/sweep/residual_q_col", residual_q_col, "Pa", "residual q of σ_COL");
    ctx.result.write("/sweep/residual_q_liq", residual_q_liq, "Pa", "residual q of σ_L");
    ctx.result.attribute("/sweep", "slope_low", slope_of(0));
    ctx.result.attribute("/sweep", "slope_high", slope_of(rates.size() - 3));
    ctx.log->info(
        "rate sweep: slope of log q_res vs log ε̇_d = {:.3f} (3 lowest rates), {:.3f} "
        "(3 highest)",
        slope_of(0), slope_of(rates.size() - 3));
    // Local slopes d ln q / d ln ε̇_d between neighbouring rates, and the table of the regimes:
    // q_COL/q_L and Λ/(Γ + Λ), the liquid's share of the dissipation of T.
    std::vector<double> local_slope(rates.size(), 0.0), ratio(rates.size());
    ctx.log->info(
        "rate sweep: ε̇_d 1/s | residual q Pa | q_COL/q_L | Λ/(Γ+Λ) | steady | slope to next");
    for (std::size_t k = 0; k < order.size(); ++k) {
      const std::size_t i = order[k];
      ratio[i] = residual_q_col[i] / residual_q_liq[i];
      std::string slope = "-";
      if (k + 1 < order.size()) {
        const std::size_t j = order[k + 1];
        local_slope[i] = std::log(residual_q[j] / residual_q[i]) / std::log(rates[j] / rates[i]);
        ctx.summary.set(fmt::format("slope.local.{}", i), local_slope[i]);
        slope = fmt::format("{:.3f}", local_slope[i]);
      }
      ctx.log->info("rate sweep: {:g} | {:.4g} | {:.3g} | {:.3f} | {:g} | {}", rates[i],
                    residual_q[i], ratio[i], lambda_share[i], steady[i], slope);
    }
    ctx.result.write("/sweep/local_slope", local_slope, "1",
                     "d ln q / d ln ε̇_d from this rate to the next higher one (0 at the highest)");
    ctx.result.write("/sweep/q_col_over_q_liq", ratio, "1", "residual q_COL / q_L");
    ctx.result.write("/sweep/liquid_dissipation_share", lambda_share, "1",
                     "Λ / (Γ + Λ) over the residual window");
    ctx.result.write("/sweep/steady", std::vector<long>(steady.begin(), steady.end()), "1",
                     "1: residual steady within loading.steady_tolerance, 0: not, -1: unchecked");
  }
  if (sweep) ctx.summary.set("sweep.count", static_cast<double>(conditions.size()));
  const double wall = ctx.wall_seconds();
  ctx.summary.set("cost.steps", static_cast<double>(total_steps));
  ctx.summary.set("cost.point_updates", static_cast<double>(total_evaluations));
  ctx.summary.set("cost.point_updates_per_s", total_evaluations / std::max(wall, 1e-9));
  ctx.summary.set("accuracy.max_radial_residual", max_residual);
  ctx.log->info(
      "cost: {} steps, {} point updates in {:.3f} s; largest radial stress residual "
      "{:.3g} Pa",
      total_steps, total_evaluations, wall, max_residual);
  ctx.plot("plot_rev_triaxial.py");
  return core::exit_ok;
}

int run_isotropic_case(core::RunContext& ctx) {
  const core::Case& c = ctx.run_case;
  const continuum::MultiRegimePoint point(continuum::read_multi_regime_settings(c));
  IsotropicControl control;
  control.void_ratio = c.number("initial.void_ratio");
  control.effective_pressure = c.number("initial.effective_pressure");
  control.overconsolidation = c.number("initial.overconsolidation");
  control.pore_pressure = c.number("initial.pore_pressure");
  control.volumetric_strain_rate = c.number("loading.volumetric_strain_rate");
  control.final_volumetric_strain = c.number("loading.final_volumetric_strain");
  control.steps = static_cast<int>(c.integer("loading.steps"));
  const ElementResult r = run_isotropic_compression(point, control);
  write_series(ctx.result, "/series", r.series);
  const auto& s = r.series;
  const std::size_t last = s.time.size() - 1;
  ctx.summary.set("final.p_eff", s.effective_pressure[last]);
  ctx.summary.set("final.e", s.void_ratio[last]);
  ctx.summary.set("final.r_c", s.locus_size[last]);
  ctx.summary.set("final.T", s.granular_temperature[last]);
  ctx.summary.set("final.eps_v", s.volumetric_strain[last]);
  ctx.log->info("isotropic compression: ε_v = {:.4g}: p' {:.5g} -> {:.5g} Pa, e {:.5g} -> {:.5g}",
                s.volumetric_strain[last], s.effective_pressure[0], s.effective_pressure[last],
                s.void_ratio[0], s.void_ratio[last]);
  ctx.plot("plot_rev_triaxial.py");
  return core::exit_ok;
}

}  // namespace

void register_element_test_kinds(core::KindRegistry& registry) {
  registry.add({"rev", "triaxial",
                "drained/undrained triaxial compression of a material point with all terms",
                triaxial_schema(), check_triaxial, run_triaxial_case,
                "cases/rev/triaxial_undrained_rate1.yaml"});
  registry.add({"rev", "isotropic_compression",
                "drained isotropic compression of a material point at imposed ε̇_v",
                isotropic_compression_schema(), check_common, run_isotropic_case,
                "cases/rev/isotropic_compression.yaml"});
}

}  // namespace granflow::rev
