// The `mpm` / `rheometer` run (docs/rheometer.md): the seed's undrained constant-volume annular
// rheometer with the multi-regime material (rheometer.hpp builds it), its averaged series, crowns,
// radial profiles and summary.
#include "continuum/mpm/kind_rheometer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "continuum/mpm/kind_geometry.hpp"
#include "continuum/mpm/kind_run.hpp"
#include "continuum/mpm/rheometer.hpp"
#include "continuum/sections/model_sections.hpp"

namespace granflow::mpm::kind {

namespace {

// The series of a run, one value per sample (on `time`); a restart continues them all (the
// summaries are taken over them) from the history, rheometer.series.<name>.
struct RheometerSeries {
  static constexpr int crowns = 3;
  std::vector<double> time, tau, sigma_G, gamma, gamma_dot, mixture_volume, pore_pressure,
      porosity_std, fluidized_fraction, temperature;
  // Numerics diagnostics: Δt and its limits, the largest ν and T, the clamp counter.
  std::vector<double> dt, dt_wave, dt_conduction, solid_fraction_max, temperature_max,
      clamped_updates, pore_pressure_std, radial_velocity_rms;
  // Crowns (inner r < R_in + L/3, middle, outer r > R_out − L/3): where strain starts, which
  // crown compacts, which fluidizes first (seed Figs. 4-6; docs/rheometer.md).
  struct Crown {
    std::vector<double> shear_strain, porosity, locus_size, fluidized_fraction;
  };
  std::array<Crown, crowns> crown;
  static constexpr const char* crown_name[crowns] = {"inner", "middle", "outer"};

  // Every series by its history name.
  std::vector<std::pair<std::string, std::vector<double>*>> named() {
    std::vector<std::pair<std::string, std::vector<double>*>> v = {
        {"time", &time},
        {"tau", &tau},
        {"sigma_G", &sigma_G},
        {"gamma", &gamma},
        {"gamma_dot", &gamma_dot},
        {"mixture_volume", &mixture_volume},
        {"pore_pressure", &pore_pressure},
        {"porosity_std", &porosity_std},
        {"fluidized_fraction", &fluidized_fraction},
        {"temperature", &temperature},
        {"dt", &dt},
        {"dt_wave", &dt_wave},
        {"dt_conduction", &dt_conduction},
        {"solid_fraction_max", &solid_fraction_max},
        {"temperature_max", &temperature_max},
        {"clamped_updates", &clamped_updates},
        {"pore_pressure_std", &pore_pressure_std},
        {"radial_velocity_rms", &radial_velocity_rms},
    };
    for (int k = 0; k < crowns; ++k) {
      const std::string name = fmt::format("crown_{}.", k);
      v.emplace_back(name + "shear_strain", &crown[k].shear_strain);
      v.emplace_back(name + "porosity", &crown[k].porosity);
      v.emplace_back(name + "locus_size", &crown[k].locus_size);
      v.emplace_back(name + "fluidized_fraction", &crown[k].fluidized_fraction);
    }
    return v;
  }

  // /series/* and /crowns/<name>/* (on /series/time) of result.h5.
  void write(core::ResultFile& result) const {
    result.write("/series/time", time, "s", "time");
    result.write("/series/tau", tau, "Pa", "averaged shear stress τ̄ = <σ_rθ> of the solid");
    result.write("/series/sigma_G", sigma_G, "Pa", "averaged mean solid stress σ̄_G (compr. +)");
    result.write("/series/gamma", gamma, "1", "averaged shear strain γ̄");
    result.write("/series/gamma_dot", gamma_dot, "1/s", "averaged shear rate <γ̇_rθ>");
    result.write("/series/mixture_volume", mixture_volume, "m^2", "Σ V of the solid points");
    result.write("/series/pore_pressure", pore_pressure, "Pa", "mean pore pressure");
    result.write("/series/porosity_std", porosity_std, "1", "standard deviation of n");
    result.write("/series/fluidized_fraction", fluidized_fraction, "1",
                 "volume fraction with r_c = 0");
    result.write("/series/temperature", temperature, "m^2/s^2", "mean T of the solid points");
    result.write("/series/temperature_max", temperature_max, "m^2/s^2",
                 "largest T of a solid point");
    result.write("/series/solid_fraction_max", solid_fraction_max, "1",
                 "largest ν of a solid point");
    result.write("/series/pore_pressure_std", pore_pressure_std, "Pa",
                 "rms of p about its mean over each ring of cells (θ-dependent part)");
    result.write("/series/radial_velocity_rms", radial_velocity_rms, "m/s", "rms of the solid v_r");
    result.write("/series/dt", dt, "s", "time step");
    result.write("/series/dt_wave", dt_wave, "s", "critical step of the wave speed");
    result.write("/series/dt_conduction", dt_conduction, "s", "critical step of T conduction");
    result.write("/series/clamped_updates", clamped_updates, "1",
                 "point updates evaluated at ν_lim so far (multi-regime guard)");
    for (int k = 0; k < crowns; ++k) {
      const std::string g = fmt::format("/crowns/{}", crown_name[k]);  // on /series/time
      result.write(g + "/shear_strain", crown[k].shear_strain, "1", "crown mean of γ_rθ");
      result.write(g + "/porosity", crown[k].porosity, "1", "crown mean of n");
      result.write(g + "/locus_size", crown[k].locus_size, "Pa", "crown mean of r_c");
      result.write(g + "/fluidized_fraction", crown[k].fluidized_fraction, "1",
                   "crown fraction r_c = 0");
    }
  }
};

// The profile arrays of result.h5 and of the history, by name.
std::array<std::pair<const char*, std::vector<double>*>, 7> profile_arrays(RheometerProfiles& pr) {
  return {{
      {"radius", &pr.radius},
      {"shear_strain", &pr.shear_strain},
      {"velocity", &pr.velocity},
      {"shear_stress", &pr.shear_stress},
      {"porosity", &pr.porosity},
      {"locus_size", &pr.locus_size},
      {"fluidized_fraction", &pr.fluidized_fraction},
  }};
}

// The rheometer's summary keys and its closing log line: peak, steady means over the last
// run.steady_fraction of the run, final crown values, volume and pore pressure drifts.
void rheometer_summary(core::RunContext& ctx, const RheometerSeries& se, const RheometerSpec& spec,
                       const RheometerProfiles& at_peak, double end_time, double clamped) {
  const core::Case& c = ctx.run_case;
  constexpr int crowns = RheometerSeries::crowns;
  const auto& t_s = se.time;
  const auto& tau_s = se.tau;
  const auto& sg_s = se.sigma_G;
  const auto& rate_s = se.gamma_dot;
  const auto& vol_s = se.mixture_volume;
  const auto& pw_s = se.pore_pressure;
  // steady values: means over the last fraction of the run
  const double t_steady = end_time * (1.0 - c.number("run.steady_fraction"));
  double tau_st = 0, sg_st = 0, rate_st = 0;
  int m = 0;
  for (std::size_t k = 0; k < t_s.size(); ++k) {
    if (t_s[k] < t_steady) continue;
    tau_st += tau_s[k];
    sg_st += sg_s[k];
    rate_st += rate_s[k];
    ++m;
  }
  m = std::max(m, 1);
  const std::size_t ipeak =
      static_cast<std::size_t>(std::max_element(tau_s.begin(), tau_s.end()) - tau_s.begin());
  const double vmax_dev = [&]() {
    double d = 0;
    for (double v : vol_s) d = std::max(d, std::fabs(v - vol_s.front()) / vol_s.front());
    return d;
  }();
  // max |p̄ − u_w0| relative to u_w0 (to p'0 when the initial pore pressure is 0)
  const double pw_dev = [&]() {
    double d = 0;
    for (double p : pw_s) d = std::max(d, std::fabs(p - pw_s.front()));
    return d / (std::fabs(pw_s.front()) > 0 ? std::fabs(pw_s.front()) : spec.effective_pressure);
  }();
  auto& sum = ctx.summary;
  sum.set("peak.tau", tau_s[ipeak]);
  sum.set("time.peak", t_s[ipeak]);
  sum.set("peak.sigma_G", *std::max_element(sg_s.begin(), sg_s.end()));
  sum.set("steady.tau", tau_st / m);
  sum.set("steady.sigma_G", sg_st / m);
  sum.set("steady.gamma_dot", rate_st / m);
  sum.set("final.gamma", se.gamma.back());
  sum.set("fluidized_fraction.final", se.fluidized_fraction.back());
  sum.set("porosity.std.final", se.porosity_std.back());
  sum.set("volume.mixture_rel_change_max", vmax_dev);
  sum.set("pore_pressure.mean_rel_change", pw_dev);
  // Loading regime: τ* / τ̄_peak > 1 means the ring acceleration's inertia outweighs the 1/r²
  // concentration at the peak (the outer ring is the more loaded), < 1 the quasi-static regime.
  const double tau_star = inertial_shear_stress(spec);
  sum.set("loading.inertial_stress", tau_star);
  sum.set("loading.inertia_ratio", tau_star / std::max(tau_s[ipeak], 1e-300));
  for (int k = 0; k < crowns; k += 2) {
    const std::string name = RheometerSeries::crown_name[k];
    sum.set("peak.gamma_" + name, at_peak.shear_strain[k]);
    sum.set("final.gamma_" + name, se.crown[k].shear_strain.back());
    sum.set("final.porosity_" + name, se.crown[k].porosity.back());
    sum.set("final.locus_size_" + name, se.crown[k].locus_size.back());
    // first time half of the crown has r_c = 0 (−1: never)
    double t_half = -1.0;
    for (std::size_t i = 0; i < se.crown[k].fluidized_fraction.size(); ++i)
      if (se.crown[k].fluidized_fraction[i] >= 0.5) {
        t_half = t_s[i];
        break;
      }
    sum.set("time.fluidized_" + name, t_half);
  }
  sum.set("final.porosity_middle", se.crown[1].porosity.back());
  sum.set("rheometer.max_velocity", spec.max_velocity);
  sum.set("rheometer.clamped_updates", clamped);
  sum.set("pore_pressure.mean_final", pw_s.back());
  sum.set("rheometer.cells_r", spec.cells_r);
  sum.set("rheometer.cells_theta", spec.cells_theta);
  sum.set("rheometer.points_per_cell", spec.points_per_cell);
  ctx.log->info(
      "rheometer: peak τ̄ = {:.4g} Pa at t = {:.4g} s; steady τ̄ = {:.4g} Pa, σ̄_G = {:.4g} Pa, "
      "γ̇ = {:.4g} 1/s; fluidized fraction {:.3g}; porosity std {:.3g}; max |ΔV|/V = {:.3g}; "
      "max |Δp̄| = {:.3g} of the initial",
      tau_s[ipeak], t_s[ipeak], tau_st / m, sg_st / m, rate_st / m, se.fluidized_fraction.back(),
      se.porosity_std.back(), vmax_dev, pw_dev);
}

}  // namespace

RheometerSpec read_rheometer(const core::Case& c) {
  RheometerSpec r;
  read_annulus(c, r);
  r.void_ratio = c.number("initial.void_ratio");
  r.effective_pressure = c.number("initial.effective_pressure");
  r.pore_pressure = c.number("initial.pore_pressure");
  r.ocr = c.number("initial.ocr");
  r.initial_temperature = c.number("initial.temperature");
  r.acceleration = c.number("loading.acceleration");
  r.max_velocity = c.number("loading.max_velocity");
  r.model = continuum::read_multi_regime_settings(c);
  // The liquid points: the same liquid as the model (ρ_L, K_w, η0, κ(ν) drag closure). Their own
  // viscous stress is the Newtonian η0 part; the mixture viscosity σ_L of the model acts on the
  // solid points (multi_regime_material.hpp).
  r.liquid.density = r.model.liquid_parameters.density;
  r.liquid.bulk_modulus = r.model.liquid_parameters.bulk_modulus;
  r.liquid.viscosity = r.model.liquid_parameters.viscosity;
  r.liquid.viscosity_law = ViscosityLaw::constant;
  r.liquid.drag_law = DragLaw::closure;
  r.liquid.closure = r.model.liquid_parameters;
  r.liquid.grain_diameter = r.model.collisional_parameters.diameter;
  r.options = read_options(c);
  // T conducted through the nodes with the collisional conductivity ρ_p d f4 T^½ of each point
  // when the collisional term is on (seed section 5).
  r.options.material_conductivity = r.model.collisional && c.boolean("run.conduct_temperature");
  r.options.closed_domain = c.boolean("run.closed_domain");
  return r;
}

void rheometer_inputs(const core::Case& c) {
  if (const auto r =
          check_restart(c, {"run.profile_times", "run.profile_bins", "run.steady_fraction"}))
    check_restart_end(c, *r, c.number("run.end_time"), "run.end_time");
}

int run_rheometer(core::RunContext& ctx) {
  const core::Case& c = ctx.run_case;
  const RheometerSpec spec = read_rheometer(c);
  rheometer_inputs(c);
  Rheometer rh = make_rheometer(spec);
  rh.material->set_internal_length(c.number("solid.internal_length"),
                                   c.number("solid.overnonlocal"));
  Solver& s = *rh.solver;
  RunHistory history = restore_run(ctx, s);
  report_setup(ctx, s, history);
  if (spec.options.material_conductivity)
    ctx.log->info("T conducted through the nodes with κ_T = ρ_p d f4 T^½ of each point");
  const double ms0 = history.get("mass.solid0", s.total_mass(Phase::solid));
  const double ml0 = history.get("mass.liquid0", s.total_mass(Phase::liquid));
  std::vector<double> gamma(s.solid().size(), 0.0);
  history.get("rheometer.shear_strain", gamma);
  if (gamma.size() != s.solid().size())
    refuse_restart(c, c.string("output.restart_from"),
                   fmt::format("its shear strains have {} points, the case {}", gamma.size(),
                               s.solid().size()));
  // The material counts its clamped updates from its construction: add those before a restart.
  const double clamped0 = history.get("rheometer.clamped_updates", 0.0);
  auto clamped = [&]() { return clamped0 + static_cast<double>(rh.material->clamped_updates()); };
  const RheometerAverages a0 = rheometer_averages(s, *rh.material, gamma);
  ctx.log->info(
      "rheometer: e0 = {:g}, p'0 = {:g} Pa, u_w0 = {:g} Pa; v_θ = {:g} t up to v_max = {:g} m/s "
      "(t = {:.4g} s); mixture volume {:.6g} m² (annulus {:.6g})",
      spec.void_ratio, spec.effective_pressure, spec.pore_pressure, spec.acceleration,
      spec.max_velocity, spec.max_velocity / spec.acceleration, a0.mixture_volume,
      M_PI * (spec.outer_radius * spec.outer_radius - spec.inner_radius * spec.inner_radius));
  auto fields = field_writer(ctx);
  if (fields) {
    fields->add_solid_field("r_c", &rh.material->locus_size(), "Pa");
    fields->add_solid_field("void_ratio", &rh.material->void_ratio(), "1");
    fields->add_solid_field("shear_strain", &gamma, "1");
  }
  const int frames = static_cast<int>(c.integer("output.frames"));
  const double end_time = c.number("run.end_time");
  const long sample_every = c.integer("run.sample_every");
  auto profile_times = c.number_list("run.profile_times");
  std::sort(profile_times.begin(), profile_times.end());
  const int bins = static_cast<int>(c.integer("run.profile_bins"));
  constexpr int crowns = RheometerSeries::crowns;
  RheometerSeries se;
  RheometerProfiles at_peak;
  double tau_max = -std::numeric_limits<double>::infinity();
  // The history a restart continues: every series, the running peak and the crown strains at it.
  const auto series = se.named();
  for (auto& [name, v] : series) history.get("rheometer.series." + name, *v);
  tau_max = history.get("rheometer.tau_max", tau_max);
  history.get("rheometer.peak_crown_shear_strain", at_peak.shear_strain);
  auto record_history = [&]() {
    for (auto& [name, v] : series) history.set("rheometer.series." + name, *v);
    history.set("rheometer.tau_max", tau_max);
    history.set("rheometer.peak_crown_shear_strain", at_peak.shear_strain);
    history.set("rheometer.shear_strain", gamma);
    history.set("rheometer.clamped_updates", clamped());
    history.set("mass.solid0", ms0);
    history.set("mass.liquid0", ml0);
  };
  auto sample = [&]() {
    const RheometerAverages a = rheometer_averages(s, *rh.material, gamma);
    const RheometerProfiles cr = rheometer_profiles(s, *rh.material, spec, gamma, crowns);
    for (int k = 0; k < crowns; ++k) {
      se.crown[k].shear_strain.push_back(cr.shear_strain[k]);
      se.crown[k].porosity.push_back(cr.porosity[k]);
      se.crown[k].locus_size.push_back(cr.locus_size[k]);
      se.crown[k].fluidized_fraction.push_back(cr.fluidized_fraction[k]);
    }
    if (a.shear_stress > tau_max) {
      tau_max = a.shear_stress;
      at_peak = cr;
    }
    double T = 0;
    for (double v : s.solid().temperature) T += v;
    se.time.push_back(s.time());
    se.tau.push_back(a.shear_stress);
    se.sigma_G.push_back(a.normal_stress);
    se.gamma.push_back(a.shear_strain);
    se.gamma_dot.push_back(a.shear_rate);
    se.mixture_volume.push_back(a.mixture_volume);
    se.pore_pressure.push_back(a.pore_pressure);
    se.porosity_std.push_back(a.porosity_std);
    se.fluidized_fraction.push_back(a.fluidized_fraction);
    se.temperature.push_back(T / std::max<double>(1.0, s.solid().size()));
    se.pore_pressure_std.push_back(a.pore_pressure_std);
    se.radial_velocity_rms.push_back(a.radial_velocity_rms);
    se.dt.push_back(s.dt());
    se.dt_wave.push_back(history.limits(s).wave);
    se.dt_conduction.push_back(history.limits(s).conduction);
    double nu_max = 0, T_max = 0;
    for (double n : s.solid().porosity) nu_max = std::max(nu_max, 1.0 - n);
    for (double v : s.solid().temperature) T_max = std::max(T_max, v);
    se.solid_fraction_max.push_back(nu_max);
    se.temperature_max.push_back(T_max);
    se.clamped_updates.push_back(clamped());
  };
  // Profile group k of result.h5 (kept in the history: a restarted run writes them again).
  int profiles = 0;
  auto write_profile = [&](RheometerProfiles pr, double at) {
    const std::string grp = fmt::format("/profiles/{}", profiles);
    const std::string h = fmt::format("rheometer.profile_{}.", profiles);
    for (const auto& [name, v] : profile_arrays(pr)) history.set(h + name, *v);
    history.set(h + "time", at);
    ctx.result.write(grp + "/radius", pr.radius, "m", "bin centre radius");
    ctx.result.write(grp + "/shear_strain", pr.shear_strain, "1", "θ-averaged accumulated γ_rθ");
    ctx.result.write(grp + "/velocity", pr.velocity, "m/s", "θ-averaged solid v_θ");
    ctx.result.write(grp + "/shear_stress", pr.shear_stress, "Pa", "θ-averaged solid σ'_rθ");
    ctx.result.write(grp + "/porosity", pr.porosity, "1", "θ-averaged porosity n");
    ctx.result.write(grp + "/locus_size", pr.locus_size, "Pa", "θ-averaged r_c");
    ctx.result.write(grp + "/fluidized_fraction", pr.fluidized_fraction, "1",
                     "volume fraction with r_c below fluidization");
    ctx.result.attribute(grp, "time", at);
    const double vt = std::min(spec.max_velocity, spec.acceleration * at);
    ctx.result.attribute(grp, "wall_velocity", vt);
    ++profiles;
    history.set("rheometer.profiles", profiles);
  };
  for (int k = 0, n = std::lround(history.get("rheometer.profiles", 0.0)); k < n; ++k) {
    const std::string h = fmt::format("rheometer.profile_{}.", k);
    RheometerProfiles pr;
    std::vector<double> at;
    for (const auto& [name, v] : profile_arrays(pr)) history.get(h + name, *v);
    history.get(h + "time", at);
    write_profile(std::move(pr), at.at(0));
  }
  // The profile times still ahead (a restart has taken those up to its checkpoint).
  std::size_t next_profile = 0;
  while (history.restarted() && next_profile < profile_times.size() &&
         s.time() >= profile_times[next_profile] - 0.5 * s.dt())
    ++next_profile;
  FrameSchedule schedule(fields.get(), end_time, frames, s);
  if (!history.restarted()) sample();  // the restored series start with it
  const double wall = advance(ctx, s, end_time, schedule, [&]() {
    accumulate_shear_strain(s, gamma);
    if (s.steps() % sample_every == 0) sample();
    while (next_profile < profile_times.size() &&
           s.time() >= profile_times[next_profile] - 0.5 * s.dt()) {
      write_profile(rheometer_profiles(s, *rh.material, spec, gamma, bins), s.time());
      ++next_profile;
    }
  });
  record_history();  // as the loop left it: a restart continues from here, not from the sample
  sample();
  se.write(ctx.result);
  ctx.result.attribute("/series", "max_velocity", spec.max_velocity);
  ctx.result.attribute("/series", "inner_radius", spec.inner_radius);
  ctx.result.attribute("/series", "outer_radius", spec.outer_radius);
  ctx.result.flush();
  common_summary(ctx, s, history, wall, ms0, ml0);
  ctx.summary.set("cost.wall_s", wall);
  rheometer_summary(ctx, se, spec, at_peak, end_time, clamped());
  finish_output(
      ctx, s, history,
      {"volume.mixture_rel_change_max", "mass.solid_rel_change", "mass.liquid_rel_change"});
  ctx.plot("plot_rheometer.py");
  return core::exit_ok;
}

}  // namespace granflow::mpm::kind
