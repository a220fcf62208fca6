// `kind: calibrate` (docs/calibration.md): fits closure parameters to DEM steady simple-shear
// datasets (docs/dem_dataset.md) and writes calibrated.yaml for rev/mpm cases.
#pragma once

#include "core/kind_registry.hpp"

namespace granflow::calibration {

core::Schema calibrate_schema();
void check_calibrate_case(const core::Case& c);
// The data the case reads (files and tables), checked before the run directory exists.
void check_calibrate_data(const core::Case& c);
int run_calibrate_case(core::RunContext& ctx);

// Registers kind `calibrate` (the CLI calls this from app/registry.cpp).
void register_calibrate_kinds(core::KindRegistry& registry);

}  // namespace granflow::calibration
