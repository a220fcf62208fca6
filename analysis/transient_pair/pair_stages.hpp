// The parts of a transient pair's comparison shared by its stages (transient_pair_kind.cpp):
// the metrics of both sides in summary.json and the result file, and the comparisons of the
// stages that follow or interrupt the shear: the shear stopped (held or drained) and a step in
// the shear rate (docs/transient_pairs.md).
#pragma once

#include <span>
#include <string>
#include <utility>

#include "analysis/transient_pair/continuum_transient.hpp"
#include "core/run.hpp"

namespace granflow::transient_pair {

struct Thresholds {
  double liquefaction, residual;  // transient.liquefaction_fraction, transient.residual_fraction
  double cooling;                 // stop.cooling_fraction
  double reconsolidation;         // stop.reconsolidation_fraction
};

// model / data − 1 (NaN when data is 0).
double relative_error(double model, double data);

// summary.json key of a metric: transient.SIDE.NAME, with .G for condition G of a sweep.
std::string metric_key(const std::string& side, const std::string& name, const std::string& g);

using MetricPair = std::pair<const char*, std::pair<double, double>>;  // name, {DEM, continuum}

// Each metric of both sides in summary.json (transient.dem.NAME with its seed error _err when the
// DEM run has one; transient.cont{suffix}.NAME) and as attributes of the group (dem_NAME,
// cont{suffix}_NAME). The DEM's are written once, with the uncalibrated continuum.
void write_metrics(core::RunContext& ctx, std::span<const MetricPair> metrics,
                   const DemTransient& dem, const std::string& group, const std::string& g,
                   const std::string& suffix);

// A time or strain metric of both sides (-1: never reached): transient.rel_err{suffix}.NAME when
// both reached it, and "X_DEM (DEM) and X_cont (continuum), ratio R" for the log (`unit` "s" or
// "" for a strain).
std::string compare_times(core::Summary& sum, const char* name, double dem_time, double cont_time,
                          const std::string& suffix, const std::string& g, const char* unit = "s");

// The shear stopped (stop.duration > 0): the continuum's stop stage from the end of `rev`, its
// series under group/stop/NAME{suffix}, the cooling metrics of both sides (transient.dem.NAME,
// transient.cont{suffix}.NAME, transient.rel_err{suffix}.cooling_time); with a drained stop also
// the reconsolidation metrics. A numerical failure of the continuum's stop is rethrown after the
// rows so far are written.
void compare_stop(core::RunContext& ctx, const core::Case& condition, const DemTransient& dem,
                  const rev::SimpleShearResult& rev, const Thresholds& limits,
                  const std::string& group, const std::string& g, const std::string& suffix);

// A step in the shear rate (rate_step.strain): dem::rate_step_metrics of both sides (μ, φ, T
// before and after the step, the dilation, the strain to half of it, the peak μ after the step)
// in summary.json, transient.rel_err{suffix}.{mu_after_step, dilation, dilation_strain}, and a
// log line.
void compare_rate_step(core::RunContext& ctx, const core::Case& condition, const DemTransient& dem,
                       const rev::SimpleShearResult& rev, const Thresholds& limits,
                       const std::string& group, const std::string& g, const std::string& suffix);

}  // namespace granflow::transient_pair
