// The pair kind's section of `granflow report` (analysis/report.hpp): DEM and continuum point by
// point and, when the pair calibrated the continuum, its held-out errors.
#include "analysis/pair/pair_report.hpp"

#include <fmt/format.h>

#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/report.hpp"

namespace granflow::pair {

using analysis::report_number;

std::string pair_report_section(const std::filesystem::path&, core::Summary& s) {
  if (!s.contains("pair.count")) return "";
  std::ostringstream md;
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
      std::string cell = s.contains(key) ? report_number(s.get(key)) : "";
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
       << report_number(s.get("pair.fit.chi2_red"))
       << ".\n\n| held-out observable | calibrated | "
          "uncalibrated |\n|---|---|---|\n";
    for (const char* o : {"friction", "solid_fraction", "scaled_temperature"}) {
      const std::string key = std::string("pair.holdout.rel_err.") + o;
      const std::string before = std::string("pair.holdout.rel_err_uncalibrated.") + o;
      if (!s.contains(key)) continue;
      md << "| " << o << " | " << report_number(s.get(key)) << " | "
         << (s.contains(before) ? report_number(s.get(before)) : "") << " |\n";
    }
    md << "\n";
  }
  return md.str();
}

}  // namespace granflow::pair
