// kind: calibrate end to end on a DEM-schema dataset (docs/dem_dataset.md) written here from the
// forward model with known noise: summary keys, calibrated.yaml, held-out improvement, bad input.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "analysis/calibration/calibrate_kind.hpp"
#include "analysis/calibration/calibration.hpp"
#include "tests/calibration/synthetic_data.hpp"

namespace granflow::calibration {
namespace {

const std::filesystem::path work = std::filesystem::path(GRANFLOW_BINARY_DIR) / "test_calibration";

std::string case_text(const std::filesystem::path& data, const std::string& parameters) {
  return "kind: calibrate\nname: calibrate_synthetic\n"
         "material: {diameter: 1.0e-3, particle_density: 2500, restitution: 0.7, "
         "particle_friction: 0.5}\n"
         "collisional: {jamming_fraction: 0.587}\n"
         // the synthetic data come from kinetic theory alone (testing::dry_model)
         "force_chains: {enabled: false}\n"
         "data: {files: '" +
         data.string() +
         "', observables: 'friction solid_fraction scaled_temperature'}\n"
         "fit: {parameters: '" +
         parameters + "'}\nholdout: {mode: every_other}\n";
}

TEST(CalibrateKind, FitsSyntheticDemDatasetAndWritesCalibratedFile) {
  const auto truth = testing::dry_model(0.8, 0.60);
  const auto data = testing::write_dem_dataset(testing::synthetic_points(truth, 42, 16),
                                               work / "dem_synthetic.h5");
  const auto schema = calibrate_schema();
  const auto c =
      core::Case::parse(case_text(data, "restitution jamming_fraction"), "test.yaml", {}, schema);
  check_calibrate_case(c);
  const auto dir = work / "run";
  {
    core::RunContext ctx(c, dir, true, true);
    ASSERT_EQ(run_calibrate_case(ctx), core::exit_ok);
    ctx.finish();
  }
  const auto s = core::Summary::read(dir / "summary.json");
  // One noise draw: within 3 standard errors (99.7 % for each parameter).
  EXPECT_LT(std::abs(s.get("fit.restitution") - 0.8), 3 * s.get("fit.restitution_err"));
  EXPECT_LT(std::abs(s.get("fit.jamming_fraction") - 0.60), 3 * s.get("fit.jamming_fraction_err"));
  // χ²_red of 8 points × 3 observables - 2 = 22 dof: sd 0.3; within 1 ± 1.2 (4σ).
  EXPECT_NEAR(s.get("fit.chi2_red"), 1.0, 1.2);
  // The start (e_r = 0.7, ν_c = 0.587) is far from the truth (0.8, 0.60) compared with the
  // noise: the held-out μ must be predicted better after calibration.
  EXPECT_LT(s.get("holdout.rel_err"), s.get("holdout.rel_err_uncalibrated"));
  EXPECT_EQ(s.get("holdout.points"), 8);
  EXPECT_EQ(s.get("fit.inside_domain"), 1);
  // calibrated.yaml: the fitted values under their case sections, as the summary reports them.
  const YAML::Node y = YAML::LoadFile((dir / "calibrated.yaml").string());
  EXPECT_NEAR(y["material"]["restitution"].as<double>(), s.get("fit.restitution"), 1e-9);
  EXPECT_NEAR(y["collisional"]["jamming_fraction"].as<double>(), s.get("fit.jamming_fraction"),
              1e-9);
  EXPECT_TRUE(std::filesystem::exists(dir / "result.h5"));
  // plot_calibration.py ran (python3-matplotlib and h5py are Debian dependencies of the project)
  EXPECT_TRUE(std::filesystem::exists(dir / "calibration.png"));
  const auto training = core::read_dataset(dir / "result.h5", "/data/training");
  EXPECT_EQ(training.size(), 16u);
}

TEST(CalibrateKind, BadParameterNamesAreRefusedAtTheKey) {
  const auto schema = calibrate_schema();
  const auto c =
      core::Case::parse(case_text("x.h5", "restitution viscosity"), "bad.yaml", {}, schema);
  try {
    check_calibrate_case(c);
    FAIL() << "unknown parameter accepted";
  } catch (const core::CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("fit.parameters"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("jamming_fraction"), std::string::npos) << e.what();
  }
  // The correlation-length constant needs Jenkins' L.
  const auto c2 =
      core::Case::parse(case_text("x.h5", "correlation_length_constant"), "bad.yaml", {}, schema);
  EXPECT_THROW(check_calibrate_case(c2), core::CaseError);
}

}  // namespace
}  // namespace granflow::calibration

namespace granflow::calibration {
namespace {

TEST(CalibrateKind, ShippedCaseFilesValidate) {
  const auto schema = calibrate_schema();
  const auto dir = std::filesystem::path(GRANFLOW_SOURCE_DIR) / "cases" / "calibrate";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".yaml") continue;
    {  // a closure study (calibrate case + `closures:`) is checked by test_closure_study.cpp
      std::ifstream in(entry.path());
      std::stringstream text;
      text << in.rdbuf();
      if (text.str().find("\nclosures:") != std::string::npos) continue;
    }
    const auto c = core::Case::load(entry.path(), {}, schema);
    EXPECT_NO_THROW(check_calibrate_case(c)) << entry.path();
    ++count;
  }
  EXPECT_GE(count, 2);
}

}  // namespace
}  // namespace granflow::calibration

namespace granflow::calibration {
namespace {

TEST(CalibrateKind, NamedHoldoutListAndMissingDataFile) {
  const auto work = std::filesystem::path(GRANFLOW_BINARY_DIR) / "test_calibration_list";
  const auto data = testing::write_dem_dataset(
      testing::synthetic_points(testing::dry_model(0.8, 0.60), 3, 8), work / "dem.h5");
  const auto schema = calibrate_schema();
  const std::string text =
      "kind: calibrate\nmaterial: {diameter: 1.0e-3, particle_density: 2500, "
      "restitution: 0.7}\ndata: {files: '" +
      data.string() +
      "', observables: 'solid_fraction friction'}\n"
      "fit: {parameters: 'jamming_fraction'}\n"
      "holdout: {mode: list, points: [0, 5]}\n";
  const auto c = core::Case::parse(text, "list.yaml", {}, schema);
  check_calibrate_case(c);
  {
    core::RunContext ctx(c, work / "run", true, true);
    ASSERT_EQ(run_calibrate_case(ctx), core::exit_ok);
    ctx.finish();
  }
  const auto s = core::Summary::read(work / "run" / "summary.json");
  EXPECT_EQ(s.get("holdout.points"), 2);
  EXPECT_EQ(s.get("fit.points"), 6);
  const auto training = core::read_dataset(work / "run" / "result.h5", "/data/training");
  ASSERT_EQ(training.size(), 8u);
  EXPECT_EQ(training[0], 0);
  EXPECT_EQ(training[5], 0);
  EXPECT_EQ(training[1], 1);
  // ν_c from φ (the first observable, which holdout.rel_err reports): within 3 standard errors.
  EXPECT_LT(std::abs(s.get("fit.jamming_fraction") - 0.60), 3 * s.get("fit.jamming_fraction_err"));
  EXPECT_NEAR(s.get("holdout.rel_err"), s.get("holdout.rel_err.solid_fraction"), 1e-15);

  // A missing dataset is refused at data.files, naming the path.
  const auto bad = core::Case::parse(
      "kind: calibrate\nmaterial: {diameter: 1.0e-3, particle_density: 2500, restitution: 0.7}\n"
      "data: {files: no_such_dir/result.h5}\nfit: {parameters: jamming_fraction}\n",
      "missing.yaml", {}, schema);
  core::RunContext ctx(bad, work / "run_bad", true, true);
  try {
    run_calibrate_case(ctx);
    FAIL() << "missing file accepted";
  } catch (const core::CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("data.files"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no_such_dir/result.h5"), std::string::npos) << e.what();
  }
}

// A relative data path is looked up in the working directory, then beside the case file, never
// in the source tree the binary was built from (another checkout's data would be used silently).
TEST(CalibrateKind, RelativeDataPathsNeverReachIntoTheSourceTree) {
  const auto schema = calibrate_schema();
  const auto dir = std::filesystem::temp_directory_path() / "granflow_data_path_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto c = core::Case::parse(
      "kind: calibrate\nmaterial: {diameter: 1.0e-3, particle_density: 2500, restitution: 0.7}\n"
      "data: {files: x.h5}\nfit: {parameters: jamming_fraction}\n",
      (dir / "case.yaml").string(), {}, schema);
  // A file that exists only in the source tree: work in the scratch directory.
  const auto previous = std::filesystem::current_path();
  std::filesystem::current_path(dir);
  const std::string only_in_source = "cases/calibrate/dry_mu_I.yaml";
  ASSERT_TRUE(std::filesystem::exists(std::filesystem::path(GRANFLOW_SOURCE_DIR) / only_in_source));
  ASSERT_FALSE(std::filesystem::exists(only_in_source));
  EXPECT_EQ(resolve_data_path(c, only_in_source), std::filesystem::path(only_in_source));
  // In the working directory, then beside the case file, it is found.
  std::filesystem::create_directories(dir / "data");
  std::ofstream(dir / "data" / "r.h5") << "x";
  EXPECT_EQ(resolve_data_path(c, "data/r.h5"), std::filesystem::path("data/r.h5"));
  std::filesystem::current_path(previous);
  EXPECT_EQ(resolve_data_path(c, "data/r.h5"), dir / "data" / "r.h5");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace granflow::calibration
