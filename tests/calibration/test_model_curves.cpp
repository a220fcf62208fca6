// The smooth model curves of kind: calibrate (analysis/calibration/model_curves.hpp, result.h5
// /curve/N): they span the swept range of the data's condition variable (γ̇ at constant pressure,
// φ at constant volume), and two paths agree: the curve's conditions at each data row's own x
// give, through the forward model, the values the kind wrote at that row (/prediction). Also the
// grouping into series (levels where x does not tell the conditions apart, repeats merged).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>

#include "analysis/calibration/calibrate_kind.hpp"
#include "analysis/calibration/calibration.hpp"
#include "analysis/calibration/model_curves.hpp"
#include "tests/calibration/synthetic_data.hpp"
#include "tests/calibration/table_data.hpp"

namespace granflow::calibration {
namespace {

const std::filesystem::path work =
    std::filesystem::path(GRANFLOW_BINARY_DIR) / "test_calibration_curves";

// Runs the calibrate kind on case `c` into `dir`.
void run(const core::Case& c, const std::filesystem::path& dir) {
  check_calibrate_case(c);
  check_calibrate_data(c);
  std::filesystem::remove_all(dir);
  core::RunContext ctx(c, dir, true, true);
  ASSERT_EQ(run_calibrate_case(ctx), core::exit_ok);
  ctx.finish();
}

// The two paths at every used row of the run: the model at the curve's conditions at the row's
// own x against /prediction/<model>/<observable> of the row. Both end in the same forward model
// at (should be) the same conditions, so they agree to rounding: the interpolation returns a
// node's own conditions at its x, and the constant-volume root in ln σ_yy stops at 1e-13;
// 1e-10 relative leaves room for that and nothing else.
void expect_curve_meets_predictions(const core::Case& c, const std::filesystem::path& dir) {
  const auto file = dir / "result.h5";
  const CaseData data = read_case_data(c);
  const auto names = split_names(c.string("fit.parameters"));
  const auto estimate = core::read_dataset(file, "/fit/estimate");
  const CalibratedModel start = read_case_model(c);
  const CalibratedModel calibrated =
      apply(start, names, Eigen::Map<const Eigen::VectorXd>(estimate.data(), estimate.size()));
  const auto series = curve_series(data.used);
  const auto member = core::read_dataset(file, "/data/curve");
  ASSERT_EQ(member.size(), data.used.size());
  for (const auto& [group, model] : std::map<std::string, const CalibratedModel*>{
           {"uncalibrated", &start}, {"calibrated", &calibrated}}) {
    for (int k = 0; k < observable_count; ++k) {
      const auto& name = observable_names()[k];
      const auto written = core::read_dataset(file, "/prediction/" + group + "/" + name);
      for (std::size_t i = 0; i < data.used.size(); ++i) {
        ASSERT_GE(member[i], 0) << "row " << i << " is on no curve";
        const CurveSeries& s = series[static_cast<std::size_t>(member[i])];
        const auto at = curve_condition(s, curve_value(data.used[i], s.variable));
        const auto state = predict(*model, at);
        ASSERT_TRUE(state.ok) << group << " row " << i << ": " << state.why;
        EXPECT_NEAR(predicted(state, Observable(k)) / written[i], 1.0, 1e-10)
            << group << " " << name << " row " << i;
      }
    }
  }
}

// The curve of series 0 spans the range of the rows' x exactly, densely and in order.
void expect_spans(const std::filesystem::path& file, const std::string& variable,
                  const std::vector<double>& rows_x) {
  EXPECT_EQ(core::read_string_attribute(file, "/curve/0", "variable"), variable);
  const auto x = core::read_dataset(file, "/curve/0/" + variable);
  ASSERT_EQ(x.size(), 150u);
  EXPECT_EQ(x.front(), *std::min_element(rows_x.begin(), rows_x.end()));
  EXPECT_EQ(x.back(), *std::max_element(rows_x.begin(), rows_x.end()));
  for (std::size_t j = 1; j < x.size(); ++j) EXPECT_GT(x[j], x[j - 1]) << j;
}

TEST(CalibrationCurves, ConstantPressureCurveSpansTheShearRatesAndMeetsTheModelAtTheRows) {
  // Kinetic theory alone (the synthetic model of synthetic_data.hpp) at σ_yy scattered ±10 %
  // about 100 Pa as a DEM servo leaves it, so that the curve must interpolate σ_yy between rows.
  const auto truth = testing::dry_model(0.8, 0.60);
  auto points = testing::synthetic_points(truth, 5, 10);
  for (std::size_t i = 0; i < points.size(); ++i) {
    auto& p = points[i];
    p.normal_stress = 100.0 * (1.0 + 0.1 * std::sin(3.0 * static_cast<double>(i)));
    const auto s = predict(truth, p);
    p.inertial_number = s.inertial_number;
    p.value[0] = s.friction, p.value[1] = s.solid_fraction, p.value[2] = s.scaled_temperature;
    p.error[2] = 0.05 * s.scaled_temperature;
  }
  const auto data = testing::write_dem_dataset(points, work / "dem.h5");
  const auto schema = calibrate_schema();
  const auto c = core::Case::parse(
      "kind: calibrate\nname: curves_pressure\n"
      "material: {diameter: 1.0e-3, particle_density: 2500, restitution: 0.7, "
      "particle_friction: 0.5}\ncollisional: {jamming_fraction: 0.587}\n"
      "force_chains: {enabled: false}\ndata: {files: '" +
          data.string() +
          "', observables: 'friction solid_fraction scaled_temperature'}\n"
          "fit: {parameters: 'restitution jamming_fraction'}\nholdout: {mode: every_other}\n",
      "curves.yaml", {}, schema);
  const auto dir = work / "pressure";
  run(c, dir);
  const auto file = dir / "result.h5";
  std::vector<double> rates;
  for (const auto& p : points) rates.push_back(p.shear_rate);
  expect_spans(file, "shear_rate", rates);
  EXPECT_EQ(core::read_string_attribute(file, "/curve/0", "axis"), "inertial_number");
  for (double m : core::read_dataset(file, "/data/curve")) EXPECT_EQ(m, 0);  // one series
  expect_curve_meets_predictions(c, dir);
  // At fixed σ_yy, I ∝ γ̇: the drawn abscissa rises along the curve, and the imposed σ_yy stays
  // between the rows' extremes (interpolated, never extrapolated).
  const auto I = core::read_dataset(file, "/curve/0/inertial_number");
  const auto sigma = core::read_dataset(file, "/curve/0/normal_stress");
  for (std::size_t j = 0; j < sigma.size(); ++j) {
    EXPECT_GE(sigma[j], 90.0 - 1e-9);
    EXPECT_LE(sigma[j], 110.0 + 1e-9);
  }
  EXPECT_GT(I.back() / I.front(), 20.0);  // γ̇ over 30×, σ_yy within ±10 %
}

TEST(CalibrationCurves, ConstantVolumeCurveIsOverTheSolidFraction) {
  // The shipped constant-volume table (cases/calibrate/from_table.yaml): φ from 0.560 to 0.587
  // with repeats at 0.572 and 0.581, γ̇ = 1 (dimensionless).
  const auto schema = calibrate_schema();
  const auto c = core::Case::load(testing::example_case(), {}, schema);
  const auto dir = work / "volume";
  run(c, dir);
  const auto file = dir / "result.h5";
  expect_spans(file, "solid_fraction", core::read_dataset(file, "/data/solid_fraction"));
  EXPECT_EQ(core::read_string_attribute(file, "/curve/0", "protocol"), "constant_volume");
  EXPECT_EQ(core::read_string_attribute(file, "/curve/0", "axis"), "solid_fraction");
  for (double rate : core::read_dataset(file, "/curve/0/shear_rate")) EXPECT_EQ(rate, 1.0);
  expect_curve_meets_predictions(c, dir);
  // On the dense branch the normal stress at constant volume rises with φ (the skeleton's
  // critical state line and kinetic theory's g0 both stiffen towards jamming): p* increases
  // along the curve, before and after the fit.
  for (const char* group : {"uncalibrated", "calibrated"}) {
    const auto p = core::read_dataset(file, std::string("/curve/0/") + group + "/scaled_pressure");
    for (std::size_t j = 1; j < p.size(); ++j) EXPECT_GT(p[j], p[j - 1]) << group << " " << j;
  }
}

DataPoint row(Protocol protocol, double rate, double sigma, double phi, double eta0) {
  DataPoint p;
  p.protocol = protocol;
  p.shear_rate = rate;
  p.normal_stress = sigma;
  p.value[static_cast<int>(Observable::solid_fraction)] = phi;
  p.liquid_viscosity = eta0;
  p.particle_friction = 0.5;
  return p;
}

TEST(CalibrationCurves, SeriesSplitIntoLevelsOnlyWhereTheVariableDoesNotTellRowsApart) {
  // An immersed sweep of η0 at one γ̇ and two σ_yy (the DEM wet sweep's design): x = η0, two
  // levels of four rows, each curve through its own rows' σ_yy.
  std::vector<DataPoint> wet;
  for (double sigma : {25.0, 100.0})
    for (double eta0 : {0.25, 0.025, 0.0025, 0.00025})
      wet.push_back(row(Protocol::constant_pressure, 10, sigma * (1 + eta0), NAN, eta0));
  auto series = curve_series(wet);
  ASSERT_EQ(series.size(), 2u);
  for (const auto& s : series) {
    EXPECT_EQ(s.variable, CurveVariable::liquid_viscosity);
    ASSERT_EQ(s.rows.size(), 4u);
    EXPECT_EQ(s.lower, 0.00025);
    EXPECT_EQ(s.upper, 0.25);
    for (const auto i : s.rows) {
      const auto at = curve_condition(s, wet[i].liquid_viscosity);
      EXPECT_EQ(at.normal_stress, wet[i].normal_stress);
      EXPECT_EQ(at.shear_rate, 10.0);
    }
  }
  // A dry γ̇ sweep with a servo 10-50 % off its target at two rows: one series, no levels.
  std::vector<DataPoint> dry;
  for (int i = 0; i < 6; ++i)
    dry.push_back(row(Protocol::constant_pressure, 2.0 * std::pow(2.0, i),
                      i == 0 ? 150.0 : (i == 3 ? 91.0 : 100.0), NAN, NAN));
  series = curve_series(dry);
  ASSERT_EQ(series.size(), 1u);
  EXPECT_EQ(series[0].variable, CurveVariable::shear_rate);
  // Between the rows σ_yy stays within its neighbours' values (a monotone cubic: no overshoot),
  // is flat where they are equal (rows 4, 5), and has no kink at a row: the slope of ln σ_yy in
  // ln γ̇ on both sides of row 1 agrees to O(ε) (linear interpolation: -0.58 against 0).
  const auto sigma = [&](double rate) { return curve_condition(series[0], rate).normal_stress; };
  for (double t = 0.05; t < 1; t += 0.05) {
    const double between = sigma(2.0 * std::pow(2.0, t));
    EXPECT_GT(between, 100.0);
    EXPECT_LT(between, 150.0);
    EXPECT_NEAR(sigma(32.0 * std::pow(2.0, t)), 100.0, 1e-12 * 100);
  }
  const double u1 = std::log(4.0), eps = 1e-6;
  const double left = (std::log(sigma(4.0)) - std::log(sigma(std::exp(u1 - eps)))) / eps;
  const double right = (std::log(sigma(std::exp(u1 + eps))) - std::log(sigma(4.0))) / eps;
  EXPECT_NEAR(left, right, 1e-4);
  // Constant volume with a repeated φ at the same γ̇: one node for both rows.
  std::vector<DataPoint> volume;
  for (double phi : {0.56, 0.57, 0.57, 0.58})
    volume.push_back(row(Protocol::constant_volume, 1.0, NAN, phi, NAN));
  series = curve_series(volume);
  ASSERT_EQ(series.size(), 1u);
  EXPECT_EQ(series[0].variable, CurveVariable::solid_fraction);
  EXPECT_EQ(series[0].rows.size(), 4u);
  EXPECT_EQ(series[0].nodes.size(), 3u);
  // A single condition has no range to draw: no series, the row on no curve.
  EXPECT_TRUE(curve_series({row(Protocol::constant_pressure, 1.0, 100.0, NAN, NAN)}).empty());
}

}  // namespace
}  // namespace granflow::calibration
