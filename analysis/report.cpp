#include "analysis/report.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/file_io.hpp"
#include "core/process.hpp"
#include "core/result_file.hpp"
#include "core/run.hpp"
#include "dem_coupling/kind/dem_fits_file.hpp"

namespace granflow::analysis {

namespace {

std::string number(double v) {
  if (std::isnan(v)) return "NaN";
  return fmt::format("{:.6g}", v);
}

// The top-level scalars of the resolved case.yaml ("kind", "name", ...); empty when the file is
// missing. `problem` says why a file that exists could not be read (it is then ignored).
std::map<std::string, std::string> case_values(const std::filesystem::path& case_file,
                                               std::string& problem) {
  std::map<std::string, std::string> values;
  if (!std::filesystem::exists(case_file)) return values;
  try {
    const YAML::Node root = YAML::LoadFile(case_file.string());
    if (!root.IsMap()) {
      problem = "not a map of case sections";
      return values;
    }
    for (const auto& item : root)
      if (item.second.IsScalar()) values[item.first.as<std::string>()] = item.second.Scalar();
  } catch (const YAML::Exception& e) {
    problem = e.what();
    values.clear();
  }
  return values;
}

// Summary keys "a.b.c": group by the first component.
std::map<std::string, std::vector<std::pair<std::string, double>>> grouped(const core::Summary& s) {
  std::map<std::string, std::vector<std::pair<std::string, double>>> out;
  for (const auto& [key, value] : s.values()) {
    const auto dot = key.find('.');
    out[dot == std::string::npos ? key : key.substr(0, dot)].push_back({key, value});
  }
  return out;
}

void calibrate_section(std::ostream& md, const core::Summary& s) {
  std::vector<std::string> parameters;
  for (const auto& [key, value] : s.values()) {
    if (key.rfind("fit.", 0) != 0) continue;
    const std::string name = key.substr(4);
    if (s.contains(key + "_err") && s.contains(key + "_initial")) parameters.push_back(name);
  }
  md << "## Calibration\n\n| parameter | estimate | standard error | start |\n|---|---|---|---|\n";
  for (const auto& p : parameters)
    md << fmt::format("| {} | {} | {} | {} |\n", p, number(s.get("fit." + p)),
                      number(s.get("fit." + p + "_err")), number(s.get("fit." + p + "_initial")));
  md << "\n";
  if (s.contains("fit.chi2_red"))
    md << fmt::format(
        "χ²_red = {} ({} degrees of freedom; ≈ 1 when the model and the DEM error "
        "bars are consistent).\n\n",
        number(s.get("fit.chi2_red")), s.contains("fit.dof") ? number(s.get("fit.dof")) : "?");
  if (s.contains("fit.inside_domain") && s.get("fit.inside_domain") == 0)
    md << "**Warning:** the estimate lies on a parameter bound; it is not a minimum.\n\n";
  if (s.contains("fit.identifiable") && s.get("fit.identifiable") == 0)
    md << "**Warning:** the data do not constrain every parameter (singular Jᵀ W J).\n\n";
  if (s.contains("holdout.rel_err"))
    md << fmt::format(
        "Held-out check ({} points): mean relative error {} calibrated vs {} uncalibrated.\n\n",
        s.contains("holdout.points") ? number(s.get("holdout.points")) : "?",
        number(s.get("holdout.rel_err")),
        s.contains("holdout.rel_err_uncalibrated") ? number(s.get("holdout.rel_err_uncalibrated"))
                                                   : "?");
  md << "Calibrated parameter file: [calibrated.yaml](calibrated.yaml).\n\n";
}

void pair_section(std::ostream& md, const core::Summary& s) {
  if (!s.contains("pair.count")) return;
  const int count = static_cast<int>(s.get("pair.count"));
  // The headline columns first, then any other per-point pair.N.* key.
  std::vector<std::string> columns = {"mu_dem", "mu_dem_err", "mu_cont", "rel_err_mu",
                                      "e_dem",  "e_cont",     "T_dem",   "T_cont"};
  std::set<std::string> known(columns.begin(), columns.end());
  for (const auto& [key, value] : s.values()) {
    if (key.rfind("pair.0.", 0) != 0) continue;
    const std::string name = key.substr(7);
    if (known.insert(name).second) columns.push_back(name);
  }
  md << "## DEM and continuum, point by point\n\n| point |";
  for (const auto& c : columns) md << " " << c << " |";
  md << "\n|---|";
  for (std::size_t i = 0; i < columns.size(); ++i) md << "---|";
  md << "\n";
  for (int n = 0; n < count; ++n) {
    md << "| " << n << " |";
    for (const auto& c : columns) {
      const std::string key = fmt::format("pair.{}.{}", n, c);
      std::string cell = s.contains(key) ? number(s.get(key)) : "";
      if (c == "regime" && s.contains(key)) {  // analysis/pair: 0..3 -> name
        static const char* regimes[] = {"quasi-static", "dense inertial", "collisional", "viscous"};
        const int r = static_cast<int>(s.get(key));
        if (r >= 0 && r < 4) cell = regimes[r];
      }
      md << " " << cell << " |";
    }
    md << "\n";
  }
  md << "\n";
  if (s.contains("pair.fit.chi2_red")) {  // the pair's own calibration (its `calibrate` section)
    md << "## The continuum calibrated on these DEM points\n\n"
          "Fitted on the even points, the odd ones held out (`_cal` columns above; "
          "`pair.fit.*` below). χ²_red = "
       << number(s.get("pair.fit.chi2_red"))
       << ".\n\n| held-out observable | calibrated | "
          "uncalibrated |\n|---|---|---|\n";
    for (const char* o : {"friction", "solid_fraction", "scaled_temperature"}) {
      const std::string key = std::string("pair.holdout.rel_err.") + o;
      const std::string before = std::string("pair.holdout.rel_err_uncalibrated.") + o;
      if (!s.contains(key)) continue;
      md << "| " << o << " | " << number(s.get(key)) << " | "
         << (s.contains(before) ? number(s.get(before)) : "") << " |\n";
    }
    md << "\n";
  }
}

// kind: dem (sweeps): re-derive the fits from result.h5 without rerunning LIGGGHTS
// (dem_coupling/kind/dem_fits.hpp): rewrite /fits in result.h5, the fit.* and boyer.* keys of
// summary.json, redraw the plots (plot_dem.py), and return the Markdown tables.
std::string dem_section(const std::filesystem::path& run_dir, core::Summary& s) {
  const auto result = run_dir / "result.h5";
  if (!std::filesystem::exists(result)) return "";
  // strain.total of the case: a sweep without /steady (running or interrupted) is read from
  // /conditions/N, and a condition that stopped before it is left out.
  double total_strain = std::numeric_limits<double>::quiet_NaN();
  try {
    const YAML::Node node = YAML::LoadFile((run_dir / "case.yaml").string());
    if (node["strain"] && node["strain"]["total"])
      total_strain = node["strain"]["total"].as<double>();
  } catch (const std::exception&) {
  }
  const dem::DemSteadyTable table = dem::read_dem_steady_table(result, total_strain);
  if (table.rows() < 2) return "";  // a single condition: nothing to fit
  const dem::DemFits fits = dem::compute_dem_fits(table);
  {
    dem::AppendedResultFile file(result);
    file.remove("/fits");
    dem::write_dem_fits(fits, table, file);
    if (fits.wet && std::isfinite(fits.mixed.alpha()))
      file.attribute("/steady", "fitted_alpha", fits.mixed.alpha());
  }
  // Old keys are kept except boyer.* (rewritten); a run made before the free mixed-number fit
  // had the one-parameter Boyer-in-K α as fit.alpha: it becomes fit.alpha_boyer*.
  std::map<std::string, double> kept;
  for (const auto& [key, value] : s.values())
    if (key.rfind("boyer.", 0) != 0) kept[key] = value;
  if (fits.wet && kept.count("fit.alpha_rms")) {
    kept["fit.alpha_boyer"] = kept["fit.alpha"];
    kept["fit.alpha_boyer_rms"] = kept["fit.alpha_rms"];
    kept["fit.alpha_boyer_chi2_per_dof"] = kept["fit.alpha_chi2_per_dof"];
    kept.erase("fit.alpha_rms");
    kept.erase("fit.alpha_chi2_per_dof");
  }
  core::Summary updated;
  for (const auto& [key, value] : kept) updated.set(key, value);
  for (const auto& [key, value] : dem::dem_fit_summary(fits, table)) updated.set(key, value);
  updated.write(run_dir / "summary.json");
  s = updated;
  core::ProcessOptions options;
  options.output = run_dir / "plot_dem.log";
  const core::ProcessResult plotted = core::run_process(
      {core::python_interpreter(),
       (core::source_dir() / "analysis" / "plots" / "plot_dem.py").string(), run_dir.string()},
      options);
  std::string md = dem::dem_fits_markdown(fits, table);
  if (!plotted.started())
    md += fmt::format("**Note:** plot_dem.py did not run: {}.\n\n", plotted.error);
  else if (plotted.status != 0)
    md += fmt::format("**Note:** plot_dem.py failed (exit {}); see plot_dem.log.\n\n",
                      plotted.status);
  return md +
         "The fits above were re-derived from result.h5 by `granflow report` (written to "
         "/fits of result.h5 and to summary.json).\n\n";
}

}  // namespace

std::filesystem::path write_report(const std::filesystem::path& run_dir) {
  const auto summary_file = run_dir / "summary.json";
  const auto case_file = run_dir / "case.yaml";
  std::string case_problem;
  const auto case_keys = case_values(case_file, case_problem);
  const auto case_value = [&](const std::string& key) {
    const auto it = case_keys.find(key);
    return it == case_keys.end() ? std::string() : it->second;
  };
  const std::string kind = case_value("kind");
  // An interrupted DEM sweep has result.h5 but no summary.json yet: its fits are still derived.
  const bool interrupted_dem = kind == "dem" && std::filesystem::exists(run_dir / "result.h5");
  if (!std::filesystem::exists(summary_file) && !interrupted_dem)
    throw std::runtime_error(
        fmt::format("{}: no summary.json; expected the directory of a finished granflow run",
                    run_dir.string()));
  core::Summary s =
      std::filesystem::exists(summary_file) ? core::Summary::read(summary_file) : core::Summary();
  std::string name = case_value("name");
  if (name.empty()) name = run_dir.filename().string();
  const std::string description = case_value("description");

  std::ostringstream md;
  md << "# " << name << "\n\n";
  md << "Kind: `" << (kind.empty() ? "?" : kind) << "`";
  const std::string test = case_value("test");
  if (!test.empty()) md << ", test: `" << test << "`";
  md << ". Run directory: `" << run_dir.string() << "`.\n\n";
  if (!case_problem.empty())
    md << "**case.yaml could not be read** (" << case_problem
       << "); the kind and name above are unknown, only summary.json is reported.\n\n";
  if (!description.empty()) md << description << "\n\n";
  if (kind == "calibrate") calibrate_section(md, s);
  if (kind == "pair") pair_section(md, s);
  if (kind == "dem") md << dem_section(run_dir, s);

  std::vector<std::filesystem::path> pngs;
  for (const auto& entry : std::filesystem::directory_iterator(run_dir))
    if (entry.path().extension() == ".png") pngs.push_back(entry.path().filename());
  std::sort(pngs.begin(), pngs.end());
  if (!pngs.empty()) {
    md << "## Plots\n\n";
    for (const auto& png : pngs)
      md << "![" << png.stem().string() << "](" << png.string() << ")\n\n";
  }

  md << "## Summary (summary.json)\n\n";
  for (const auto& [group, rows] : grouped(s)) {
    md << "### " << group << "\n\n| key | value |\n|---|---|\n";
    for (const auto& [key, value] : rows) md << "| `" << key << "` | " << number(value) << " |\n";
    md << "\n";
  }
  md << "Files: [case.yaml](case.yaml) (the case as run), result.h5 (data), "
        "[log.txt](log.txt).\n";
  const auto out = run_dir / "report.md";
  core::write_text_file(out, md.str());
  return out;
}

}  // namespace granflow::analysis
