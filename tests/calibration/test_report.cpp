// analysis/report: report.md of a calibrate run holds the fit table with the summary's values,
// the held-out sentence, every summary key and links to the run's PNGs.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "analysis/calibration/calibrate_kind.hpp"
#include "analysis/report.hpp"
#include "tests/calibration/synthetic_data.hpp"

namespace granflow::calibration {
namespace {

// The registry `granflow report` uses, with the calibrate kind (its report section).
const core::KindRegistry& registry() {
  static const core::KindRegistry r = [] {
    core::KindRegistry k;
    register_calibrate_kinds(k);
    return k;
  }();
  return r;
}

TEST(CalibrationReport, CalibrateRunReport) {
  const auto work = std::filesystem::path(GRANFLOW_BINARY_DIR) / "test_calibration_report";
  const auto data = testing::write_dem_dataset(
      testing::synthetic_points(testing::dry_model(0.8, 0.6), 5, 10), work / "dem.h5");
  const auto schema = calibrate_schema();  // the Case refers to it: keep it alive
  const auto c = core::Case::parse(
      "kind: calibrate\nname: report_check\ndescription: report test\n"
      "material: {diameter: 1.0e-3, particle_density: 2500, restitution: 0.7}\n"
      "data: {files: '" +
          data.string() + "', observables: 'friction solid_fraction'}\n" +
          "fit: {parameters: 'restitution jamming_fraction'}\n",
      "report.yaml", {}, schema);
  const auto dir = work / "run";
  {
    core::RunContext ctx(c, dir, true, true);
    ASSERT_EQ(run_calibrate_case(ctx), core::exit_ok);
    ctx.finish();
  }
  const auto file = analysis::write_report(dir, registry());
  std::ifstream in(file);
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string md = buffer.str();
  const auto s = core::Summary::read(dir / "summary.json");
  EXPECT_NE(md.find("# report_check"), std::string::npos);
  EXPECT_NE(md.find("Kind: `calibrate`"), std::string::npos);
  EXPECT_NE(md.find(fmt::format("| restitution | {:.6g} | {:.6g} |", s.get("fit.restitution"),
                                s.get("fit.restitution_err"))),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("Held-out check (5 points)"), std::string::npos);
  for (const auto& [key, value] : s.values())
    EXPECT_NE(md.find("`" + key + "`"), std::string::npos) << key;
  if (std::filesystem::exists(dir / "calibration.png")) {
    EXPECT_NE(md.find("](calibration.png)"), std::string::npos);
  }
  EXPECT_THROW(analysis::write_report(work / "no_such_run", registry()), std::runtime_error);
}

}  // namespace
}  // namespace granflow::calibration
