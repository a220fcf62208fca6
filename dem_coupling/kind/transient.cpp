#include "dem_coupling/kind/transient.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>

#include "dem_coupling/kind/dem_columns.hpp"
#include "dem_coupling/kind/prepare_kind.hpp"
#include "dem_coupling/kind/series_table.hpp"
#include "statistics/steady_state.hpp"

namespace granflow::dem {

namespace {

std::filesystem::path preparation_directory(const core::Case& c) {
  const std::filesystem::path p(c.string("start.preparation"));
  if (p.is_absolute() || std::filesystem::exists(p)) return std::filesystem::absolute(p);
  const auto beside_case = std::filesystem::path(c.origin()).parent_path() / p;
  if (std::filesystem::exists(beside_case)) return std::filesystem::absolute(beside_case);
  return p;
}

// The `kind:` line of a run directory's case.yaml (written by granflow), or "".
std::string kind_of_run(const std::filesystem::path& dir) {
  std::ifstream in(dir / "case.yaml");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("kind:", 0) == 0) {
      std::string kind = line.substr(5);
      kind.erase(0, kind.find_first_not_of(" \t\"'"));
      kind.erase(kind.find_last_not_of(" \t\"'\r") + 1);
      return kind;
    }
  return "";
}

}  // namespace

TransientMetrics transient_metrics(std::span<const double> strain, std::span<const double> p,
                                   std::span<const double> tau, double p0,
                                   double liquefaction_fraction, double residual_fraction) {
  TransientMetrics m;
  const std::size_t n = std::min({strain.size(), p.size(), tau.size()});
  if (n == 0) return m;
  const std::size_t peak =
      std::size_t(std::max_element(tau.begin(), tau.begin() + long(n)) - tau.begin());
  m.peak_tau = tau[peak];
  m.peak_strain = strain[peak];
  for (std::size_t i = 0; i < n; ++i)
    if (p[i] < liquefaction_fraction * p0) {
      m.liquefaction_strain = strain[i];
      break;
    }
  const double from = (1.0 - residual_fraction) * strain[n - 1];
  std::size_t start = 0;
  while (start + 1 < n && strain[start] < from) ++start;
  const auto tail_tau = tau.subspan(start, n - start);
  const auto tail_p = p.subspan(start, n - start);
  if (tail_tau.size() >= 8) {
    const auto t = statistics::correlated_mean(tail_tau);
    const auto q = statistics::correlated_mean(tail_p);
    m.residual_tau = t.mean;
    m.residual_tau_err = t.standard_error;
    m.residual_p = q.mean;
    m.residual_p_err = q.standard_error;
  } else {  // too short for batch means: the plain mean, no error bar
    double st = 0, sp = 0;
    for (std::size_t i = 0; i < tail_tau.size(); ++i) st += tail_tau[i], sp += tail_p[i];
    m.residual_tau = st / double(tail_tau.size());
    m.residual_p = sp / double(tail_p.size());
  }
  m.p_final_over_p0 = m.residual_p / p0;
  return m;
}

StopMetrics stop_metrics(std::span<const double> time_since_stop, std::span<const double> T,
                         std::span<const double> p, double flowing_temperature, double p0,
                         double cooling_fraction) {
  StopMetrics m;
  m.flowing_temperature = flowing_temperature;
  const std::size_t n = std::min({time_since_stop.size(), T.size(), p.size()});
  if (n == 0 || !(flowing_temperature > 0)) return m;
  const double target = cooling_fraction * flowing_temperature;
  double t_prev = 0.0, T_prev = flowing_temperature;
  for (std::size_t i = 0; i < n; ++i) {
    if (T[i] <= target) {
      // ln T linear between the samples (Haff's T ∝ (1 + t/t_H)^-2 is close to it over a sample)
      const double w =
          T[i] > 0.0 && T_prev > T[i] ? std::log(T_prev / target) / std::log(T_prev / T[i]) : 1.0;
      m.cooling_time = t_prev + std::clamp(w, 0.0, 1.0) * (time_since_stop[i] - t_prev);
      break;
    }
    t_prev = time_since_stop[i], T_prev = T[i];
  }
  m.final_temperature_ratio = T[n - 1] / flowing_temperature;
  m.final_p_over_p0 = p0 > 0.0 ? p[n - 1] / p0 : 0.0;
  return m;
}

DrainedStopMetrics drained_stop_metrics(std::span<const double> time_since_stop,
                                        std::span<const double> sigma_yy,
                                        std::span<const double> solid_fraction,
                                        double solid_fraction_at_stop, double normal_stress,
                                        double reconsolidation_fraction) {
  DrainedStopMetrics m;
  const std::size_t n = std::min({time_since_stop.size(), sigma_yy.size(), solid_fraction.size()});
  if (n == 0) return m;
  const double target = reconsolidation_fraction * normal_stress;
  for (std::size_t i = 0; i < n; ++i)
    if (sigma_yy[i] >= target) {
      if (i == 0) {
        m.reconsolidation_time = time_since_stop[0];
      } else {
        const double w = (target - sigma_yy[i - 1]) / (sigma_yy[i] - sigma_yy[i - 1]);
        m.reconsolidation_time =
            time_since_stop[i - 1] + w * (time_since_stop[i] - time_since_stop[i - 1]);
      }
      break;
    }
  m.final_solid_fraction = solid_fraction[n - 1];
  m.solid_fraction_change = solid_fraction[n - 1] - solid_fraction_at_stop;
  return m;
}

double residual_mean(std::span<const double> strain, std::span<const double> values,
                     double residual_fraction) {
  const std::size_t n = std::min(strain.size(), values.size());
  if (n == 0) return std::numeric_limits<double>::quiet_NaN();
  const double from = (1.0 - residual_fraction) * strain[n - 1];
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (strain[i] >= from) sum += values[i], ++count;
  return sum / double(count);
}

PreparedState read_prepared_state(const core::Case& c, long seed) {
  const auto dir = preparation_directory(c);
  if (!std::filesystem::is_directory(dir))
    c.fail("start.preparation",
           fmt::format("a kind: dem_prepare run directory; {} is not a directory", dir.string()));
  if (const std::string kind = kind_of_run(dir); kind != "dem_prepare")
    c.fail("start.preparation",
           fmt::format("a kind: dem_prepare run directory; {} is not one ({})", dir.string(),
                       kind.empty() ? "no case.yaml" : "its case.yaml says kind: " + kind));
  const auto seed_dir = prepared_seed_directory(dir, seed);
  PreparedState s;
  s.restart = seed_dir / "prepared.restart";
  const SeriesTable t = std::filesystem::exists(s.restart)
                            ? read_series_table(seed_dir / "prepared.tsv")
                            : SeriesTable{};
  if (t.rows() != 1)
    c.fail("start.preparation",
           fmt::format("a prepared state for dem.seed {}: {} has none (prepared.restart and "
                       "prepared.tsv; the preparation failed, or prepared fewer seeds)",
                       seed, seed_dir.string()));
  if (s.restart.string().find_first_of(" \t\n\"'") != std::string::npos)
    c.fail(
        "start.preparation",
        fmt::format("a path without spaces or quotes (LIGGGHTS reads it): {}", s.restart.string()));
  s.phi = t.at("phi")[0];
  s.p = t.at("p")[0];
  s.sigma_yy = t.at("sigma_yy")[0];
  s.particles = t.at("particles")[0];
  return s;
}

void check_preparation_inputs(const core::Case& run_case) {
  if (!run_case.has("start.preparation")) return;
  const long seeds = run_case.integer("statistics.seeds");
  for (const core::Case& c : run_case.expand_sweep())
    for (long k = 0; k < seeds; ++k) read_prepared_state(c, c.integer("dem.seed") + k);
}

TransientShear::TransientShear(const core::Case& run_case)
    : enabled_(run_case.has("start.preparation")),
      fraction_(run_case.number("transient.liquefaction_fraction")),
      residual_(run_case.number("transient.residual_fraction")),
      cooling_fraction_(run_case.number("stop.cooling_fraction")),
      reconsolidation_fraction_(run_case.number("stop.reconsolidation_fraction")) {}

void TransientShear::apply(const core::Case& c, ShearDeckParams& p) const {
  if (!enabled_) return;
  const PreparedState s = read_prepared_state(c, long(p.seed));
  p.prepared_restart = s.restart.string();
  p.particles = std::lround(s.particles);
  p.solid_fraction = s.phi;
  if (!c.has("control.initial_temperature")) p.initial_temperature = 0.0;
  if (!c.has("stop.normal_stress")) p.stop_normal_stress = s.p;  // a drained stop's default σ_n
  if ((p.drainage_length > 0.0 || p.height_resistance > 0.0) && !c.has("control.normal_stress"))
    p.normal_stress = s.p;  // a drained or damped shear's default σ_n
}

void TransientShear::absorb(core::RunContext& ctx, std::size_t n, const std::filesystem::path& dir,
                            const std::string& group, const ShearDeckParams& p,
                            const std::string& suffix) {
  if (!enabled_) return;
  const SeriesTable t = read_series_table(dir / "series.tsv");
  if (t.rows() == 0) return;
  for (const DemColumn& row : dem_columns::network_series)
    ctx.result.write(group + "/series/" + row.column.name, t.at(row.key), row.column.unit,
                     row.column.description);
  if (t.columns.count("p_fluid"))
    ctx.result.write(group + "/series/fluid_pressure", t.at("p_fluid"), "Pa",
                     "hydrodynamic (lubrication + drag) part of tr(P)/3; p' = p - this");
  const PreparedState s = read_prepared_state(ctx.run_case, long(p.seed));
  Point& point = points_[n];
  const std::vector<double>& strain = t.at("strain");
  // The shear's rows, then the stop's (stop.duration > 0), which repeat the strain of the stop.
  const std::size_t sheared = p.stop_duration > 0.0 ? shear_rows(strain) : strain.size();
  point.strain.assign(strain.begin(), strain.begin() + long(sheared));
  for (std::size_t i = sheared; i < strain.size(); ++i)
    point.stop_time.push_back(t.at("time")[i] - t.at("time")[sheared - 1]);
  for (const DemColumn& column : dem_columns::transient_band) {
    std::vector<double> v = t.at(column.key);
    // Immersed runs: p' is the effective (solid) mean stress, the hydrodynamic part of the virial
    // (lubrication + drag, series column p_fluid) taken out; dry runs: p.
    if (std::string_view(column.key) == "p" && t.columns.count("p_fluid"))
      for (std::size_t i = 0; i < v.size(); ++i) v[i] -= t.at("p_fluid")[i];
    point.stop_band.emplace_back(v.begin() + long(sheared), v.end());
    v.resize(sheared);
    point.band.push_back(std::move(v));
  }
  const std::vector<double>& p_eff = point.band[0];  // transient_band: p', then τ
  point.p0 = s.p;
  point.phi0 = s.phi;
  point.metrics = transient_metrics(point.strain, p_eff, point.band[1], s.p, fraction_, residual_);
  const TransientMetrics& m = point.metrics;
  // transient.NAME{suffix} in summary.json and transient_NAME on the point's series
  const auto publish = [&](std::initializer_list<std::pair<const char*, double>> values) {
    for (const auto& [name, value] : values) {
      ctx.summary.set(fmt::format("transient.{}{}", name, suffix), value);
      ctx.result.attribute(group + "/series", std::string("transient_") + name, value);
    }
  };
  if (!point.stop_time.empty()) {
    constexpr std::size_t p_row = 0, T_row = 3;  // transient_band: p', τ, σ_yy, T, ...
    point.stop = stop_metrics(point.stop_time, point.stop_band[T_row], point.stop_band[p_row],
                              residual_mean(point.strain, point.band[T_row], residual_), s.p,
                              cooling_fraction_);
    const StopMetrics& q = point.stop;
    publish({{"flowing_T", q.flowing_temperature},
             {"cooling_time", q.cooling_time},
             {"stop_T_over_flowing_T", q.final_temperature_ratio},
             {"stop_p_over_p0", q.final_p_over_p0}});
    ctx.log->info(
        "point {}: shear stopped for {:.4g} s: T fell below {:g} × the flowing T ({:.4g} m²/s²) "
        "{}; at the end T = {:.3g} × flowing, p' = {:.3g} p0",
        n, point.stop_time.back(), cooling_fraction_, q.flowing_temperature,
        q.cooling_time >= 0 ? fmt::format("after {:.4g} s", q.cooling_time) : std::string("never"),
        q.final_temperature_ratio, q.final_p_over_p0);
    if (p.stop_drainage_length > 0.0) {
      constexpr std::size_t sigma_row = 2, phi_row = 6;  // transient_band: σ_yy, φ
      point.drained = true;
      point.stop_normal_stress = p.stop_normal_stress;
      point.drained_stop = drained_stop_metrics(
          point.stop_time, point.stop_band[sigma_row], point.stop_band[phi_row],
          point.band[phi_row].back(), p.stop_normal_stress, reconsolidation_fraction_);
      const DrainedStopMetrics& d = point.drained_stop;
      publish({{"reconsolidation_time", d.reconsolidation_time},
               {"stop_phi", d.final_solid_fraction},
               {"stop_phi_change", d.solid_fraction_change}});
      ctx.log->info(
          "point {}: drained over {:g} m under σ_n = {:.4g} Pa: σ_yy reached {:g} σ_n {}; φ "
          "{:.4f} -> {:.4f}",
          n, p.stop_drainage_length, p.stop_normal_stress, reconsolidation_fraction_,
          d.reconsolidation_time >= 0 ? fmt::format("after {:.4g} s", d.reconsolidation_time)
                                      : std::string("never"),
          point.band[phi_row].back(), d.final_solid_fraction);
    }
  }
  if (p.rate_step_strain > 0.0) {
    constexpr std::size_t tau_row = 1, sigma_row = 2, T_row = 3, phi_row = 6;  // transient_band
    point.rate_step = true;
    point.step_strain = p.rate_step_strain;
    point.step_rate = p.rate_step_shear_rate;
    point.stepped =
        rate_step_metrics(point.strain, point.band[tau_row], point.band[sigma_row],
                          point.band[phi_row], point.band[T_row], p.rate_step_strain, residual_);
    const RateStepMetrics& r = point.stepped;
    publish({{"mu_before_step", r.mu_before},
             {"mu_after_step", r.mu_after},
             {"phi_before_step", r.phi_before},
             {"phi_after_step", r.phi_after},
             {"T_before_step", r.T_before},
             {"T_after_step", r.T_after},
             {"dilation", r.dilation},
             {"peak_mu_after_step", r.peak_mu}});
    if (r.dilation_strain >= 0.0)
      ctx.summary.set(fmt::format("transient.dilation_strain{}", suffix), r.dilation_strain);
    ctx.log->info(
        "point {}: shear rate {:g} -> {:g} 1/s at γ = {:g}: μ {:.4g} -> {:.4g} (peak {:.4g}), φ "
        "{:.4f} -> {:.4f} ({}), T {:.3g} -> {:.3g} m²/s²",
        n, p.shear_rate, p.rate_step_shear_rate, p.rate_step_strain, r.mu_before, r.mu_after,
        r.peak_mu, r.phi_before, r.phi_after,
        r.dilation_strain >= 0.0
            ? fmt::format("half of it {:.3g} strain after the step", r.dilation_strain)
            : std::string("never half"),
        r.T_before, r.T_after);
  }
  publish({
      {"p0", s.p},
      {"phi0", s.phi},
      {"first_p_over_p0", p_eff.front() / s.p},
      {"peak_tau", m.peak_tau},
      {"peak_strain", m.peak_strain},
      {"liquefied", m.liquefaction_strain >= 0.0 ? 1.0 : 0.0},
      {"residual_tau", m.residual_tau},
      {"residual_tau_err", m.residual_tau_err},
      {"residual_p", m.residual_p},
      {"residual_p_err", m.residual_p_err},
      {"p_final_over_p0", m.p_final_over_p0},
  });
  if (m.liquefaction_strain >= 0.0)
    ctx.summary.set(fmt::format("transient.liquefaction_strain{}", suffix), m.liquefaction_strain);
  ctx.log->info(
      "point {}: from rest at φ0 = {:.4f}, p0 = {:.4g} Pa: peak τ = {:.4g} Pa at γ = {:.3g}; {}; "
      "residual τ = {:.4g} ± {:.2g} Pa, p = {:.4g} Pa = {:.3g} p0",
      n, s.phi, s.p, m.peak_tau, m.peak_strain,
      m.liquefaction_strain >= 0.0
          ? fmt::format("liquefied (p < {:g} p0) at γ = {:.3g}", fraction_, m.liquefaction_strain)
          : fmt::format("not liquefied (p >= {:g} p0 throughout)", fraction_),
      m.residual_tau, m.residual_tau_err, m.residual_p, m.p_final_over_p0);
}

void TransientShear::write_band(core::RunContext& ctx, const std::string& prefix,
                                const std::vector<const Point*>& members, std::size_t rows,
                                std::vector<std::vector<double>> Point::*series,
                                const std::string& note) {
  for (std::size_t k = 0; k < std::size(dem_columns::transient_band); ++k) {
    const core::Column& column = dem_columns::transient_band[k].column;
    std::vector<double> mean(rows), low(rows), high(rows);
    for (std::size_t i = 0; i < rows; ++i) {
      double sum = 0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (const Point* m : members) {
        const double v = (m->*series)[k][i];
        sum += v, lo = std::min(lo, v), hi = std::max(hi, v);
      }
      mean[i] = sum / double(members.size()), low[i] = lo, high[i] = hi;
    }
    const std::string name = prefix + column.name;
    const std::string doc = std::string(column.description) + note;
    ctx.result.write(name + dem_columns::band_mean, mean, column.unit,
                     doc + ": mean over the seeds, sample by sample");
    ctx.result.write(name + dem_columns::band_min, low, column.unit, doc + ": lowest seed");
    ctx.result.write(name + dem_columns::band_max, high, column.unit, doc + ": highest seed");
  }
}

void TransientShear::finish(core::RunContext& ctx, const std::vector<Condition>& swept) {
  if (!enabled_ || points_.empty()) return;
  std::vector<SeedGroup> groups = group_by_seed(swept);
  if (groups.empty())  // one seed per condition: each its own group
    for (std::size_t n = 0; n < swept.size(); ++n) groups.push_back({swept[n], {n}});
  const bool several = groups.size() > 1;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    std::vector<const Point*> members;
    for (std::size_t n : groups[g].members)
      if (points_.count(n)) members.push_back(&points_.at(n));
    if (members.empty()) continue;
    std::size_t rows = members.front()->strain.size();
    for (const Point* m : members) rows = std::min(rows, m->strain.size());
    const std::string group = fmt::format("/transient/group_{}", g);
    const std::string key_suffix = several ? fmt::format(".{}", g) : std::string();
    std::vector<double> strain(members.front()->strain.begin(),
                               members.front()->strain.begin() + long(rows));
    ctx.result.write(group + "/" + core::columns::strain.name, strain, core::columns::strain.unit,
                     "shear strain of the samples");
    write_band(ctx, group + "/", members, rows, &Point::band, "");
    // The stop: time since the stop and the same bands over the stop's rows.
    std::size_t stop_rows = members.front()->stop_time.size();
    for (const Point* m : members) stop_rows = std::min(stop_rows, m->stop_time.size());
    if (stop_rows > 0) {
      const std::vector<double>& t0 = members.front()->stop_time;
      ctx.result.write(group + "/stop/" + core::columns::time.name,
                       std::vector<double>(t0.begin(), t0.begin() + long(stop_rows)),
                       core::columns::time.unit, "time since the shear was stopped");
      write_band(ctx, group + "/stop/", members, stop_rows, &Point::stop_band, ", shear stopped");
      ctx.result.attribute(group + "/stop", "cooling_fraction", cooling_fraction_);
      if (members.front()->drained) {
        ctx.result.attribute(group + "/stop", "reconsolidation_fraction",
                             reconsolidation_fraction_);
        double sigma_n = 0.0;  // the members' mean (each seed's own prepared p0 by default)
        for (const Point* m : members) sigma_n += m->stop_normal_stress / double(members.size());
        ctx.result.attribute(group + "/stop", "normal_stress", sigma_n);
      }
    }
    // Metrics: mean over the seeds and its standard error (between-seed sd / sqrt(N)).
    auto stats = [&](auto get, const char* name) {
      std::vector<double> v;
      for (const Point* m : members)
        if (const double x = get(*m); std::isfinite(x)) v.push_back(x);
      if (v.empty()) return;
      double sum = 0, sum2 = 0;
      for (double x : v) sum += x, sum2 += x * x;
      const double k = double(v.size()), mean = sum / k;
      const double var = k > 1 ? std::max(0.0, (sum2 - k * mean * mean) / (k - 1)) : 0.0;
      ctx.summary.set(fmt::format("transient.mean.{}{}", name, key_suffix), mean);
      ctx.summary.set(fmt::format("transient.err.{}{}", name, key_suffix), std::sqrt(var / k));
      ctx.result.attribute(group, std::string("mean_") + name, mean);
      ctx.result.attribute(group, std::string("err_") + name, std::sqrt(var / k));
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    stats([](const Point& m) { return m.p0; }, "p0");
    stats([](const Point& m) { return m.phi0; }, "phi0");
    stats([](const Point& m) { return m.metrics.peak_tau; }, "peak_tau");
    stats([](const Point& m) { return m.metrics.peak_strain; }, "peak_strain");
    stats([](const Point& m) { return m.metrics.residual_tau; }, "residual_tau");
    stats([](const Point& m) { return m.metrics.residual_p; }, "residual_p");
    stats([](const Point& m) { return m.metrics.p_final_over_p0; }, "p_final_over_p0");
    stats(
        [&](const Point& m) {
          return m.metrics.liquefaction_strain >= 0 ? m.metrics.liquefaction_strain : nan;
        },
        "liquefaction_strain");
    if (stop_rows > 0) {
      stats([](const Point& m) { return m.stop.flowing_temperature; }, "flowing_T");
      stats([&](const Point& m) { return m.stop.cooling_time >= 0 ? m.stop.cooling_time : nan; },
            "cooling_time");
      stats([](const Point& m) { return m.stop.final_temperature_ratio; }, "stop_T_over_flowing_T");
      stats([](const Point& m) { return m.stop.final_p_over_p0; }, "stop_p_over_p0");
      if (members.front()->drained) {
        stats(
            [&](const Point& m) {
              return m.drained_stop.reconsolidation_time >= 0 ? m.drained_stop.reconsolidation_time
                                                              : nan;
            },
            "reconsolidation_time");
        stats([](const Point& m) { return m.drained_stop.final_solid_fraction; }, "stop_phi");
        stats([](const Point& m) { return m.drained_stop.solid_fraction_change; },
              "stop_phi_change");
      }
    }
    if (members.front()->rate_step) {
      ctx.result.attribute(group, "rate_step_strain", members.front()->step_strain);
      ctx.result.attribute(group, "rate_step_shear_rate", members.front()->step_rate);
      stats([](const Point& m) { return m.stepped.mu_before; }, "mu_before_step");
      stats([](const Point& m) { return m.stepped.mu_after; }, "mu_after_step");
      stats([](const Point& m) { return m.stepped.phi_before; }, "phi_before_step");
      stats([](const Point& m) { return m.stepped.phi_after; }, "phi_after_step");
      stats([](const Point& m) { return m.stepped.T_before; }, "T_before_step");
      stats([](const Point& m) { return m.stepped.T_after; }, "T_after_step");
      stats([](const Point& m) { return m.stepped.dilation; }, "dilation");
      stats([](const Point& m) { return m.stepped.peak_mu; }, "peak_mu_after_step");
      stats(
          [&](const Point& m) {
            return m.stepped.dilation_strain >= 0 ? m.stepped.dilation_strain : nan;
          },
          "dilation_strain");
    }
    double liquefied = 0;
    for (const Point* m : members) liquefied += m->metrics.liquefaction_strain >= 0 ? 1 : 0;
    ctx.summary.set("transient.liquefied_seeds" + key_suffix, liquefied);
    ctx.summary.set("transient.seeds" + key_suffix, double(members.size()));
    ctx.result.attribute(group, "liquefaction_fraction", fraction_);
    ctx.result.attribute(group, "liquefied_seeds", liquefied);
    ctx.result.attribute(group, "seeds", double(members.size()));
    ctx.log->info("transient{}: {} of {} seeds liquefied (p < {:g} p0)", key_suffix, liquefied,
                  members.size(), fraction_);
  }
  ctx.result.flush();
  ctx.plot("plot_transient_dem.py");
}

}  // namespace granflow::dem
