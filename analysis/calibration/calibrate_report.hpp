// The calibrate kind's section of report.md (core::KindEntry::report).
#pragma once

#include <filesystem>
#include <string>

#include "core/run.hpp"

namespace granflow::calibration {

std::string calibrate_report_section(const std::filesystem::path& run_dir, core::Summary& summary);

}  // namespace granflow::calibration
