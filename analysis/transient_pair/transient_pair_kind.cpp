#include "analysis/transient_pair/transient_pair_kind.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "continuum/rev/simple_shear.hpp"
#include "continuum/sections/model_sections.hpp"
#include "core/interrupt.hpp"
#include "core/numerical_failure.hpp"
#include "core/result_file.hpp"
#include "core/sweep_scheduler.hpp"
#include "dem_coupling/dem_kind.hpp"
#include "dem_coupling/kind/transient.hpp"

namespace granflow::transient_pair {

namespace {

// Sections of a transient pair case that only the continuum reads.
constexpr const char* continuum_sections[] = {"collisional", "force_chains", "continuum"};

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

// The continuum's undrained shear of one condition from (φ0, p0): rev::run_simple_shear at
// constant volume, the skeleton isotropic at p'0 = p0 on its yield locus (r_c = √3 p'0), T0 a
// small fraction of (d γ̇)² (the DEM starts at rest), run through the DEM's strain (no steady
// stop: steady_tolerance 0).
// Throws core::NumericalFailure (step, variable); `result` then holds the series so far.
void continuum_transient(const core::Case& condition, double phi0, double p0,
                         rev::SimpleShearResult& result) {
  const continuum::MultiRegimeSettings settings =
      continuum::read_multi_regime_settings(condition);
  rev::SimpleShearControl control;
  control.control = rev::ShearControl::constant_volume;
  control.shear_rate = condition.number("shear_rate");
  control.void_ratio = 1.0 / phi0 - 1.0;
  control.effective_pressure = p0;
  control.overconsolidation = 1.0;
  const double d = condition.number("material.diameter");
  control.initial_temperature =
      condition.number("continuum.initial_temperature") * std::pow(d * control.shear_rate, 2);
  control.strain_increment = condition.number("continuum.strain_increment");
  control.max_strain = condition.number("strain.total");
  control.steady_tolerance = 0.0;
  control.max_steps = std::numeric_limits<long>::max() / 2;
  rev::run_simple_shear(continuum::MultiRegimePoint(settings), control, result);
}

double relative_error(double model, double data) {
  return data != 0.0 ? model / data - 1.0 : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

core::Schema transient_pair_schema() {
  core::Schema s = core::kind_header(
      "transient_pair", "",
      "Undrained shear from rest of a prepared packing in the DEM (kind: dem from "
      "start.preparation, several seeds) and in the multi-regime REV from the same φ0, p0 and "
      "γ̇; p'(γ), τ(γ) side by side with the transition metrics (peak τ, liquefaction, residual).");
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
  return s;
}

void check_transient_pair_case(const core::Case& c) {
  if (!c.has("start.preparation"))
    c.fail("start.preparation",
           "a kind: dem_prepare run directory (both sides start from its prepared packing)");
  if (c.string("control.mode") != "constant_volume")
    c.fail("control.mode", "constant_volume (the undrained test)");
  if (!c.boolean("collisional.enabled"))
    c.fail("collisional.enabled", "true (the continuum side carries T and the collisions)");
  core::KindRegistry registry;
  const auto& entry = dem_entry(registry, c);
  const core::Case d = dem_part(c, entry.schema);
  if (entry.check) entry.check(d);
}

// Before the run: every prepared state exists (the DEM's own check), and the continuum can start
// at its φ0: below the collisional closures' pole (model::maximum_solid_fraction).
void check_transient_pair_inputs(const core::Case& c) {
  dem::check_preparation_inputs(c);
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
  // ---- DEM side: the dem kind's own run function in RUN_DIR/dem/
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

  // ---- continuum side, condition by condition (the DEM's /transient/group_G, in sweep order)
  const auto h5 = dem_dir / "result.h5";
  const double fraction = c.number("transient.liquefaction_fraction");
  const double residual = c.number("transient.residual_fraction");
  const std::vector<core::Case> conditions = c.expand_sweep();
  auto& sum = ctx.summary;
  for (std::size_t g = 0; g < conditions.size(); ++g) {
    const std::string dem_group = fmt::format("/transient/group_{}", g);
    const std::string group = fmt::format("/transient_pair/group_{}", g);
    const std::string key = conditions.size() > 1 ? fmt::format("transient_pair.{}.", g)
                                                  : std::string("transient_pair.");
    const double phi0 = core::read_number_attribute(h5, dem_group, "mean_phi0");
    const double p0 = core::read_number_attribute(h5, dem_group, "mean_p0");
    const auto strain_dem = core::read_dataset(h5, dem_group + "/strain");
    const auto p_dem = core::read_dataset(h5, dem_group + "/p_mean");
    const auto tau_dem = core::read_dataset(h5, dem_group + "/tau_mean");
    const auto dem_m = dem::transient_metrics(strain_dem, p_dem, tau_dem, p0, fraction, residual);

    rev::SimpleShearResult rev;
    bool failed = false;
    try {
      continuum_transient(conditions[g], phi0, p0, rev);
    } catch (const core::NumericalFailure& e) {
      log.error("condition {}: the continuum's undrained shear stopped: {}", g, e.what());
      failed = true;  // the series so far are written below, then exit 3
    }
    const auto& s = rev.series;
    const auto cont_m =
        dem::transient_metrics(s.strain, s.pressure, s.shear_stress, p0, fraction, residual);
    ctx.result.write(group + "/strain", s.strain, "1", "shear strain of the continuum's steps");
    ctx.result.write(group + "/p", s.pressure, "Pa",
                     "continuum mean stress p' = p_COL + tr(σ_FC)/3 (the DEM's tr(P)/3)");
    ctx.result.write(group + "/sigma_yy", s.normal_stress, "Pa", "continuum normal stress σ_yy");
    ctx.result.write(group + "/tau", s.shear_stress, "Pa", "continuum shear stress τ");
    ctx.result.write(group + "/tau_force_chains", s.force_chain_shear_stress, "Pa",
                     "τ carried by the force chains");
    ctx.result.write(group + "/granular_temperature", s.granular_temperature, "m^2/s^2",
                     "continuum granular temperature T");
    ctx.result.attribute(group, "phi0", phi0);
    ctx.result.attribute(group, "p0", p0);
    ctx.result.attribute(group, "shear_rate", conditions[g].number("shear_rate"));
    ctx.result.attribute(group, "liquefaction_fraction", fraction);
    if (failed) {
      ctx.result.flush();
      return core::exit_numerical;
    }

    const std::pair<const char*, std::pair<double, double>> metrics[] = {
        {"peak_tau", {dem_m.peak_tau, cont_m.peak_tau}},
        {"peak_strain", {dem_m.peak_strain, cont_m.peak_strain}},
        {"residual_tau", {dem_m.residual_tau, cont_m.residual_tau}},
        {"residual_p", {dem_m.residual_p, cont_m.residual_p}},
    };
    for (const auto& [name, values] : metrics) {
      sum.set(key + name + "_dem", values.first);
      sum.set(key + name + "_cont", values.second);
      ctx.result.attribute(group, std::string(name) + "_dem", values.first);
      ctx.result.attribute(group, std::string(name) + "_cont", values.second);
    }
    sum.set(key + "rel_err_peak_tau", relative_error(cont_m.peak_tau, dem_m.peak_tau));
    sum.set(key + "phi0", phi0);
    sum.set(key + "p0", p0);
    const bool liq_dem = dem_m.liquefaction_strain >= 0, liq_cont = cont_m.liquefaction_strain >= 0;
    sum.set(key + "liquefied_dem", liq_dem ? 1 : 0);
    sum.set(key + "liquefied_cont", liq_cont ? 1 : 0);
    ctx.result.attribute(group, "liquefied_dem", liq_dem ? 1.0 : 0.0);
    ctx.result.attribute(group, "liquefied_cont", liq_cont ? 1.0 : 0.0);
    if (liq_dem) sum.set(key + "liquefaction_strain_dem", dem_m.liquefaction_strain);
    if (liq_cont) sum.set(key + "liquefaction_strain_cont", cont_m.liquefaction_strain);
    if (liq_dem && liq_cont)
      sum.set(key + "rel_err_liquefaction_strain",
              relative_error(cont_m.liquefaction_strain, dem_m.liquefaction_strain));
    // The residual τ against the DEM's seed band: its seed-mean ± 2 standard errors (between
    // seeds, dem transient.err.residual_tau) or ± 2 batch-means errors of one seed's tail.
    const double band_err = std::max(
        dem_m.residual_tau_err, core::read_number_attribute(h5, dem_group, "err_residual_tau"));
    const bool within = std::abs(cont_m.residual_tau - dem_m.residual_tau) <= 2.0 * band_err;
    sum.set(key + "residual_tau_dem_err", band_err);
    sum.set(key + "residual_tau_within_band", within ? 1 : 0);
    log.info(
        "condition {} (φ0 = {:.4f}, p0 = {:.4g} Pa, γ̇ = {:g} 1/s): peak τ DEM {:.4g} Pa at γ = "
        "{:.3g}, continuum {:.4g} Pa at {:.3g} ({:+.1f} %); liquefied: DEM {}, continuum {}; "
        "residual τ DEM {:.4g} ± {:.2g} Pa, continuum {:.4g} Pa{}",
        g, phi0, p0, conditions[g].number("shear_rate"), dem_m.peak_tau, dem_m.peak_strain,
        cont_m.peak_tau, cont_m.peak_strain,
        100.0 * relative_error(cont_m.peak_tau, dem_m.peak_tau),
        liq_dem ? fmt::format("at γ = {:.3g}", dem_m.liquefaction_strain) : std::string("no"),
        liq_cont ? fmt::format("at γ = {:.3g}", cont_m.liquefaction_strain) : std::string("no"),
        dem_m.residual_tau, 2.0 * band_err, cont_m.residual_tau,
        within ? " (within the DEM band)" : "");
  }
  sum.set("transient_pair.count", double(conditions.size()));
  ctx.result.flush();
  ctx.plot("plot_transient_pair.py");
  return core::exit_ok;
}

void register_transient_pair_kinds(core::KindRegistry& registry) {
  core::KindEntry entry{"transient_pair", "",
                        "undrained shear from rest, DEM and continuum side by side (one material)",
                        transient_pair_schema(), check_transient_pair_case,
                        run_transient_pair_case, "cases/pair/undrained_loose_pair.yaml"};
  entry.check_inputs = check_transient_pair_inputs;
  entry.distributes_conditions = true;
  registry.add(std::move(entry));
}

}  // namespace granflow::transient_pair
