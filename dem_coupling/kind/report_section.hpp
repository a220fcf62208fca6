// The DEM kind's section of report.md (core::KindEntry::report): a sweep's rheology fits
// re-derived from result.h5 without rerunning LIGGGHTS (also for an interrupted sweep, which has
// result.h5 but no summary.json yet): /fits of result.h5 and the fit.* and boyer.* keys of
// summary.json rewritten, plot_dem.py redrawn, and the Markdown tables returned.
#pragma once

#include <filesystem>
#include <string>

#include "core/run.hpp"

namespace granflow::dem {

std::string dem_report_section(const std::filesystem::path& run_dir, core::Summary& summary);

}  // namespace granflow::dem
