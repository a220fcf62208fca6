// The DEM kind's section of `granflow report` (analysis/report.hpp).
#include "dem_coupling/kind/report_section.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <limits>
#include <map>
#include <string>

#include "core/process.hpp"
#include "core/result_file.hpp"
#include "dem_coupling/kind/dem_fits_file.hpp"

namespace granflow::dem {

// kind: dem (sweeps): re-derive the fits from result.h5 without rerunning LIGGGHTS
// (dem_coupling/kind/dem_fits.hpp): rewrite /fits in result.h5, the fit.* and boyer.* keys of
// summary.json, redraw the plots (plot_dem.py), and return the Markdown tables.
std::string dem_report_section(const std::filesystem::path& run_dir, core::Summary& s) {
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
  const DemSteadyTable table = read_dem_steady_table(result, total_strain);
  if (table.rows() < 2) return "";  // a single condition: nothing to fit
  const DemFits fits = compute_dem_fits(table);
  {
    core::ResultFile file(result, core::ResultFile::Mode::append);
    file.remove("/fits");
    write_dem_fits(fits, table, file);
    if (fits.wet && std::isfinite(fits.mixed.alpha()))
      file.attribute("/steady", "fitted_alpha", fits.mixed.alpha());
    file.close();
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
  for (const auto& [key, value] : dem_fit_summary(fits, table)) updated.set(key, value);
  updated.write(run_dir / "summary.json");
  s = updated;
  core::ProcessOptions options;
  options.output = run_dir / "plot_dem.log";
  const core::ProcessResult plotted = core::run_process(
      {core::python_interpreter(),
       (core::source_dir() / "analysis" / "plots" / "plot_dem.py").string(), run_dir.string()},
      options);
  std::string md = dem_fits_markdown(fits, table);
  if (!plotted.ok()) core::record_plot_failure();
  if (!plotted.started())
    md += fmt::format("**Note:** plot_dem.py did not run: {}.\n\n", plotted.error);
  else if (plotted.status != 0)
    md += fmt::format("**Note:** plot_dem.py failed (exit {}); see plot_dem.log.\n\n",
                      plotted.status);
  return md +
         "The fits above were re-derived from result.h5 by `granflow report` (written to "
         "/fits of result.h5 and to summary.json).\n\n";
}

}  // namespace granflow::dem
