// The calibrate kind's section of `granflow report` (analysis/report.hpp): the fitted parameters
// with their standard errors and starts, χ²_red, the warnings of the fit and the held-out check.
#include "analysis/calibration/calibrate_report.hpp"

#include <fmt/format.h>

#include <sstream>
#include <string>
#include <vector>

#include "analysis/report.hpp"

namespace granflow::calibration {

using analysis::report_number;

std::string calibrate_report_section(const std::filesystem::path&, core::Summary& s) {
  std::ostringstream md;
  std::vector<std::string> parameters;
  for (const auto& [key, value] : s.values()) {
    if (key.rfind("fit.", 0) != 0) continue;
    const std::string name = key.substr(4);
    if (s.contains(key + "_err") && s.contains(key + "_initial")) parameters.push_back(name);
  }
  md << "## Calibration\n\n| parameter | estimate | standard error | start |\n|---|---|---|---|\n";
  for (const auto& p : parameters)
    md << fmt::format("| {} | {} | {} | {} |\n", p, report_number(s.get("fit." + p)),
                      report_number(s.get("fit." + p + "_err")),
                      report_number(s.get("fit." + p + "_initial")));
  md << "\n";
  if (s.contains("fit.chi2_red"))
    md << fmt::format(
        "χ²_red = {} ({} degrees of freedom; ≈ 1 when the model and the DEM error "
        "bars are consistent).\n\n",
        report_number(s.get("fit.chi2_red")),
        s.contains("fit.dof") ? report_number(s.get("fit.dof")) : "?");
  if (s.contains("fit.inside_domain") && s.get("fit.inside_domain") == 0)
    md << "**Warning:** the estimate lies on a parameter bound; it is not a minimum.\n\n";
  if (s.contains("fit.identifiable") && s.get("fit.identifiable") == 0)
    md << "**Warning:** the data do not constrain every parameter (singular Jᵀ W J).\n\n";
  if (s.contains("holdout.rel_err"))
    md << fmt::format(
        "Held-out check ({} points): mean relative error {} calibrated vs {} uncalibrated.\n\n",
        s.contains("holdout.points") ? report_number(s.get("holdout.points")) : "?",
        report_number(s.get("holdout.rel_err")),
        s.contains("holdout.rel_err_uncalibrated")
            ? report_number(s.get("holdout.rel_err_uncalibrated"))
            : "?");
  md << "Calibrated parameter file: [calibrated.yaml](calibrated.yaml).\n\n";
  return md.str();
}

}  // namespace granflow::calibration
