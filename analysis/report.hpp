// `granflow report RUN_DIR`: one readable Markdown report of a finished run (any kind): the case,
// the kind's own section (core::KindEntry::report: calibration tables, DEM/continuum point by
// point, re-derived DEM fits), the summary table, and the PNG plots of the run directory embedded
// by relative path (report.md sits next to them, so it renders as is).
#pragma once

#include <filesystem>
#include <string>

#include "core/kind_registry.hpp"

namespace granflow::analysis {

// Writes RUN_DIR/report.md and returns its path. The kind and test in RUN_DIR/case.yaml select the
// kind's section from `registry` (none when this build lacks the kind). Throws std::runtime_error
// naming the file when RUN_DIR has no summary.json (not a finished run directory) and the kind
// has no section that reads an interrupted run.
std::filesystem::path write_report(const std::filesystem::path& run_dir,
                                   const core::KindRegistry& registry);

// A number in a report table: 6 significant digits, "NaN" for a missing value.
std::string report_number(double v);

}  // namespace granflow::analysis
