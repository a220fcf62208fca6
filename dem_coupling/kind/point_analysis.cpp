#include "dem_coupling/kind/point_analysis.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <span>

#include "dem_coupling/kind/dem_columns.hpp"
#include "dem_coupling/kind/dem_fits.hpp"
#include "dem_coupling/kind/series_table.hpp"
#include "dem_coupling/kind/steady_checks.hpp"
#include "statistics/steady_state.hpp"

namespace granflow::dem {

namespace {

// Steady value of one series: MSER start (given), mean and a standard error that accounts for
// the correlation of the samples (statistics::correlated_mean).
struct Steady {
  double mean, error;
};
Steady steady_of(const std::vector<double>& series, std::size_t start) {
  const auto e = statistics::correlated_mean(std::span(series).subspan(start));
  return {e.mean, e.standard_error};
}

// strain.target_error: the strain the point used and its errors against the targets, as
// PointResult::run_length, /conditions/N attributes (named by dem_run_length_name,
// dem_columns.hpp: strain_used, strain_max, target_met, target_error_NAME, achieved_error_NAME,
// target_met_NAME) and a log line.
void report_targets(const SteadyWindow& window, const ShearDeckParams& p, PointResult& r,
                    const std::string& group, core::ResultFile& out) {
  const TargetStatus status = target_status(window, p.targets);
  const double used = r.values["end_strain"];
  r.run_length["used"] = used;
  r.run_length["max"] = p.total_strain;
  r.run_length["target_met"] = status.all_met ? 1.0 : 0.0;
  out.attribute(group, dem_run_length_name("used"), used);
  out.attribute(group, dem_run_length_name("max"), p.total_strain);
  out.attribute(group, dem_run_length_name("target_met"), status.all_met ? 1L : 0L);
  std::string met, missed;
  for (std::size_t k = 0; k < target_observables.size(); ++k) {
    const double target = p.targets.error[k];
    if (!(target > 0.0)) continue;
    const std::string name = target_observables[k];
    const double achieved = status.achieved[k];
    r.run_length["target_error." + name] = target;
    if (std::isfinite(achieved)) r.run_length["achieved_error." + name] = achieved;
    r.run_length["target_met." + name] = status.met[k] ? 1.0 : 0.0;
    out.attribute(group, dem_run_length_name("target_error." + name), target);
    out.attribute(group, dem_run_length_name("achieved_error." + name), achieved);
    out.attribute(group, dem_run_length_name("target_met." + name), status.met[k] ? 1L : 0L);
    std::string& list = status.met[k] ? met : missed;
    list +=
        fmt::format("{}{} {:.3g} (target {:g})", list.empty() ? "" : ", ", name, achieved, target);
  }
  if (status.all_met) {
    r.notes.push_back(
        fmt::format("strain.target_error met at strain {:.4g} (strain.max {:g}): steady, errors {}",
                    used, p.total_strain, met));
    return;
  }
  r.warnings.push_back(
      fmt::format("strain.target_error NOT met: stopped at strain.max = {:g} (strain {:.4g}){}{}{}",
                  p.total_strain, used, missed.empty() ? "" : "; missed: " + missed,
                  met.empty() ? "" : "; met: " + met,
                  window.reached ? "" : "; the window is not steady (see the drift warnings)"));
}

}  // namespace

PointResult analyse_point(core::RunContext& ctx, const std::filesystem::path& dir,
                          const std::string& group, const ShearDeckParams& p,
                          const ShearDeck& deck) {
  PointResult r;
  SeriesTable t = read_series_table(dir / "series.tsv");
  auto& out = ctx.result;
  if (t.rows() > 0) {
    for (const DemColumn& c : dem_columns::series)
      out.write(group + "/series", c.column, t.at(c.key));
    if (p.wet.enabled)
      for (const DemColumn& c : dem_columns::wet_series)
        out.write(group + "/series", c.column, t.at(c.key));
    const SeriesTable prof = read_series_table(dir / "profile.tsv", false);
    if (prof.rows() > 0 && prof.names.size() > 2) {
      const std::size_t bins = prof.names.size() - 2;
      std::vector<double> matrix;
      matrix.reserve(prof.rows() * bins);
      for (std::size_t i = 0; i < prof.rows(); ++i)
        for (std::size_t b = 0; b < bins; ++b) matrix.push_back(prof.at(std::to_string(b + 2))[i]);
      out.write_matrix(group + "/profile/velocity", matrix, prof.rows(), bins, "m/s",
                       "mean v_x per y bin (rows: samples, cols: bins from ylo up)");
      out.write(group + "/profile/strain", prof.at("1"), "1", "shear strain of each row");
    }
    // The series above keep the stop's rows (stop.duration); the analysis below is the shear's.
    if (p.stop_duration > 0.0) {
      const std::size_t sheared = shear_rows(t.at("strain"));
      for (auto& [name, column] : t.columns) column.resize(sheared);
    }
  }
  out.attribute(group, dem_columns::time_step.name, deck.dt);
  out.attribute(group, "time_step_limit", deck.dt_limit);
  if (p.wet.enabled) {
    out.attribute(group, core::columns::liquid_viscosity.name, p.wet.viscosity);
    out.attribute(group, "minimum_gap", p.wet.minimum_gap * p.material.diameter);
    out.attribute(group, "maximum_gap", p.wet.maximum_gap * p.material.diameter);
    out.attribute(group, "permeability", p.wet.permeability);
  }
  out.attribute(group, "rayleigh_time", deck.times.rayleigh);
  out.attribute(group, "hertz_time", deck.times.hertz);
  out.attribute(group, "contact_law",
                p.material.contact_law == ContactLaw::hooke ? "hooke" : "hertz");
  if (p.material.contact_law == ContactLaw::hooke) {
    out.attribute(group, "linear_spring_contact_time", deck.times.linear_spring);
    out.attribute(group, "normal_stiffness", p.material.normal_stiffness);
  }
  out.attribute(group, "shear_rate", p.shear_rate);
  out.attribute(group, "mean_diameter", deck.mean_diameter);
  out.attribute(group, "particles", static_cast<long>(p.particles));
  out.attribute(group, "particle_friction", p.material.particle_friction);
  out.attribute(group, "restitution", p.material.restitution);
  out.attribute(group, "control", p.constant_pressure ? "constant_pressure" : "constant_volume");
  if (p.constant_pressure)
    out.attribute(group, "normal_stress_target", p.normal_stress);
  else
    out.attribute(group, "solid_fraction_target", p.solid_fraction);
  out.flush();
  r.dt = deck.dt;
  r.particles = double(p.particles);
  if (t.rows() < 8) return r;

  // The steady window, μ and the main errors (kind/steady_checks.hpp: the one definition that
  // granflow-dem's stopping rule for strain.target_error also uses).
  const double d = deck.mean_diameter;
  const SteadyWindow window = steady_window(t.columns, d * p.shear_rate * d * p.shear_rate);
  const std::size_t start = window.start;
  const auto& sigma = t.at("sigma_yy");
  const Steady s_sigma{window.sigma.mean, window.sigma.standard_error};
  const Steady s_tau{window.tau.mean, window.tau.standard_error};
  const double mu = window.mu;
  const std::vector<double>& residual = window.mu_residual;
  const double mu_err = window.mu_err;
  const Steady s_phi{window.phi.mean, window.phi.standard_error};
  const Steady s_T{window.temperature.mean, window.temperature.standard_error};
  const Steady s_p = steady_of(t.at("p"), start);
  const Steady s_Z = steady_of(t.at("Z"), start);
  const Steady s_dev = steady_of(t.at("profile_deviation"), start);
  const double inertial = p.shear_rate * d / std::sqrt(s_sigma.mean / p.material.particle_density);
  auto& v = r.values;
  v["mu"] = mu;
  v["mu_err"] = mu_err;
  v["phi"] = s_phi.mean;
  v["phi_err"] = s_phi.error;
  v["e"] = 1.0 / s_phi.mean - 1.0;
  v["e_err"] = s_phi.error / (s_phi.mean * s_phi.mean);
  v["T"] = s_T.mean;
  v["T_err"] = s_T.error;
  v["T_scaled"] = window.scaled_temperature;
  v["p"] = s_sigma.mean;
  v["p_err"] = s_sigma.error;
  v["p_mean"] = s_p.mean;
  v["p_mean_err"] = s_p.error;
  v["tau"] = s_tau.mean;
  v["tau_err"] = s_tau.error;
  v["I"] = inertial;
  v["I_err"] = 0.5 * inertial * s_sigma.error / s_sigma.mean;  // I ∝ σ^(-1/2)
  v["Z"] = s_Z.mean;
  v["Z_err"] = s_Z.error;
  v["profile_deviation"] = s_dev.mean;
  if (t.columns.count("overlap")) {  // how soft the sample is: <δ>/d (granflow-dem's overlap)
    const Steady s_overlap = steady_of(t.at("overlap"), start);
    v["overlap"] = s_overlap.mean / d;
    v["overlap_err"] = s_overlap.error / d;
  }
  v["start_strain"] = t.at("strain")[start];
  v["end_strain"] = t.at("strain").back();
  v["samples"] = double(t.rows() - start);
  v["tau_int_mu"] =
      statistics::integrated_autocorrelation_time(std::span<const double>(residual).subspan(start));
  if (p.constant_pressure) {
    // The servo holds the mean σ_yy (extraction/normal_stress_servo.hpp); a miss of more than
    // max_target_miss standard errors is flagged (kind/steady_checks.hpp).
    v["p_rel_dev"] = s_sigma.mean / p.normal_stress - 1.0;
    const double miss = s_sigma.error > 0.0 ? (s_sigma.mean - p.normal_stress) / s_sigma.error
                                            : std::numeric_limits<double>::quiet_NaN();
    v["normal_stress_miss_se"] = miss;
    v["normal_stress_on_target"] = std::abs(miss) <= max_target_miss ? 1.0 : 0.0;
    if (!(std::abs(miss) <= max_target_miss))
      r.warnings.push_back(fmt::format(
          "steady σ_yy = {:.4g} ± {:.2g} Pa misses the imposed {:g} Pa by {:.1f} standard errors "
          "({:+.1f} %)",
          s_sigma.mean, s_sigma.error, p.normal_stress, miss, 100.0 * v["p_rel_dev"]));
  }
  // Steady means steady: no observable may drift over the window (kind/steady_checks.hpp).
  const SteadyCheck& check = window.check;
  // A sample whose T never leaves ~0 (spheres on streamlines, no collisions) has steady-looking
  // series of nothing: flagged frozen and not steady (steady_checks.hpp, frozen_temperature).
  const bool frozen = window.frozen;
  v["frozen"] = frozen ? 1.0 : 0.0;
  if (frozen)
    r.warnings.push_back(fmt::format(
        "NOT steady: frozen, T/(d γ̇)² = {:.3g} < {:g}: the spheres move on the streamlines "
        "without colliding (start it with velocity fluctuations, control.initial_temperature)",
        v["T_scaled"], frozen_temperature));
  v["reached"] = window.reached ? 1.0 : 0.0;
  v["drift_max"] = check.worst;
  for (const auto& [key, z] : check.drift) {
    if (std::isfinite(z)) v["drift." + key] = z;
    const std::string name = key == "p" ? "σ_yy (p)" : key == "p_mean" ? "tr(P)/3 (p_mean)" : key;
    if (!std::isfinite(z))
      r.warnings.push_back(fmt::format(
          "NOT steady: the window from strain {:.3g} is too short to test {} for a drift",
          v["start_strain"], name));
    else if (std::abs(z) > max_drift)
      r.warnings.push_back(fmt::format(
          "NOT steady: {} drifts over the window (strain {:.3g}-{:.3g}): second half − first half "
          "= {:.1f} standard errors (limit {:g}); run longer (strain.total) or read the value as "
          "a transient",
          name, v["start_strain"], v["end_strain"], z, max_drift));
  }
  if (p.targets.any()) report_targets(window, p, r, group, out);
  if (p.wet.enabled) {
    // Viscous number J = η0 γ̇ / σ_yy (Boyer et al. 2011), Stokes number St = ρ_p d² γ̇ / η0 = I²/J,
    // K = J + α I² (Trulsson et al. 2012). Errors from that of σ_yy (J ∝ 1/σ, I² ∝ 1/σ).
    const double eta = p.wet.viscosity;
    const double viscous = eta * p.shear_rate / s_sigma.mean;
    const double rel = s_sigma.error / s_sigma.mean;
    const double alpha = p.wet.trulsson_alpha;
    v["eta"] = eta;
    v["St"] = p.material.particle_density * d * d * p.shear_rate / eta;
    v["J"] = viscous;
    v["J_err"] = viscous * rel;
    v["K"] = viscous + alpha * inertial * inertial;
    v["K_err"] = v["K"] * rel;
    for (const char* part : {"tau_contact", "tau_lub", "tau_drag", "tau_kin"}) {
      const Steady s_part = steady_of(t.at(part), start);
      v[part] = s_part.mean;
      v[std::string(part) + "_err"] = s_part.error;
    }
    // Stress ratios of the parts, for Boyer's μ_c(J) and μ_h(J) (kind/dem_fits.hpp).
    const StressRatio contact = stress_ratio_of_series(t.at("tau_contact"), sigma, start);
    const StressRatio lub = stress_ratio_of_series(t.at("tau_lub"), sigma, start);
    v["mu_contact"] = contact.value;
    v["mu_contact_err"] = contact.error;
    v["mu_lub"] = lub.value;
    v["mu_lub_err"] = lub.error;
  }
  // Named as the /steady columns (kind/dem_columns.hpp); counts and flags as integers.
  for (const auto& [key, value] : v) {
    if (dem_steady_integer(key))
      out.attribute(group + "/steady", dem_steady_name(key), std::lround(value));
    else
      out.attribute(group + "/steady", dem_steady_name(key), value);
  }
  return r;
}

void write_seed_statistics(core::RunContext& ctx, const std::vector<SeedGroup>& groups,
                           const std::vector<PointResult>& results) {
  if (groups.empty()) return;
  struct Observable {
    const char *key, *unit, *doc;
  };
  constexpr Observable observables[] = {
      {"mu", "1", "μ"},      {"phi", "1", "φ"},   {"e", "1", "e"},
      {"T", "m^2/s^2", "T"}, {"p", "Pa", "σ_yy"}, {"p_mean", "Pa", "tr(P)/3"},
      {"tau", "Pa", "τ"},    {"I", "1", "I"},     {"Z", "1", "Z"}};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto get = [&](std::size_t n, const std::string& key) {
    if (n >= results.size()) return nan;
    const auto it = results[n].values.find(key);
    return it != results[n].values.end() ? it->second : nan;
  };
  std::map<std::string, std::vector<double>> columns;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    std::map<std::string, SeedCombined> combined;
    for (const Observable& o : observables) {
      std::vector<double> v, e;
      for (std::size_t n : groups[g].members) {
        v.push_back(get(n, o.key));
        e.push_back(get(n, std::string(o.key) + "_err"));
      }
      const SeedCombined c = combine_seeds(v, e);
      combined[o.key] = c;
      const std::string k = o.key;
      columns[k].push_back(c.mean);
      columns[k + "_err"].push_back(c.error);
      columns[k + "_within_err"].push_back(c.within);
      columns[k + "_scatter_ratio"].push_back(c.scatter_ratio);
      for (const auto& [name, value] :
           {std::pair{k, c.mean}, {k + "_err", c.error}, {k + "_scatter_ratio", c.scatter_ratio}})
        if (std::isfinite(value)) ctx.summary.set(fmt::format("seeds.{}.{}", name, g), value);
    }
    ctx.summary.set(fmt::format("seeds.count.{}", g), double(combined["mu"].seeds));
    columns["seeds"].push_back(double(combined["mu"].seeds));
    std::string label;
    for (const auto& [key, value] : groups[g].condition) {
      label += fmt::format(" {}={:g}", key, value);
      columns[key].push_back(value);
    }
    const auto& mu = combined["mu"];
    const auto& phi = combined["phi"];
    const auto& p = combined["p"];
    const auto& t = combined["T"];
    ctx.log->info(
        "seeds{}: {} seeds: μ = {:.4f} ± {:.4f}, φ = {:.4f} ± {:.4f}, σ_yy = {:.4g} ± {:.2g} Pa, "
        "T = {:.4g} ± {:.2g} m²/s² (mean ± between-seed standard error; between-seed / per-run "
        "error: μ {:.2f}, φ {:.2f}, σ_yy {:.2f}, T {:.2f})",
        label, mu.seeds, mu.mean, mu.error, phi.mean, phi.error, p.mean, p.error, t.mean, t.error,
        mu.scatter_ratio, phi.scatter_ratio, p.scatter_ratio, t.scatter_ratio);
  }
  ctx.summary.set("seeds.groups", double(groups.size()));
  // Named as the /steady columns (kind/dem_columns.hpp): NAME, NAME_err, NAME_within_err,
  // NAME_scatter_ratio; a swept key keeps its case-file name.
  for (const auto& [key, values] : columns) {
    std::string name = key, unit = "1", doc = "swept key of the group";
    for (const Observable& o : observables) {
      const std::string k = o.key, n = dem_steady_name(o.key);
      if (key == k) name = n, unit = o.unit, doc = std::string(o.doc) + ": mean over the seeds";
      if (key == k + "_err")
        name = n + "_err", unit = o.unit,
        doc = std::string(o.doc) + ": between-seed standard error s/sqrt(N)";
      if (key == k + "_within_err")
        name = n + "_within_err", unit = o.unit,
        doc = std::string(o.doc) + ": per-run errors alone, rms/sqrt(N)";
      if (key == k + "_scatter_ratio")
        name = n + "_scatter_ratio", doc = std::string(o.doc) + ": between-seed / per-run";
    }
    if (key == "seeds") {
      std::vector<long> counts(values.begin(), values.end());
      ctx.result.write("/seeds/seeds", counts, "1", "seeds with a steady value");
      continue;
    }
    ctx.result.write("/seeds/" + name, values, unit, doc);
  }
  ctx.result.flush();
}

}  // namespace granflow::dem
