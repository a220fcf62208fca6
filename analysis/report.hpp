// `granflow report RUN_DIR`: one readable Markdown report of a finished run (any kind; extra
// sections for `calibrate` and `pair`): the case, the summary table, and the PNG plots of the run
// directory embedded by relative path (report.md sits next to them, so it renders as is).
#pragma once

#include <filesystem>

namespace granflow::analysis {

// Writes RUN_DIR/report.md and returns its path. Throws std::runtime_error naming the file when
// RUN_DIR has no summary.json (not a finished run directory).
std::filesystem::path write_report(const std::filesystem::path& run_dir);

}  // namespace granflow::analysis
