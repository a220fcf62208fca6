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
#include "core/kind_registry.hpp"
#include "core/process.hpp"
#include "core/result_file.hpp"
#include "core/run.hpp"

namespace granflow::analysis {

std::string report_number(double v) {
  if (std::isnan(v)) return "NaN";
  return fmt::format("{:.6g}", v);
}

namespace {

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

}  // namespace

std::filesystem::path write_report(const std::filesystem::path& run_dir,
                                   const core::KindRegistry& registry) {
  const auto summary_file = run_dir / "summary.json";
  const auto case_file = run_dir / "case.yaml";
  std::string case_problem;
  const auto case_keys = case_values(case_file, case_problem);
  const auto case_value = [&](const std::string& key) {
    const auto it = case_keys.find(key);
    return it == case_keys.end() ? std::string() : it->second;
  };
  const std::string kind = case_value("kind");
  const std::string test = case_value("test");
  const core::KindEntry* entry = registry.lookup(kind, test);
  // An interrupted run has result.h5 but no summary.json yet: a kind with a report section (a
  // DEM sweep re-derives its fits from result.h5) still reports it.
  const bool interrupted = entry && entry->report && std::filesystem::exists(run_dir / "result.h5");
  if (!std::filesystem::exists(summary_file) && !interrupted)
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
  if (!test.empty()) md << ", test: `" << test << "`";
  md << ". Run directory: `" << run_dir.string() << "`.\n\n";
  if (!case_problem.empty())
    md << "**case.yaml could not be read** (" << case_problem
       << "); the kind and name above are unknown, only summary.json is reported.\n\n";
  if (!description.empty()) md << description << "\n\n";
  if (entry && entry->report) md << entry->report(run_dir, s);

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
    for (const auto& [key, value] : rows)
      md << "| `" << key << "` | " << report_number(value) << " |\n";
    md << "\n";
  }
  md << "Files: [case.yaml](case.yaml) (the case as run), result.h5 (data), "
        "[log.txt](log.txt).\n";
  const auto out = run_dir / "report.md";
  core::write_text_file(out, md.str());
  return out;
}

}  // namespace granflow::analysis
