#include "analysis/pair/pair_kind.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "analysis/calibration/calibration.hpp"
#include "analysis/pair/pair_columns.hpp"
#include "analysis/pair/pair_curves.hpp"
#include "analysis/pair/pair_report.hpp"
#include "continuum/rev/simple_shear.hpp"
#include "continuum/sections/model_sections.hpp"
#include "core/interrupt.hpp"
#include "core/sweep_scheduler.hpp"
#include "dem_coupling/dem_kind.hpp"

namespace granflow::pair {

namespace {

// The DEM case of a pair case: the same file without the continuum-only sections, kind: dem.
// `schema` must outlive the returned Case (it refers to it).
core::Case dem_case(const core::Case& c, const core::Schema& schema) {
  YAML::Node root = YAML::Load(c.resolved_yaml());
  // Continuum-only sections (the DEM schema carries the continuum's liquid section itself).
  for (const char* section : {"collisional", "force_chains", "steady", "calibrate"})
    root.remove(section);
  root["kind"] = "dem";
  YAML::Emitter out;
  out << root;
  return core::Case::parse(out.c_str(), c.origin() + " (DEM part)", {}, schema);
}

// "a b c" -> {"a", "b", "c"}
std::vector<std::string> split_words(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

}  // namespace

int dry_regime(double I) { return I < 1e-3 ? 0 : (I < 0.1 ? 1 : 2); }

// Immersed: viscous when the Stokes number St = I²/J is below 1 (viscous drag outweighs grain
// inertia; Courrech du Pont et al. 2003, Trulsson et al. 2012), otherwise the dry classes by I.
int flow_regime(double I, double J) { return (J > 0 && I * I < J) ? 3 : dry_regime(I); }

const char* regime_name(int regime) {
  switch (regime) {
    case 0:
      return "quasi-static";
    case 1:
      return "dense inertial";
    case 2:
      return "collisional";
    default:
      return "viscous";
  }
}

core::Schema pair_schema() {
  core::Schema s = core::kind_header(
      "pair", "",
      "DEM (kind: dem, LIGGGHTS) and continuum steady simple shear at the same conditions from "
      "one material description; side-by-side table with relative errors and regimes.");
  const core::Schema dem = dem::shear_schema();
  // statistics.seeds stays out: the pair table has one DEM point per condition.
  const std::set<std::string> header = {"kind", "test", "name", "description", "statistics"};
  for (const auto& child : dem.children())
    if (!header.count(child.key())) s.add(child);
  s.add(continuum::collisional_section());
  s.add(continuum::force_chains_section(true));
  s.add(continuum::steady_section());
  // `liquid` comes with the DEM schema: the continuum's own section with a sweepable viscosity.
  auto& cal = s.section("calibrate",
                        "optional: calibrate the continuum on the DEM points just run (every "
                        "other point held out) and show it beside the uncalibrated one");
  cal.string("parameters",
             "parameters to fit (names of kind: calibrate's fit.parameters, separated by "
             "spaces); none: no calibration")
      .default_value("none");
  cal.string("observables", "observables fitted: friction, solid_fraction, scaled_temperature")
      .default_value("friction solid_fraction scaled_temperature");
  cal.integer("starts", "starting points of the fit (as kind: calibrate's fit.starts)")
      .default_value("8")
      .at_least(1);
  return s;
}

void check_pair_case(const core::Case& c) {
  if (c.string("control.mode") == "drained")
    c.fail("control.mode",
           "constant_volume or constant_pressure (a steady pair; drained shear is a transient: "
           "kind: transient_pair)");
  if (c.has("rate_step.strain"))
    c.fail("rate_step.strain",
           "absent (a steady pair; a rate step is a transient: kind: "
           "transient_pair)");
  if (!c.boolean("collisional.enabled"))
    c.fail("collisional.enabled", "true (the continuum side is the collisional steady shear)");
  for (const auto& name : split_words(c.string("calibrate.parameters"))) {
    if (name == "none") continue;
    try {
      const auto& spec = calibration::parameter_spec(name);
      if ((spec.case_key.rfind("force_chains.", 0) == 0 ||
           spec.case_key.rfind("steady.", 0) == 0) &&
          !c.boolean("force_chains.enabled"))
        c.fail(
            "calibrate.parameters",
            fmt::format("'{}' is a force-chain parameter: needs force_chains.enabled: true", name));
    } catch (const std::invalid_argument& e) {
      c.fail("calibrate.parameters", e.what());
    }
  }
  for (const auto& o : split_words(c.string("calibrate.observables"))) try {
      calibration::parse_observable(o);
    } catch (const std::invalid_argument& e) {
      c.fail("calibrate.observables", e.what());
    }
  core::KindRegistry registry;
  dem::register_dem_kinds(registry);
  const auto& entry = registry.find("dem", "", c.origin());
  const core::Case d = dem_case(c, entry.schema);
  if (entry.check) entry.check(d);
}

int run_pair_case(core::RunContext& ctx) {
  const core::Case& c = ctx.run_case;
  auto& log = *ctx.log;
  // ---- DEM side: the dem kind's own run function in RUN_DIR/dem/
  core::KindRegistry registry;
  dem::register_dem_kinds(registry);
  const auto& entry = registry.find("dem", "", c.origin());
  const core::Case d = dem_case(c, entry.schema);
  const auto dem_dir = ctx.directory.path() / "dem";
  log.info("DEM part: kind dem in {} (log: dem/log.txt)", dem_dir.string());
  int code = 0;
  {
    core::RunContext dem_ctx(d, dem_dir, true, false);  // its progress on stderr too
    code = entry.run(dem_ctx);
    // Under mpirun the DEM points were shared out over the ranks (core/sweep_scheduler.hpp); the
    // continuum side, a fraction of a second per point, stays on rank 0 with the outputs.
    if (!core::owns_outputs()) return code;
    if (core::interrupted()) dem_ctx.summary.set("run.interrupted", 1);
    dem_ctx.finish();
  }
  if (core::interrupted()) return code;  // the CLI reports it; dem/ holds the points so far
  if (code != core::exit_ok) {
    log.error("the DEM part failed (exit {}); see {}", code, (dem_dir / "log.txt").string());
    return code;
  }
  const auto data = calibration::read_dem_dataset(dem_dir / "result.h5", 0);
  for (const auto& why : data.skipped) log.warn("DEM {}", why);

  // ---- continuum side: the steady simple shear at each DEM condition (γ̇, measured σ_yy, μ_p)
  // Wet rows carry their own η0; the case's viscosity is the reference (factor 1).
  const calibration::CalibratedModel model = calibration::read_case_model(c);
  // The comparison model: kinetic theory alone (the same sections, force chains off).
  calibration::CalibratedModel kinetic = model;
  kinetic.settings.force_chains = false;
  const bool in_parallel = model.settings.force_chains;
  log.info(
      "continuum: {}",
      in_parallel
          ? fmt::format("in-parallel steady state (force chains on the critical "
                        "state, μ_FC = {:.4g}; docs/model/steady_state.md), beside "
                        "kinetic theory alone",
                        calibration::critical_state_friction(model.settings.force_chain_parameters))
          : std::string("kinetic theory alone (force_chains.enabled: false)"));

  if (const auto caveat = calibration::in_parallel_caveat(model.settings); !caveat.empty())
    log.warn("{}", caveat);
  // ---- optional calibration on the DEM points just run (every other point held out)
  std::vector<std::string> fit_names;
  for (const auto& name : split_words(c.string("calibrate.parameters")))
    if (name != "none") fit_names.push_back(name);
  calibration::CalibratedModel calibrated = model;
  const bool calibrate = !fit_names.empty();
  auto& sum = ctx.summary;
  if (calibrate) {
    std::vector<calibration::Observable> observables;
    for (const auto& o : split_words(c.string("calibrate.observables")))
      observables.push_back(calibration::parse_observable(o));
    std::vector<calibration::DataPoint> training, held;
    for (std::size_t i = 0; i < data.points.size(); ++i)
      (i % 2 ? held : training).push_back(data.points[i]);
    try {
      const auto r = calibration::fit(model, fit_names, training, observables, 4000,
                                      static_cast<int>(c.integer("calibrate.starts")));
      calibrated = calibration::apply(model, fit_names, r.estimate);
      log.info("calibrated on {} of {} points (every other held out): χ²_red {:.4g}",
               training.size(), data.points.size(), r.chi2_red);
      for (std::size_t j = 0; j < fit_names.size(); ++j) {
        log.info("  {} = {:.6g} ± {:.3g} (start {:.6g}){}", fit_names[j], r.estimate[j],
                 r.standard_error[j], r.initial[j],
                 j < r.at_bound.size() && r.at_bound[j] ? " (on its bound)" : "");
        sum.set("pair.fit." + fit_names[j], r.estimate[j]);
        sum.set("pair.fit." + fit_names[j] + "_err", r.standard_error[j]);
      }
      sum.set("pair.fit.chi2_red", r.chi2_red);
      sum.set("pair.fit.inside_domain", r.inside_domain ? 1 : 0);
      for (const auto o : observables) {
        const auto& on = calibration::observable_names()[static_cast<int>(o)];
        sum.set("pair.holdout.rel_err." + on,
                calibration::mean_relative_error(calibrated, held, o));
        sum.set("pair.holdout.rel_err_uncalibrated." + on,
                calibration::mean_relative_error(model, held, o));
      }
    } catch (const std::invalid_argument& e) {
      c.fail("calibrate.parameters", e.what());
    }
  }

  const double d_mean = c.number("material.diameter"),
               rho_p = c.number("material.particle_density");
  const double alpha = c.number("liquid.trulsson_alpha");
  std::vector<std::vector<double>> cols(21);
  enum {
    shear_rate,
    normal_stress,
    mu_dem,
    mu_dem_err,
    mu_cont,
    phi_dem,
    phi_dem_err,
    phi_cont,
    e_dem,
    e_cont,
    T_dem,
    T_dem_err,
    T_cont,
    I_dem,
    I_cont,
    K_dem,
    K_cont,
    rel_mu,
    rel_e,
    rel_T,
    regime
  };
  std::vector<std::vector<double>> rev_cols(3), viscous_cols(3);  // J_dem, J_cont, St
  // Kinetic theory alone, the calibrated model, the share of each term (in-parallel model).
  std::map<std::string, std::vector<double>> extra;
  double max_rev_diff = 0;
  int n = 0;
  for (const auto& p : data.points) {
    const auto s = calibration::predict(model, p);
    const auto s_kt = calibration::predict(kinetic, p);
    // Second path: the time-stepped REV (rev::run_simple_shear, constant_pressure) at the same
    // condition for kinetic theory alone; tests/calibration shows the two agree to 1e-7, here it
    // is recorded per point.
    double mu_rev = NAN, T_rev = NAN, phi_rev = NAN;
    try {
      continuum::MultiRegimeSettings rs = kinetic.settings;
      if (std::isfinite(p.particle_friction))
        rs.collisional_parameters.particle_friction = p.particle_friction;
      if (rs.liquid && std::isfinite(p.liquid_viscosity))
        rs.liquid_parameters.viscosity = p.liquid_viscosity;  // the condition's η0 (wet sweeps)
      rev::SimpleShearControl control;
      control.shear_rate = p.shear_rate;
      if (p.protocol == calibration::Protocol::constant_volume) {  // at the DEM's φ
        control.control = rev::ShearControl::constant_volume;
        control.void_ratio = 1.0 / p.value[1] - 1.0;
      } else {
        control.control = rev::ShearControl::constant_pressure;
        control.normal_stress = p.normal_stress;
      }
      const auto r = rev::run_simple_shear(continuum::MultiRegimePoint(rs), control);
      if (r.steady.reached)
        mu_rev = r.steady.friction, T_rev = r.steady.granular_temperature,
        phi_rev = r.steady.solid_fraction;
    } catch (const std::exception& e) {
      log.warn("point {}: REV simple shear failed: {}", n, e.what());
    }
    rev_cols[0].push_back(mu_rev);
    rev_cols[1].push_back(phi_rev);
    rev_cols[2].push_back(T_rev);
    if (s_kt.ok && std::isfinite(mu_rev))
      max_rev_diff = std::max({max_rev_diff, std::abs(mu_rev / s_kt.friction - 1),
                               std::abs(phi_rev / s_kt.solid_fraction - 1),
                               std::abs(T_rev / s_kt.granular_temperature - 1)});
    const double scale = std::pow(d_mean * p.shear_rate, 2);  // T = T* (d γ̇)²
    const double T_d = p.value[2] * scale, T_c = s.ok ? s.granular_temperature : NAN;
    const double phi = p.value[1];
    const double e_d = 1.0 / phi - 1.0, e_c = s.ok ? 1.0 / s.solid_fraction - 1.0 : NAN;
    const double mu_c = s.ok ? s.friction : NAN;
    const double I_d = p.shear_rate * d_mean / std::sqrt(p.normal_stress / rho_p);
    // Viscous number J = η0 γ̇ / σ_yy (Boyer et al. 2011); 0 for a dry condition.
    const double eta0 = std::isfinite(p.liquid_viscosity) ? p.liquid_viscosity : 0.0;
    const double J_d = eta0 * p.shear_rate / p.normal_stress, J_c = s.ok ? s.viscous_number : NAN;
    viscous_cols[0].push_back(J_d);
    viscous_cols[1].push_back(J_c);
    viscous_cols[2].push_back(J_d > 0 ? I_d * I_d / J_d : INFINITY);
    const double row[21] = {p.shear_rate,
                            p.normal_stress,
                            p.value[0],
                            p.error[0],
                            mu_c,
                            phi,
                            p.error[1],
                            s.ok ? s.solid_fraction : NAN,
                            e_d,
                            e_c,
                            T_d,
                            p.error[2] * scale,
                            T_c,
                            I_d,
                            s.ok ? s.inertial_number : NAN,
                            J_d + alpha * I_d * I_d,  // K = J + α I² (Trulsson et al. 2012)
                            s.ok ? J_c + alpha * s.inertial_number * s.inertial_number : NAN,
                            mu_c / p.value[0] - 1.0,
                            e_c / e_d - 1.0,
                            T_c / T_d - 1.0,
                            double(flow_regime(I_d, J_d))};
    for (int k = 0; k < 21; ++k) cols[k].push_back(row[k]);
    const auto ok = [](const calibration::SteadyShearState& st, double v) {
      return st.ok ? v : NAN;
    };
    const double tau = s.shear_stress,
                 p_total = s.force_chain_normal_stress + s.collisional_pressure;
    const std::map<std::string, double> more = {
        {"friction_kt", ok(s_kt, s_kt.friction)},
        {"solid_fraction_kt", ok(s_kt, s_kt.solid_fraction)},
        {"granular_temperature_kt", ok(s_kt, s_kt.granular_temperature)},
        {"share_tau_fc", ok(s, s.force_chain_shear_stress / tau)},
        {"share_tau_col", ok(s, s.collisional_shear_stress / tau)},
        {"share_tau_liq", ok(s, s.liquid_shear_stress / tau)},
        {"share_p_fc", ok(s, s.force_chain_normal_stress / p_total)},
        // σ_yy of the continuum: the imposed one at constant pressure, its prediction at the
        // DEM's φ at constant volume
        {"normal_stress_cont", ok(s, s.normal_stress)},
        {"normal_stress_rel_err", ok(s, s.normal_stress / p.normal_stress - 1.0)}};
    for (const auto& [name, value] : more) extra[name].push_back(value);
    const std::string key = fmt::format("pair.{}.", n);
    if (calibrate) {
      const auto s_cal = calibration::predict(calibrated, p);
      extra["friction_cal"].push_back(ok(s_cal, s_cal.friction));
      extra["solid_fraction_cal"].push_back(ok(s_cal, s_cal.solid_fraction));
      extra["granular_temperature_cal"].push_back(ok(s_cal, s_cal.granular_temperature));
      extra["held_out"].push_back(n % 2 ? 1.0 : 0.0);
      sum.set(key + "mu_cal", ok(s_cal, s_cal.friction));
      sum.set(key + "rel_err_mu_cal", ok(s_cal, s_cal.friction / p.value[0] - 1.0));
      sum.set(key + "T_cal", ok(s_cal, s_cal.granular_temperature));
    }
    sum.set(key + "mu_dem", p.value[0]);
    sum.set(key + "mu_dem_err", p.value[0] > 0 ? p.error[0] : NAN);
    sum.set(key + "mu_cont", mu_c);
    sum.set(key + "T_dem", T_d);
    sum.set(key + "T_cont", T_c);
    sum.set(key + "e_dem", e_d);
    sum.set(key + "e_cont", e_c);
    sum.set(key + "rel_err_mu", row[rel_mu]);
    sum.set(key + "I_dem", I_d);
    sum.set(key + "p_cont", more.at("normal_stress_cont"));
    if (in_parallel) {
      sum.set(key + "mu_kt", more.at("friction_kt"));
      sum.set(key + "share_tau_fc", more.at("share_tau_fc"));
    }
    if (J_d > 0) sum.set(key + "J_dem", J_d), sum.set(key + "J_cont", J_c);
    sum.set(key + "regime", row[regime]);
    log.info(
        "point {}: γ̇ = {:g} 1/s, I = {:.3g} ({}): μ DEM {:.4g} ± {:.2g} vs continuum {:.4g} "
        "({:+.1f} %; kinetic theory alone {:.4g}), e {:.4g} vs {:.4g}, T {:.3g} vs {:.3g} m²/s², "
        "σ_yy {:.4g} vs {:.4g} Pa, τ carried {:.0f} % by the force chains{}",
        n, p.shear_rate, I_d, regime_name(flow_regime(I_d, J_d)), p.value[0], p.error[0], mu_c,
        100 * row[rel_mu], more.at("friction_kt"), e_d, e_c, T_d, T_c, p.normal_stress,
        more.at("normal_stress_cont"), 100 * more.at("share_tau_fc"),
        s.ok ? "" : fmt::format(" ({})", s.why));
    ++n;
  }
  sum.set("pair.count", n);
  sum.set("pair.rev_vs_algebraic_max_rel_diff", max_rev_diff);
  log.info(
      "kinetic theory alone by two paths (algebraic steady state vs time-stepped REV): largest "
      "relative difference of μ, φ, T {:.2g}",
      max_rev_diff);
  // The /pair table, QUANTITY_SOURCE names (pair_columns.hpp).
  auto write = [&](const std::string& name, const std::vector<double>& values) {
    const PairColumn column = pair_column(name);
    ctx.result.write("/pair/" + name, values, column.unit, column.description);
  };
  write("viscous_number_dem", viscous_cols[0]);
  write("viscous_number_cont", viscous_cols[1]);
  ctx.result.write("/pair",
                   core::columns::described(core::columns::stokes_number,
                                            "Stokes number I²/J of the DEM point (inf dry)"),
                   viscous_cols[2]);
  write("friction_rev", rev_cols[0]);
  write("solid_fraction_rev", rev_cols[1]);
  write("granular_temperature_rev", rev_cols[2]);
  const char* names[21] = {"shear_rate",
                           "normal_stress",
                           "friction_dem",
                           "friction_dem_err",
                           "friction_cont",
                           "solid_fraction_dem",
                           "solid_fraction_dem_err",
                           "solid_fraction_cont",
                           "void_ratio_dem",
                           "void_ratio_cont",
                           "granular_temperature_dem",
                           "granular_temperature_dem_err",
                           "granular_temperature_cont",
                           "inertial_number_dem",
                           "inertial_number_cont",
                           "mixed_number_dem",
                           "mixed_number_cont",
                           "friction_rel_err",
                           "void_ratio_rel_err",
                           "granular_temperature_rel_err",
                           "regime"};
  for (int k = 0; k < 21; ++k) {
    if (k == shear_rate || k == normal_stress) {
      ctx.result.write("/pair",
                       k == shear_rate ? core::columns::shear_rate
                                       : core::columns::described(core::columns::normal_stress,
                                                                  "σ_yy of the DEM point"),
                       cols[k]);
    } else if (k == regime) {
      ctx.result.write("/pair/regime", std::vector<long>(cols[k].begin(), cols[k].end()), "1",
                       "regime of the DEM point: 0 quasi-static (I < 1e-3), 1 dense inertial, 2 "
                       "collisional (I >= 0.1), 3 viscous (St = I²/J < 1)");
    } else {
      write(names[k], cols[k]);
    }
  }
  for (const auto& [name, values] : extra) {
    if (name == "held_out") {
      ctx.result.write("/pair/held_out", std::vector<long>(values.begin(), values.end()), "1",
                       "1: left out of the calibration (calibrate section), 0: fitted");
    } else if (name.rfind("share_", 0) == 0) {
      ctx.result.write("/pair/" + name, values, "1",
                       name == "share_p_fc"
                           ? "σ_yy,FC/(σ_yy,FC + p_COL), the force chains' share "
                             "of the normal stress (continuum)"
                           : "share of τ carried by the " +
                                 std::string(name == "share_tau_fc"    ? "force chains"
                                             : name == "share_tau_col" ? "collisions"
                                                                       : "liquid") +
                                 " (continuum)");
    } else {
      write(name, values);
    }
  }
  write_model_curves(ctx, data.points, model, kinetic, calibrate ? &calibrated : nullptr);
  write_viscous_curves(ctx, data.points, model, kinetic, calibrate ? &calibrated : nullptr);
  ctx.plot("plot_pair.py");
  return core::exit_ok;
}

void register_pair_kinds(core::KindRegistry& registry) {
  core::KindEntry entry{"pair",
                        "",
                        "DEM and continuum steady simple shear side by side (one material)",
                        pair_schema(),
                        check_pair_case,
                        run_pair_case,
                        "cases/pair/dry_pair.yaml"};
  entry.distributes_conditions = true;
  entry.report = pair_report_section;
  registry.add(std::move(entry));
}

}  // namespace granflow::pair
