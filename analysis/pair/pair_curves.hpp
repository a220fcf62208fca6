// The pair's smooth model curves (/pair/curve, /pair/curve_J), beside the DEM points, written by
// run_pair_case (pair_kind.cpp).
#pragma once

#include <vector>

#include "analysis/calibration/calibration.hpp"
#include "core/run.hpp"

namespace granflow::pair {

// Smooth model curves over the DEM's range of γ̇ (a factor 2 beyond each end, 80 rates, log
// spaced) with the first point's μ_p and η0: /pair/curve/*. The normal stress follows the DEM's
// measured σ_yy (constant volume: the solid fraction follows the DEM's φ), interpolated linearly
// in log γ̇ between the points (constant beyond the ends), so that the curves pass through the
// model's values at the DEM points (the model is not a function of I alone: the critical state
// line depends on p).
void write_model_curves(core::RunContext& ctx, const std::vector<calibration::DataPoint>& points,
                        const calibration::CalibratedModel& model,
                        const calibration::CalibratedModel& kinetic,
                        const calibration::CalibratedModel* calibrated);

// Immersed pairs that vary η0: smooth curves over the viscous number J = η0 γ̇/σ_yy, one per
// level of σ_yy (points within 30 % of each other's σ_yy form a level), at the level's mean γ̇
// and σ_yy, η0 log spaced from half the smallest to twice the largest of the level:
// /pair/curve_J/<level>/{viscous_number, friction_*, solid_fraction_*, granular_temperature_*}.
void write_viscous_curves(core::RunContext& ctx, const std::vector<calibration::DataPoint>& points,
                          const calibration::CalibratedModel& model,
                          const calibration::CalibratedModel& kinetic,
                          const calibration::CalibratedModel* calibrated);

}  // namespace granflow::pair
