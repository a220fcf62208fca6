#include "analysis/transient_pair/transient_pair_kind.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <set>
#include <span>
#include <sstream>
#include <tuple>

#include "analysis/transient_pair/continuum_transient.hpp"
#include "analysis/transient_pair/pair_stages.hpp"
#include "continuum/sections/model_sections.hpp"
#include "core/interrupt.hpp"
#include "core/numerical_failure.hpp"
#include "core/result_file.hpp"
#include "core/sweep_scheduler.hpp"
#include "dem_coupling/dem_kind.hpp"
#include "dem_coupling/kind/dem_columns.hpp"
#include "dem_coupling/kind/transient.hpp"

namespace granflow::transient_pair {

namespace {

// Top-level keys of a transient pair case that the DEM part does not read.
constexpr const char* continuum_sections[] = {"collisional", "force_chains", "continuum",
                                              "calibrate", "dem_run"};

// The DEM case of a transient pair case: the same file without the continuum-only sections,
// kind: dem. `schema` must outlive the returned Case (it refers to it).
core::Case dem_part(const core::Case& c, const core::Schema& schema) {
  YAML::Node root = YAML::Load(c.resolved_yaml());
  for (const char* section : continuum_sections) root.remove(section);
  root["kind"] = "dem";
  YAML::Emitter out;
  out << root;
  return core::Case::parse(out.c_str(), c.origin() + " (DEM part)", {}, schema);
}

const core::KindEntry& dem_entry(core::KindRegistry& registry, const core::Case& c) {
  dem::register_dem_kinds(registry);
  return registry.find("dem", "", c.origin());
}

// "a b c" -> {"a", "b", "c"}; "none" alone -> {}.
std::vector<std::string> parameter_names(const core::Case& c) {
  std::vector<std::string> out;
  std::istringstream in(c.string("calibrate.parameters"));
  for (std::string w; in >> w;)
    if (w != "none") out.push_back(w);
  return out;
}

// The DEM's seed mean and band of condition `index` beside the continuum (one file holds the
// pair): group/dem/strain and group/dem/NAME_{mean,min,max} for the band's columns (a table of
// its own: the DEM's samples are not the continuum's steps).
void write_dem_band(core::RunContext& ctx, const std::filesystem::path& dem_h5, std::size_t index,
                    const std::string& group) {
  const std::string from = fmt::format("/transient/group_{}/", index);
  const auto copy_band = [&](const std::string& part_path) {  // "" or "stop/"
    for (const auto& row : dem::dem_columns::transient_band)
      if (core::dataset_exists(dem_h5, from + part_path + row.column.name +  // older DEM runs
                                           dem::dem_columns::band_mean))     // lack some columns
        for (const char* part : {dem::dem_columns::band_mean, dem::dem_columns::band_min,
                                 dem::dem_columns::band_max}) {
          const std::string name = part_path + row.column.name + part;
          ctx.result.write(
              group + "/dem/" + name, core::read_dataset(dem_h5, from + name), row.column.unit,
              core::read_string_attribute(dem_h5, from + name, "description") + " (DEM)");
        }
  };
  ctx.result.write(group + "/dem/strain", core::read_dataset(dem_h5, from + "strain"), "1",
                   "shear strain of the DEM samples");
  copy_band("");
  // The shear stopped (stop.duration > 0): the DEM's stop band.
  if (!core::dataset_exists(dem_h5, from + "stop/" + core::columns::time.name)) return;
  ctx.result.write(group + "/dem/stop/" + core::columns::time.name,
                   core::read_dataset(dem_h5, from + "stop/" + core::columns::time.name),
                   core::columns::time.unit, "time since the DEM's shear was stopped");
  copy_band("stop/");
}

// The continuum's undrained shear of one condition beside the DEM's: series under
// group/NAME{suffix} (results vocabulary), metrics of both sides in summary.json
// (transient.dem.NAME, transient.cont{suffix}.NAME, transient.rel_err{suffix}.NAME; `g` is the
// condition suffix) and as attributes of the group. False (after logging and writing the series
// so far) when the continuum stopped on a numerical failure.
bool compare(core::RunContext& ctx, const core::Case& condition, const DemTransient& dem,
             const Thresholds& limits, const std::string& group, const std::string& g,
             const std::string& suffix, std::size_t index) {
  rev::SimpleShearResult rev;
  bool failed = false;
  try {
    continuum_transient(condition, dem.phi0, dem.p0, rev);
  } catch (const core::NumericalFailure& e) {
    ctx.log->error("condition {}: the continuum's undrained shear stopped: {}", index, e.what());
    failed = true;  // the series so far are written below
  }
  const auto& s = rev.series;
  namespace col = core::columns;
  const std::string model =
      suffix.empty() ? "continuum" : "continuum with the fitted force-chain parameters";
  const std::tuple<const char*, core::Column, const std::vector<double>&> series[] = {
      {nullptr, col::strain, s.strain},
      {nullptr,
       col::described(col::mean_stress,
                      "mean stress p' = p_COL + p_IC + tr(σ_FC)/3 (the DEM's tr(P)/3)"),
       s.pressure},
      {nullptr, col::normal_stress, s.normal_stress},
      {nullptr, col::shear_stress, s.shear_stress},
      {"shear_stress_force_chains",
       col::described(col::shear_stress, "shear stress τ_FC carried by the force chains"),
       s.force_chain_shear_stress},
      {"shear_stress_collisional",
       col::described(col::shear_stress, "shear stress τ_COL of the collisions (kinetic theory)"),
       s.collisional_shear_stress},
      {"shear_stress_liquid",
       col::described(col::shear_stress,
                      "shear stress τ_L of the liquid (mixture viscosity η(ν) and the contacts' "
                      "viscous share)"),
       s.liquid_shear_stress},
      {nullptr, col::granular_temperature, s.granular_temperature},
      {nullptr, col::solid_fraction, s.solid_fraction},
  };
  for (const auto& [name, column, values] : series)
    ctx.result.write(group + "/" + (name ? name : column.name) + suffix, values, column.unit,
                     model + ": " + column.description);
  if (failed) {
    ctx.result.flush();
    return false;
  }
  const auto dem_m = dem::transient_metrics(dem.strain, dem.p_mean, dem.tau_mean, dem.p0,
                                            limits.liquefaction, limits.residual);
  const auto cont_m = dem::transient_metrics(s.strain, s.pressure, s.shear_stress, dem.p0,
                                             limits.liquefaction, limits.residual);
  auto& sum = ctx.summary;
  const std::string cont = "cont" + suffix;
  const bool liq_dem = dem_m.liquefaction_strain >= 0, liq_cont = cont_m.liquefaction_strain >= 0;
  const MetricPair metrics[] = {
      {"peak_tau", {dem_m.peak_tau, cont_m.peak_tau}},
      {"peak_strain", {dem_m.peak_strain, cont_m.peak_strain}},
      {"residual_tau", {dem_m.residual_tau, cont_m.residual_tau}},
      {"residual_p", {dem_m.residual_p, cont_m.residual_p}},
      {"p_final_over_p0", {dem_m.p_final_over_p0, cont_m.p_final_over_p0}},
      {"liquefied", {liq_dem ? 1.0 : 0.0, liq_cont ? 1.0 : 0.0}},
  };
  write_metrics(ctx, metrics, dem, group, g, suffix);
  sum.set(metric_key("rel_err" + suffix, "peak_tau", g),
          relative_error(cont_m.peak_tau, dem_m.peak_tau));
  // The liquefaction strain is absent on the side that does not liquefy.
  if (liq_dem && suffix.empty()) {
    sum.set(metric_key("dem", "liquefaction_strain", g), dem_m.liquefaction_strain);
    if (const auto e = dem.metric_err.find("liquefaction_strain"); e != dem.metric_err.end())
      sum.set(metric_key("dem", "liquefaction_strain_err", g), e->second);
  }
  if (liq_cont) sum.set(metric_key(cont, "liquefaction_strain", g), cont_m.liquefaction_strain);
  if (liq_dem && liq_cont)
    sum.set(metric_key("rel_err" + suffix, "liquefaction_strain", g),
            relative_error(cont_m.liquefaction_strain, dem_m.liquefaction_strain));
  // The residual τ against the DEM's seed band: its seed mean ± 2 standard errors (between
  // seeds) or ± 2 batch-means errors of the mean series' tail, whichever is larger.
  const auto seed_err = dem.metric_err.find("residual_tau");
  const double band_err =
      std::max(dem_m.residual_tau_err, seed_err != dem.metric_err.end() ? seed_err->second : 0.0);
  const bool within = std::abs(cont_m.residual_tau - dem_m.residual_tau) <= 2.0 * band_err;
  if (suffix.empty()) sum.set(metric_key("dem", "residual_tau_band", g), band_err);
  sum.set(metric_key(cont, "residual_tau_within_band", g), within ? 1 : 0);
  if (condition.has("rate_step.strain"))
    compare_rate_step(ctx, condition, dem, rev, limits, group, g, suffix);
  if (!dem.stop_time.empty()) try {
      compare_stop(ctx, condition, dem, rev, limits, group, g, suffix);
    } catch (const core::NumericalFailure& e) {
      ctx.log->error("condition {}: the continuum's stop stage stopped: {}", index, e.what());
      ctx.result.flush();
      return false;
    }
  ctx.log->info(
      "condition {}{} (φ0 = {:.4f}, p0 = {:.4g} Pa, γ̇ = {:g} 1/s): peak τ DEM {:.4g} Pa at γ = "
      "{:.3g}, continuum {:.4g} Pa at {:.3g} ({:+.1f} %); liquefied: DEM {}, continuum {}; "
      "residual τ DEM {:.4g} ± {:.2g} Pa, continuum {:.4g} Pa{}",
      index, suffix.empty() ? "" : " calibrated", dem.phi0, dem.p0, condition.number("shear_rate"),
      dem_m.peak_tau, dem_m.peak_strain, cont_m.peak_tau, cont_m.peak_strain,
      100.0 * relative_error(cont_m.peak_tau, dem_m.peak_tau),
      liq_dem ? fmt::format("at γ = {:.3g}", dem_m.liquefaction_strain) : std::string("no"),
      liq_cont ? fmt::format("at γ = {:.3g}", cont_m.liquefaction_strain) : std::string("no"),
      dem_m.residual_tau, 2.0 * band_err, cont_m.residual_tau,
      within ? " (within the DEM band)" : "");
  return true;
}

// The completed `kind: dem` run of `dem_run`, resolved from the working directory, then beside
// the case file.
std::filesystem::path dem_run_directory(const core::Case& c) {
  const std::filesystem::path p(c.string("dem_run"));
  if (p.is_absolute() || std::filesystem::exists(p)) return std::filesystem::absolute(p);
  const auto beside_case = std::filesystem::path(c.origin()).parent_path() / p;
  return std::filesystem::exists(beside_case) ? std::filesystem::absolute(beside_case) : p;
}

// A `dem_run` must be a finished kind: dem run of this case's DEM part: its /transient groups
// are the conditions, in sweep order, at the same shear rates.
void check_dem_run(const core::Case& c) {
  const auto dir = dem_run_directory(c);
  const auto expected = [&](const std::string& why) {
    c.fail("dem_run", fmt::format("a finished kind: dem run of this case's conditions ({}); {}",
                                  dir.string(), why));
  };
  if (!std::filesystem::is_directory(dir)) expected("not a directory");
  if (!std::filesystem::exists(dir / "case.yaml") ||
      core::peek_kind(dir / "case.yaml").first != "dem")
    expected("its case.yaml is not kind: dem");
  core::KindRegistry registry;
  const auto& entry = dem_entry(registry, c);
  const core::Case run = core::Case::load(dir / "case.yaml", {}, entry.schema);
  const auto theirs = run.expand_sweep();
  const auto ours = c.expand_sweep();
  if (theirs.size() != ours.size())
    expected(fmt::format("it has {} conditions, this case {}", theirs.size(), ours.size()));
  for (std::size_t g = 0; g < ours.size(); ++g) {
    if (theirs[g].number("shear_rate") != ours[g].number("shear_rate"))
      expected(fmt::format("condition {} is sheared at {:g} 1/s there, {:g} 1/s here", g,
                           theirs[g].number("shear_rate"), ours[g].number("shear_rate")));
    try {
      core::read_number_attribute(dir / "result.h5", fmt::format("/transient/group_{}", g),
                                  "mean_phi0");
    } catch (const std::exception&) {
      expected(
          fmt::format("its result.h5 has no /transient/group_{} (started from "
                      "start.preparation, finished)",
                      g));
    }
  }
}

}  // namespace

core::Schema transient_pair_schema() {
  core::Schema s = core::kind_header(
      "transient_pair", "",
      "Undrained (or drained) shear from rest of a prepared packing in the DEM (kind: dem from "
      "start.preparation, several seeds) and in the multi-regime REV from the same φ0, p0 and "
      "γ̇ (and its steps); p'(γ), τ(γ) side by side with the transition metrics (peak τ, "
      "liquefaction, residual; the rate step's μ, φ, T and dilation).");
  const core::Schema dem = dem::shear_schema();
  const std::set<std::string> header = {"kind", "test", "name", "description"};
  for (const auto& child : dem.children())
    if (!header.count(child.key())) s.add(child);
  s.add(continuum::collisional_section());
  s.add(continuum::force_chains_section(true));
  auto& cont = s.section("continuum", "accuracy controls of the continuum's undrained shear");
  cont.number("strain_increment", "", "largest shear strain increment per REV step")
      .default_value("1.0e-3")
      .greater_than(0)
      .at_most(0.05);
  cont.number("initial_temperature", "",
              "T0 / (d γ̇)² of the REV (the DEM starts at rest; kinetic theory needs T > 0)")
      .default_value("1.0e-4")
      .greater_than(0);
  auto& cal = s.section("calibrate",
                        "optional: fit force-chain parameters to the DEM transient of one "
                        "condition (the others held out) and show the calibrated continuum");
  cal.string("parameters",
             "force_chains keys to fit (e.g. xi_psi beta_f) or other key paths of positive numbers "
             "(e.g. liquid.viscous_contact), separated by spaces; none: no fit")
      .default_value("none");
  cal.integer("condition", "the condition (in sweep order) fitted").default_value("0").at_least(0);
  cal.number("range", "",
             "each fitted parameter stays within [v/range, v × range] of the case's value v")
      .default_value("20")
      .greater_than(1);
  s.string("dem_run",
           "optional: a finished kind: dem run of this case's DEM part (the same conditions, from "
           "start.preparation) whose transients are used instead of running the DEM again "
           "(a refit, another continuum); from the working directory, else beside the case file");
  return s;
}

void check_transient_pair_case(const core::Case& c) {
  if (!c.has("start.preparation"))
    c.fail("start.preparation",
           "a kind: dem_prepare run directory (both sides start from its prepared packing)");
  if (const std::string mode = c.string("control.mode"); mode == "constant_pressure")
    c.fail("control.mode", "constant_volume (the undrained test) or drained");
  if (const std::string mode = c.string("control.mode");
      (mode == "drained" || mode == "damped_height") && !c.boolean("force_chains.enabled"))
    c.fail("control.mode",
           "constant_volume without the force chains (a drained or damped continuum solves σ_yy "
           "with its skeleton: force_chains.enabled)");
  if (!c.boolean("collisional.enabled"))
    c.fail("collisional.enabled", "true (the continuum side carries T and the collisions)");
  const auto names = parameter_names(c);
  if (!names.empty()) {
    if (!c.boolean("force_chains.enabled"))
      c.fail("calibrate.parameters", "no fit without the force chains (force_chains.enabled)");
    const std::size_t count = c.expand_sweep().size();
    if (std::size_t(c.integer("calibrate.condition")) >= count)
      c.fail("calibrate.condition", fmt::format("a condition index below {}", count));
    for (const auto& name : names) try {
        if (!(c.number(fitted_key(name)) > 0)) throw std::logic_error("not positive");
      } catch (const std::logic_error&) {  // no such number key (Case::number), or <= 0
        c.fail("calibrate.parameters",
               fmt::format("positive numeric force_chains keys, or key paths of positive numbers "
                           "(docs/cases.md); '{}' is not one",
                           name));
      }
  }
  core::KindRegistry registry;
  const auto& entry = dem_entry(registry, c);
  const core::Case d = dem_part(c, entry.schema);
  if (entry.check) entry.check(d);
}

// Before the run: every prepared state exists (the DEM's own check), and the continuum can start
// at its φ0: below the collisional closures' pole (model::maximum_solid_fraction).
void check_transient_pair_inputs(const core::Case& c) {
  dem::check_preparation_inputs(c);
  if (c.has("dem_run")) check_dem_run(c);
  for (const core::Case& condition : c.expand_sweep()) {
    const auto prepared = dem::read_prepared_state(condition, condition.integer("dem.seed"));
    const auto settings = continuum::read_multi_regime_settings(condition);
    const double nu_max = model::maximum_solid_fraction(settings.collisional_parameters);
    if (prepared.phi >= nu_max)
      c.fail("collisional.jamming_fraction",
             fmt::format("a pole above the prepared φ0 = {:.4f} (the continuum starts there); "
                         "the closures diverge at {:.4f}",
                         prepared.phi, nu_max));
  }
}

int run_transient_pair_case(core::RunContext& ctx) {
  const core::Case& c = ctx.run_case;
  auto& log = *ctx.log;
  std::filesystem::path h5;
  if (c.has("dem_run")) {                             // ---- DEM side: a finished run
    if (!core::owns_outputs()) return core::exit_ok;  // mpirun: nothing to share, rank 0 fits
    h5 = dem_run_directory(c) / "result.h5";
    log.info("DEM part: the finished run {} (not run again)", h5.parent_path().string());
  } else {  // ---- DEM side: the dem kind's own run function in RUN_DIR/dem/
    core::KindRegistry registry;
    const auto& entry = dem_entry(registry, c);
    const core::Case d = dem_part(c, entry.schema);
    const auto dem_dir = ctx.directory.path() / "dem";
    log.info("DEM part: kind dem in {} (log: dem/log.txt)", dem_dir.string());
    int code = 0;
    {
      core::RunContext dem_ctx(d, dem_dir, true, false);
      code = entry.run(dem_ctx);
      if (!core::owns_outputs()) return code;  // mpirun: the DEM seeds were shared out
      if (core::interrupted()) dem_ctx.summary.set("run.interrupted", 1);
      dem_ctx.finish();
    }
    if (core::interrupted()) return code;
    if (code != core::exit_ok) {
      log.error("the DEM part failed (exit {}); see {}", code, (dem_dir / "log.txt").string());
      return code;
    }
    h5 = dem_dir / "result.h5";
  }

  const std::vector<core::Case> conditions = c.expand_sweep();
  std::vector<DemTransient> dem_side;
  namespace band = dem::dem_columns;
  const std::string p_name = band::transient_band[0].column.name;    // p'
  const std::string tau_name = band::transient_band[1].column.name;  // τ
  for (std::size_t g = 0; g < conditions.size(); ++g) {
    const std::string group = fmt::format("/transient/group_{}/", g);
    DemTransient t;
    t.phi0 = core::read_number_attribute(h5, group, "mean_phi0");
    t.p0 = core::read_number_attribute(h5, group, "mean_p0");
    t.strain = core::read_dataset(h5, group + core::columns::strain.name);
    t.p_mean = core::read_dataset(h5, group + p_name + band::band_mean);
    t.p_min = core::read_dataset(h5, group + p_name + band::band_min);
    t.p_max = core::read_dataset(h5, group + p_name + band::band_max);
    t.tau_mean = core::read_dataset(h5, group + tau_name + band::band_mean);
    t.tau_min = core::read_dataset(h5, group + tau_name + band::band_min);
    t.tau_max = core::read_dataset(h5, group + tau_name + band::band_max);
    const std::string T_name = band::transient_band[3].column.name;  // T
    t.T_mean = core::read_dataset(h5, group + T_name + band::band_mean);
    const std::string sigma_name = band::transient_band[2].column.name;  // σ_yy
    const std::string phi_name = band::transient_band[6].column.name;    // φ
    if (core::dataset_exists(h5, group + phi_name + band::band_mean)) {
      t.sigma_yy_mean = core::read_dataset(h5, group + sigma_name + band::band_mean);
      t.phi_mean = core::read_dataset(h5, group + phi_name + band::band_mean);
    }
    if (core::dataset_exists(h5, group + "stop/" + core::columns::time.name)) {
      t.stop_time = core::read_dataset(h5, group + "stop/" + core::columns::time.name);
      t.stop_T_mean = core::read_dataset(h5, group + "stop/" + T_name + band::band_mean);
      t.stop_p_mean = core::read_dataset(h5, group + "stop/" + p_name + band::band_mean);
      if (core::dataset_exists(h5, group + "stop/" + phi_name + band::band_mean)) {
        t.stop_sigma_yy_mean =
            core::read_dataset(h5, group + "stop/" + sigma_name + band::band_mean);
        t.stop_phi_mean = core::read_dataset(h5, group + "stop/" + phi_name + band::band_mean);
      }
    }
    for (const char* name : {"peak_tau",
                             "peak_strain",
                             "residual_tau",
                             "residual_p",
                             "p_final_over_p0",
                             "liquefaction_strain",
                             "flowing_T",
                             "cooling_time",
                             "stop_T_over_flowing_T",
                             "stop_p_over_p0",
                             "reconsolidation_time",
                             "stop_phi",
                             "stop_phi_change",
                             "mu_before_step",
                             "mu_after_step",
                             "phi_before_step",
                             "phi_after_step",
                             "T_before_step",
                             "T_after_step",
                             "dilation",
                             "peak_mu_after_step",
                             "dilation_strain"})
      try {
        t.metric_err[name] = core::read_number_attribute(h5, group, std::string("err_") + name);
      } catch (const std::exception&) {  // no seed liquefied: no liquefaction strain
      }
    dem_side.push_back(std::move(t));
  }

  // ---- optional fit of force-chain parameters on one condition's DEM transient
  const std::vector<std::string> fit_names = parameter_names(c);
  const auto schema = transient_pair_schema();
  const std::size_t fitted = std::size_t(c.integer("calibrate.condition"));
  std::vector<double> estimate;
  auto& sum = ctx.summary;
  if (!fit_names.empty()) {
    log.info("fitting force_chains.{{{}}} to the DEM transient of condition {} ...",
             fmt::join(fit_names, ", "), fitted);
    const auto fit = fit_force_chains(conditions[fitted], schema, fit_names, dem_side[fitted]);
    estimate = fit.estimate;
    for (std::size_t j = 0; j < fit_names.size(); ++j) {
      log.info("  {} = {:.6g} ± {:.3g} (start {:.6g}){}", fit_names[j], fit.estimate[j],
               fit.standard_error[j], fit.start[j], fit.at_bound[j] ? " (on its bound)" : "");
      sum.set("transient.fit." + fit_names[j], fit.estimate[j]);
      sum.set("transient.fit." + fit_names[j] + "_err", fit.standard_error[j]);
      sum.set("transient.fit." + fit_names[j] + "_start", fit.start[j]);
    }
    log.info("  χ²_red {:.4g} (start {:.4g}), {} REV runs{}", fit.chi2_red,
             fit.chi2_initial / std::max(1, fit.points - int(fit_names.size())), fit.evaluations,
             fit.converged ? "" : ", not converged");
    sum.set("transient.fit.chi2_red", fit.chi2_red);
    sum.set("transient.fit.evaluations", fit.evaluations);
    sum.set("transient.fit.converged", fit.converged ? 1 : 0);
    sum.set("transient.fit.condition", double(fitted));
  }

  // ---- continuum side, condition by condition (the DEM's /transient/group_G, in sweep order)
  const Thresholds limits{
      c.number("transient.liquefaction_fraction"), c.number("transient.residual_fraction"),
      c.number("stop.cooling_fraction"), c.number("stop.reconsolidation_fraction")};
  for (std::size_t g = 0; g < conditions.size(); ++g) {
    const std::string key = conditions.size() > 1 ? fmt::format(".{}", g) : std::string();
    const std::string group = fmt::format("/transient_pair/group_{}", g);
    ctx.result.attribute(group, "phi0", dem_side[g].phi0);
    ctx.result.attribute(group, "p0", dem_side[g].p0);
    ctx.result.attribute(group, "shear_rate", conditions[g].number("shear_rate"));
    ctx.result.attribute(group, "liquefaction_fraction", limits.liquefaction);
    ctx.result.attribute(group, "dem_result", h5.string());
    if (const std::string mode = conditions[g].string("control.mode");
        mode == "drained" || mode == "damped_height") {  // the total σ_n, and H or R
      if (mode == "drained")
        ctx.result.attribute(group, "drainage_length",
                             conditions[g].number("control.drainage_length"));
      else
        ctx.result.attribute(group, "height_resistance",
                             conditions[g].number("control.height_resistance"));
      ctx.result.attribute(group, "normal_stress",
                           conditions[g].has("control.normal_stress")
                               ? conditions[g].number("control.normal_stress")
                               : dem_side[g].p0);
    }
    sum.set("transient.phi0" + key, dem_side[g].phi0);
    sum.set("transient.p0" + key, dem_side[g].p0);
    write_dem_band(ctx, h5, g, group);
    if (!compare(ctx, conditions[g], dem_side[g], limits, group, key, "", g))
      return core::exit_numerical;
    if (!estimate.empty()) {
      const core::Case calibrated =
          with_force_chain_values(conditions[g], schema, fit_names, estimate);
      if (!compare(ctx, calibrated, dem_side[g], limits, group, key, "_cal", g))
        return core::exit_numerical;
      sum.set("transient.held_out" + key, g == fitted ? 0 : 1);
    }
  }
  sum.set("transient.conditions", double(conditions.size()));
  ctx.result.flush();
  ctx.plot("plot_transient_pair.py");
  return core::exit_ok;
}

void register_transient_pair_kinds(core::KindRegistry& registry) {
  core::KindEntry entry{"transient_pair",
                        "",
                        "undrained or drained shear from rest, DEM and continuum side by side "
                        "(one material)",
                        transient_pair_schema(),
                        check_transient_pair_case,
                        run_transient_pair_case,
                        "cases/transient_pair/undrained_loose.yaml"};
  entry.check_inputs = check_transient_pair_inputs;
  entry.distributes_conditions = true;
  registry.add(std::move(entry));
}

}  // namespace granflow::transient_pair
