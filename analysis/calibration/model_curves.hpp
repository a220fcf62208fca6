// Smooth model curves of a calibration (result.h5 /curve/N, drawn by plot_calibration.py): the
// forward model (predict, calibration.hpp) evaluated densely over the swept range of the DEM
// data's condition variable, so that the plot draws the model itself, not straight lines between
// its values at the data points. The mechanism of the pair kind's /pair/curve: the C++ model
// writes the curve, Python only draws it.
//
// Series. The used rows are grouped by protocol, μ_p and dry/immersed; the condition variable x of
// a group is
//   - constant volume: the imposed solid fraction φ (linear grid);
//   - constant pressure: the shear rate γ̇ when the group has more than one, else η0 (an immersed
//     sweep of the viscosity at one γ̇), else σ_yy (log grids).
// The other conditions (γ̇, σ_yy at constant pressure, η0) are interpolated between the rows by a
// monotone cubic (Fritsch-Carlson) in ln of the condition against the coordinate u = ln x (u = φ
// at constant volume): the row's own at u of a row, so that the curve meets the model's value at
// every data point, C¹ there (no kink where a DEM servo left σ_yy off its target) and within the
// neighbouring rows' values between them (the pair's curves interpolate σ_yy linearly in ln γ̇,
// with a kink at each row). Where rows with the same x differ in the
// other conditions (e.g. two σ_yy levels at each η0), the group is split into levels: rows whose
// other conditions lie within a factor 1.3 of a level's first row (the pair's grouping of σ_yy
// levels); repeats with the same x in a level are merged (the mean of ln of each condition).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "analysis/calibration/calibration.hpp"
#include "core/result_file.hpp"

namespace granflow::calibration {

enum class CurveVariable { shear_rate, solid_fraction, liquid_viscosity, normal_stress };
// The result.h5 name of the condition (core/result_columns.hpp): "shear_rate", ...
const char* curve_variable_name(CurveVariable variable);

struct CurveSeries {
  Protocol protocol = Protocol::constant_pressure;
  CurveVariable variable = CurveVariable::shear_rate;
  std::vector<std::size_t> rows;  // indices of its rows in the points given to curve_series
  // One per distinct x, sorted by x: the conditions the curve interpolates (repeats merged).
  std::vector<DataPoint> nodes;
  double lower = 0, upper = 0;  // the swept range of x: the smallest and largest row's
};

// The point's value of the condition variable (φ = value[solid_fraction]).
double curve_value(const DataPoint& point, CurveVariable variable);
// The series of `points` (see above). A level with a single distinct x has no range and no
// series: its rows are in none.
std::vector<CurveSeries> curve_series(const std::vector<DataPoint>& points);
// The conditions at x (clamped to [lower, upper]): protocol and μ_p of the series, γ̇, σ_yy
// (constant pressure; NaN at constant volume, where the model predicts it), φ (constant volume)
// and η0 interpolated as above; at the x of a node, that node's conditions exactly.
DataPoint curve_condition(const CurveSeries& series, double x);
// `count` values of x from lower to upper inclusive: log spaced (γ̇, η0, σ_yy) or linear (φ).
std::vector<double> curve_grid(const CurveSeries& series, int count);

// Writes /curve/N for every series (attributes protocol, variable, axis, particle_friction,
// count): the conditions along the grid and, per model in `models` (group name -> model, e.g.
// "calibrated"), the four observables and I as predicted there (NaN where the model has no
// steady state). Returns, per point, the index N of the series whose rows include it (-1: none).
std::vector<long> write_model_curves(core::ResultFile& out, const std::vector<DataPoint>& points,
                                     const std::map<std::string, const CalibratedModel*>& models,
                                     int count = 150);

}  // namespace granflow::calibration
