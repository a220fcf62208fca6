// Outputs of `granflow study closures` (closure_study.hpp): the ranked table as closures.csv,
// report.md and study.json, the curves of the best combinations in closures.h5 and their plot.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <sstream>
#include <utility>

#include "analysis/calibration/closure_study.hpp"
#include "core/file_io.hpp"
#include "core/process.hpp"
#include "core/result_file.hpp"
#include "core/run.hpp"

namespace granflow::calibration {

namespace fs = std::filesystem;

namespace {

std::string num(double v, const std::string& format = "{:.10g}") {
  if (format == "yes/no") return v > 0.5 ? "yes" : "**no**";
  return std::isfinite(v) ? fmt::format(fmt::runtime(format), v) : std::string();
}

std::string csv_text(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char ch : s) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return q + "\"";
}

std::string observable(Observable o) { return observable_names()[static_cast<int>(o)]; }

// The ranked table, one column per quantity: closures.csv has every column but the json-only
// ones, report.md those with a title, study.json the numeric ones as combination.<i>.<name>.
struct Column {
  std::string name, title, format;  // title "": not in report.md
  bool numeric, in_csv = true;
  std::vector<double> values;      // per combination (numeric columns)
  std::vector<std::string> texts;  // per combination (text columns)
  std::string cell(std::size_t i, bool report) const {
    return numeric ? num(values[i], report ? format : "{:.10g}") : texts[i];
  }
};

struct Study {
  const ClosureStudy& study;
  const StudyData& data;
  const std::vector<ClosureFit>& fits;
  std::vector<std::size_t> order;  // combinations by rank
  std::vector<Column> columns;
  double wall_s = 0;
  const Column& column(const std::string& name) const {
    return *std::find_if(columns.begin(), columns.end(), [&](auto& c) { return c.name == name; });
  }
  void number(const std::string& name, const std::string& title, const std::string& format,
              const std::function<double(std::size_t)>& value, bool in_csv = true) {
    Column c{name, title, format, true, in_csv, {}, {}};
    for (std::size_t i = 0; i < fits.size(); ++i) c.values.push_back(value(i));
    columns.push_back(std::move(c));
  }
  void text(const std::string& name, const std::string& title,
            const std::function<std::string(std::size_t)>& value) {
    Column c{name, title, "", false, true, {}, {}};
    for (std::size_t i = 0; i < fits.size(); ++i) c.texts.push_back(value(i));
    columns.push_back(std::move(c));
  }
};

void build_table(Study& t) {
  const auto& s = t.study;
  const auto& fits = t.fits;
  const auto rank_of = [&](std::size_t i) {
    return static_cast<std::size_t>(std::find(t.order.begin(), t.order.end(), i) - t.order.begin());
  };
  const auto ok = [&](std::size_t i, double v) { return fits[i].ok ? v : NAN; };
  // Akaike weights w_i = exp(-Δ_i/2) / Σ_j exp(-Δ_j/2), Δ_i = AIC_i - min AIC: the relative
  // likelihood of each combination within the set (Burnham & Anderson 2002, §2.9).
  const double best = fits[t.order.front()].aic;
  double norm = 0;
  for (const auto& f : fits)
    if (f.ok && std::isfinite(f.aic)) norm += std::exp(-(f.aic - best) / 2);
  t.number("rank", "rank", "{:.0f}", [&](std::size_t i) { return rank_of(i) + 1.0; });
  t.number("combination", "", "", [](std::size_t i) { return double(i); });
  for (std::size_t j = 0; j < s.keys.size(); ++j) {
    t.text(s.keys[j], s.short_keys[j],
           [&, j](std::size_t i) { return s.combinations[i].values[j]; });
    // study.json: the value's index in the closures list (booleans: 1 = true)
    t.number(
        "option." + s.keys[j], "", "",
        [&, j](std::size_t i) {
          const auto& v = s.combinations[i].values[j];
          const auto& list = s.options[j];
          if (v == "true" || v == "false") return v == "true" ? 1.0 : 0.0;
          return double(std::find(list.begin(), list.end(), v) - list.begin());
        },
        false);
  }
  t.number("k", "k", "{:.0f}", [&](std::size_t i) { return double(fits[i].k); });
  t.text("parameters", "", [&](std::size_t i) { return join(s.combinations[i].parameters, ";"); });
  t.text("dropped", "", [&](std::size_t i) { return join(s.combinations[i].dropped, ";"); });
  for (const auto& p : s.parameters)
    for (const bool err : {false, true})
      t.number((err ? "fit." + p + "_err" : "fit." + p), "", "", [&, p, err](std::size_t i) {
        const auto& list = s.combinations[i].parameters;
        const auto j = std::size_t(std::find(list.begin(), list.end(), p) - list.begin());
        const auto& v = err ? fits[i].standard_error : fits[i].estimate;
        return j < v.size() ? v[j] : NAN;
      });
  t.number("chi2", "χ²", "{:.4g}", [&](std::size_t i) { return ok(i, fits[i].chi2); });
  t.number("chi2_red", "χ²_red", "{:.4g}", [&](std::size_t i) { return ok(i, fits[i].chi2_red); });
  t.number("dof", "dof", "{:.0f}", [&](std::size_t i) { return double(fits[i].dof); });
  t.number("residuals", "", "", [&](std::size_t i) { return double(fits[i].residuals); });
  t.number("aic", "AIC", "{:.5g}", [&](std::size_t i) { return ok(i, fits[i].aic); });
  t.number("aicc", "AICc", "{:.5g}", [&](std::size_t i) { return ok(i, fits[i].aicc); });
  t.number("delta_aic", "ΔAIC", "{:.3g}", [&](std::size_t i) { return ok(i, fits[i].aic - best); });
  t.number("akaike_weight", "weight", "{:.2g}",
           [&](std::size_t i) { return ok(i, std::exp(-(fits[i].aic - best) / 2) / norm); });
  for (std::size_t k = 0; k < s.observables.size(); ++k)
    t.number("holdout.rel_err." + observable(s.observables[k]),
             "held-out " + observable(s.observables[k]), "{:.3g}", [&, k](std::size_t i) {
               return k < fits[i].holdout_rel_err.size() ? fits[i].holdout_rel_err[k] : NAN;
             });
  for (std::size_t k = 0; k < s.observables.size(); ++k)
    t.number("train.rel_err." + observable(s.observables[k]), "", "", [&, k](std::size_t i) {
      return k < fits[i].train_rel_err.size() ? fits[i].train_rel_err[k] : NAN;
    });
  t.number("fit.inside_domain", "inside", "yes/no",
           [&](std::size_t i) { return fits[i].ok && fits[i].inside_domain ? 1.0 : 0.0; });
  t.number("fit.identifiable", "ident.", "yes/no",
           [&](std::size_t i) { return fits[i].ok && fits[i].identifiable ? 1.0 : 0.0; });
  t.number("no_steady_state", "no steady state", "{:.0f}",
           [&](std::size_t i) { return double(fits[i].no_steady_state); });
  // The same χ² (1e-9) and k as a better-ranked row: the option changed nothing at these data.
  t.number("same_as_rank", "same as rank", "{:.0f}", [&](std::size_t i) {
    for (std::size_t r = 0; r < rank_of(i); ++r) {
      const auto& a = fits[t.order[r]];
      if (fits[i].ok && a.k == fits[i].k && std::abs(a.chi2 - fits[i].chi2) <= 1e-9 * a.chi2)
        return r + 1.0;
    }
    return double(NAN);
  });
  t.number("status", "", "", [&](std::size_t i) { return double(fits[i].status); });
  t.number("evaluations", "", "", [&](std::size_t i) { return double(fits[i].evaluations); });
  t.text("error", "", [&](std::size_t i) { return fits[i].error; });
}

void write_csv(const Study& t, const fs::path& file) {
  std::ostringstream out;
  const auto row = [&](const std::function<std::string(const Column&)>& cell) {
    bool first = true;
    for (const auto& c : t.columns)
      if (c.in_csv) out << (std::exchange(first, false) ? "" : ",") << cell(c);
    out << "\n";
  };
  row([](const Column& c) { return c.name; });
  for (const std::size_t i : t.order)
    row([&](const Column& c) { return csv_text(c.cell(i, false)); });
  core::write_text_file(file, out.str());
}

void write_json(const Study& t, const fs::path& file) {
  core::Summary sum;  // flat name: number; NaN/Inf are left out
  sum.set("study.combinations", double(t.fits.size()));
  sum.set("study.points", double(t.data.used.size()));
  sum.set("study.training_points", double(t.data.training.size()));
  sum.set("study.holdout_points", double(t.data.holdout.size()));
  sum.set("study.wall_s", t.wall_s);
  for (std::size_t r = 0; r < t.order.size(); ++r)
    sum.set(fmt::format("rank.{}", r + 1), double(t.order[r]));
  for (const auto& c : t.columns)
    if (c.numeric && c.name != "combination")
      for (std::size_t i = 0; i < c.values.size(); ++i)
        sum.set(fmt::format("combination.{}.{}", i, c.name), c.values[i]);
  sum.write(file);
}

void write_report_text(const Study& t, bool plotted, std::ostream& out) {
  const auto& s = t.study;
  const auto& base = *s.base;
  out << "# Closure study: " << s.name << "\n\n"
      << fmt::format(
             "Case `{}`, data `{}`: {} points, {} fitted, {} held out (holdout.mode: {}); "
             "observables {}; fit.parameters `{}`. {} combinations in {:.1f} s.\n\n",
             s.file.string(),
             base.has("data.files") ? base.string("data.files") : base.string("data.table"),
             t.data.used.size(), t.data.training.size(), t.data.holdout.size(),
             base.string("holdout.mode"), base.string("data.observables"),
             base.string("fit.parameters"), t.fits.size(), t.wall_s)
      << "Ranked by AIC = χ² + 2k (Akaike 1974; k fitted parameters, χ² with the DEM error "
         "bars), ties by χ²_red. AICc = AIC + 2k(k+1)/(n−k−1), n residuals (Hurvich & Tsai "
         "1989). weight = exp(−ΔAIC/2)/Σ (Burnham & Anderson 2002). held-out: mean |f − y|/|y| "
         "on the held-out points. inside: fit.inside_domain; ident.: fit.identifiable; no "
         "steady state: points the model cannot carry at the estimate; same as rank: identical "
         "χ² and k (the option changes nothing here).\n\n|";
  std::string rule = "|";
  for (const auto& c : t.columns)
    if (!c.title.empty()) out << " " << c.title << " |", rule += "---|";
  out << " not fitted |\n" << rule << "---|\n";
  for (const std::size_t i : t.order) {
    out << "|";
    for (const auto& c : t.columns)
      if (!c.title.empty()) out << " " << c.cell(i, true) << " |";
    const auto& f = t.fits[i];
    out << " " << (f.ok ? join(s.combinations[i].dropped, ", ") : "fit failed: " + f.error)
        << " |\n";
  }
  out << "\n## Parameters not fitted\n\n";
  std::map<std::string, std::pair<std::string, int>> dropped;  // name -> (why, combinations)
  for (const auto& comb : s.combinations)
    for (const auto& p : comb.dropped) {
      dropped[p].first = dropped_because(p, *comb.run_case);
      ++dropped[p].second;
    }
  if (dropped.empty()) out << "Every combination fits every parameter of fit.parameters.\n";
  for (const auto& [p, why] : dropped)
    out << fmt::format(
        "- `{}` is not fitted in {} of {} combinations ({}); it keeps the case's "
        "value there and does not count in k.\n",
        p, why.second, s.combinations.size(), why.first);
  const std::size_t b = t.order.front();
  const auto& f = t.fits[b];
  const auto& comb = s.combinations[b];
  out << "\n## Best model\n\n" << comb.label << fmt::format(" (combination {}): ", b);
  if (!f.ok) {
    out << "no combination could be fitted.\n";
    return;
  }
  out << fmt::format("χ² = {:.4g}, χ²_red = {:.4g} ({} dof), AIC = {:.5g}.\n\n", f.chi2, f.chi2_red,
                     f.dof, f.aic)
      << "| parameter | case key | estimate | standard error | on a bound "
         "|\n|---|---|---|---|---|\n";
  for (std::size_t j = 0; j < comb.parameters.size(); ++j)
    out << fmt::format("| {} | `{}` | {:.6g} | {} | {} |\n", comb.parameters[j],
                       parameter_spec(comb.parameters[j]).case_key, f.estimate[j],
                       num(f.standard_error[j], "{:.3g}"), f.at_bound[j] > 0 ? "yes" : "no");
  if (plotted)
    out << "\n![The best three distinct combinations against the DEM data](closures.png)\n";
}

void write_report(const Study& t, const fs::path& file, bool plotted) {
  std::ostringstream out;
  write_report_text(t, plotted, out);
  core::write_text_file(file, out.str());
}

// The DEM points and the smooth predictions of the best three distinct combinations (a row with
// `same_as_rank` repeats a curve already drawn), for plot_closures.py: at constant pressure over I
// at the mean DEM σ_yy (γ̇ = I √(σ_yy/ρ_p)/d); when every used row is at constant volume, over the
// imposed φ at the mean DEM γ̇ (the model then predicts σ_yy). Attribute /curves protocol says
// which ("constant_pressure" or "constant_volume"), and the grid is /curves/inertial_number or
// /curves/solid_fraction.
void write_curves(const Study& o, const fs::path& file) {
  const auto& s = o.study;
  const auto& used = o.data.used;
  core::ResultFile h5(file);
  const auto column = [&](auto get) {
    std::vector<double> v;
    for (const auto& p : used) v.push_back(get(p));
    return v;
  };
  const auto material = start_model(*s.base).settings.collisional_parameters;
  const double d = material.diameter, rho = material.particle_density;
  const auto inertial = [&](const DataPoint& p) {
    return std::isfinite(p.inertial_number) && p.inertial_number > 0
               ? p.inertial_number
               : p.shear_rate * d / std::sqrt(p.normal_stress / rho);
  };
  h5.write("/data/inertial_number", column(inertial), "1", "DEM I");
  h5.write("/data/normal_stress", column([](const DataPoint& p) { return p.normal_stress; }), "Pa",
           "DEM σ_yy");
  std::vector<long> training;
  for (char held : o.data.held) training.push_back(held ? 0L : 1L);
  h5.write("/data/training", training, "1", "1: fitted, 0: held out");
  for (int k = 0; k < observable_count; ++k) {
    const std::string& n = observable_names()[k];
    h5.write("/data/" + n, column([&](const DataPoint& p) { return p.value[k]; }), "1", "DEM " + n);
    h5.write("/data/" + n + "_err", column([&](const DataPoint& p) { return p.error[k]; }), "1",
             "DEM standard error of " + n);
  }
  const bool constant_volume =
      !used.empty() && std::all_of(used.begin(), used.end(), [](const DataPoint& p) {
        return p.protocol == Protocol::constant_volume;
      });
  const auto phi = [](const DataPoint& p) {
    return p.value[static_cast<int>(Observable::solid_fraction)];
  };
  double lo = INFINITY, hi = 0, p_mean = 0, rate_mean = 0;
  for (const auto& p : used) {
    lo = std::min(lo, constant_volume ? phi(p) : inertial(p));
    hi = std::max(hi, constant_volume ? phi(p) : inertial(p));
    p_mean += p.normal_stress / static_cast<double>(used.size());
    rate_mean += p.shear_rate / static_cast<double>(used.size());
  }
  const int n_grid = 80;
  std::vector<double> grid;
  for (int g = 0; g < n_grid; ++g)
    grid.push_back(constant_volume
                       ? lo + (hi - lo) * g / double(n_grid - 1)  // the swept φ, linear
                       : lo / 1.5 * std::pow(hi * 1.5 / (lo / 1.5), g / double(n_grid - 1)));
  if (constant_volume) {
    h5.write("/data/solid_fraction_imposed", column(phi), "1", "DEM φ (imposed)");
    h5.write("/curves/solid_fraction", grid, "1", "φ of the curves");
    h5.attribute("/curves", "protocol", std::string("constant_volume"));
    h5.attribute("/curves", "shear_rate", rate_mean);
  } else {
    h5.write("/curves/inertial_number", grid, "1", "I of the curves");
    h5.attribute("/curves", "protocol", std::string("constant_pressure"));
    h5.attribute("/curves", "normal_stress", p_mean);
  }
  int written = 0;
  const auto& same = o.column("same_as_rank").values;
  for (std::size_t r = 0; r < o.order.size() && written < 3; ++r) {
    const std::size_t i = o.order[r];
    const auto& f = o.fits[i];
    if (!f.ok) break;
    if (std::isfinite(same[i])) continue;
    int twins = 0;
    for (const std::size_t n : o.order) twins += same[n] == r + 1.0 ? 1 : 0;
    const auto& comb = s.combinations[i];
    const Eigen::VectorXd estimate =
        Eigen::Map<const Eigen::VectorXd>(f.estimate.data(), Eigen::Index(f.estimate.size()));
    const CalibratedModel m = apply(start_model(*comb.run_case), comb.parameters, estimate);
    std::vector<std::vector<double>> curves(observable_count);
    for (const double x : grid) {
      DataPoint point;
      if (constant_volume) {
        point.protocol = Protocol::constant_volume;
        point.shear_rate = rate_mean;
        point.normal_stress = NAN;
        point.value[static_cast<int>(Observable::solid_fraction)] = x;
      } else {
        point.shear_rate = x * std::sqrt(p_mean / rho) / d;
        point.normal_stress = p_mean;
      }
      point.particle_friction = comb.run_case->has("data.particle_friction")
                                    ? comb.run_case->number("data.particle_friction")
                                    : NAN;
      const auto state = predict(m, point);
      for (int k = 0; k < observable_count; ++k)
        curves[k].push_back(state.ok ? predicted(state, Observable(k)) : NAN);
    }
    const std::string group = fmt::format("/curves/{}", ++written);
    for (int k = 0; k < observable_count; ++k)
      h5.write(group + "/" + observable_names()[k], curves[k], "1",
               "continuum steady " + observable_names()[k] + ", rank " + std::to_string(written));
    h5.attribute(group, "label",
                 comb.label + (twins ? fmt::format(" (+{} identical)", twins) : std::string()));
    h5.attribute(group, "rank", static_cast<long>(r + 1));
    h5.attribute(group, "aic", f.aic);
    h5.attribute(group, "chi2_red", f.chi2_red);
  }
  h5.attribute("/curves", "count", static_cast<long>(written));
  h5.flush();
}

// analysis/plots/plot_closures.py DIR, started from an argument vector (no shell), its output
// appended to log.txt. False (and a warning) when it cannot run.
bool run_plot(const fs::path& dir, spdlog::logger& log) {
  const auto script = core::source_dir() / "analysis" / "plots" / "plot_closures.py";
  if (!fs::exists(script)) {
    core::record_plot_failure();
    log.warn("plot script {} not found; no closures.png", script.string());
    return false;
  }
  core::ProcessOptions options;
  options.output = dir / "log.txt";
  options.append = true;
  const core::ProcessResult r =
      core::run_process({core::python_interpreter(), script.string(), dir.string()}, options);
  if (!r.ok()) {
    core::record_plot_failure();
    log.warn("{} {} failed ({}); data in closures.h5", core::python_interpreter(), script.string(),
             r.started()
                 ? fmt::format("exit {}; python3-matplotlib and python3-h5py installed?", r.status)
                 : r.error);
    return false;
  }
  return true;
}

}  // namespace

void write_closure_study(const ClosureStudyResults& results, const fs::path& dir, bool plot,
                         spdlog::logger& log, std::chrono::steady_clock::time_point started) {
  Study t{results.study, results.data, results.fits, results.order, {}, 0};
  build_table(t);
  write_curves(t, dir / "closures.h5");
  const bool plotted = plot && run_plot(dir, log);
  t.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  write_csv(t, dir / "closures.csv");
  write_json(t, dir / "study.json");
  write_report(t, dir / "report.md", plotted);
  for (std::size_t r = 0; r < std::min<std::size_t>(5, t.order.size()); ++r) {
    const std::size_t i = t.order[r];
    log.info("rank {}: {}: k = {}, χ²_red = {}, AIC = {}", r + 1,
             results.study.combinations[i].label, t.fits[i].k, num(t.fits[i].chi2_red, "{:.4g}"),
             num(t.fits[i].aic, "{:.6g}"));
  }
  log.info("finished in {:.3f} s; results in {}", t.wall_s, dir.string());
}

}  // namespace granflow::calibration
