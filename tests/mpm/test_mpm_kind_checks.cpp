// Bad input of the MPM kinds that cannot give a result, through the granflow command: refused
// with exit code 2 and one line naming the key and the bound, before anything runs. And an error
// measure that is not a number stops the run as a numerical failure naming it (exit code 3):
// summary.json would leave it out as "not available" with exit code 0.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "continuum/mpm/mpm_kind.hpp"
#include "continuum/mpm/restart.hpp"
#include "core/kind_registry.hpp"
#include "core/process.hpp"
#include "core/run.hpp"
#include "tests/mpm/mpm_cli.hpp"

namespace fs = std::filesystem;
using namespace granflow;

namespace {

using test::mpm_case;
using test::Output;
using test::run_granflow;

fs::path scratch(const std::string& name) { return test::mpm_scratch("mpm_checks_" + name); }

bool one_line(const std::string& text) {
  return !text.empty() && text.find('\n') == text.size() - 1;
}

}  // namespace

TEST(MpmKindChecks, CouetteWithOneRadialCellIsRefusedNamingTheMinimum) {
  // One radial cell has no interior node ring, where the error is measured: it was run and
  // reported "RMS v_θ error / V = -nan" with exit code 0.
  const fs::path dir = scratch("couette_1r");
  const Output r =
      run_granflow({"run", mpm_case("couette.yaml"), "--set", "geometry.cells_r=1", "--set",
                    "geometry.cells_theta=8", "--out", (dir / "run").string()},
                   dir / "output.txt");
  EXPECT_EQ(r.code, core::exit_bad_input) << r.text;
  EXPECT_NE(r.text.find("geometry.cells_r: at least 2"), std::string::npos) << r.text;
  EXPECT_TRUE(one_line(r.text)) << r.text;
  EXPECT_FALSE(fs::exists(dir / "run")) << "refused before the run directory is created";
  // Two radial cells: one interior ring, a finite error.
  const Output ok = run_granflow({"check", mpm_case("couette.yaml"), "--set", "geometry.cells_r=2"},
                                 dir / "output.txt");
  EXPECT_EQ(ok.code, core::exit_ok) << ok.text;
}

TEST(MpmKindChecks, RheometerBeyondJammingIsRefusedNamingTheBound) {
  // e0 = 0.5: ν0 = 1/(1 + e0) = 0.667 > collisional.jamming_fraction = liquid.maximum_packing =
  // 0.64 of rheometer_ci.yaml, where g0 and η(ν) diverge (the REV tests refuse it the same way).
  const fs::path dir = scratch("rheometer_jam");
  const Output r =
      run_granflow({"run", mpm_case("rheometer_ci.yaml"), "--set", "initial.void_ratio=0.5",
                    "--set", "run.end_time=0.002", "--set", "run.profile_times=[0.001, 0.002]",
                    "--out", (dir / "run").string()},
                   dir / "output.txt");
  EXPECT_EQ(r.code, core::exit_bad_input) << r.text;
  EXPECT_NE(r.text.find("initial.void_ratio: solid fraction 1/(1+e0) = 0.666667"),
            std::string::npos)
      << r.text;
  EXPECT_NE(r.text.find("jamming_fraction 0.64"), std::string::npos) << r.text;
  EXPECT_NE(r.text.find("e0 > 0.5625"), std::string::npos) << r.text;
  EXPECT_TRUE(one_line(r.text)) << r.text;
  // Just below jamming (ν0 = 0.6399) stays allowed.
  const Output ok =
      run_granflow({"check", mpm_case("rheometer_ci.yaml"), "--set", "initial.void_ratio=0.562744"},
                   dir / "output.txt");
  EXPECT_EQ(ok.code, core::exit_ok) << ok.text;
}

TEST(MpmKindChecks, ErrorMeasureThatIsNotANumberIsANumericalFailure) {
  core::KindRegistry registry;
  mpm::register_mpm_kinds(registry);
  const fs::path path = mpm_case("couette.yaml");
  const auto& entry = registry.find("mpm", "couette", path.string());
  const core::Case c = core::Case::load(path, {}, entry.schema);
  core::RunContext ctx(c, scratch("nan_error") / "run", /*force=*/true, /*quiet=*/true);
  ctx.summary.set("couette.rms_radial_velocity", 4e-4);
  ctx.summary.set("couette.l2_err_velocity", 6.6e-4);
  EXPECT_NO_THROW(mpm::check_error_measures(
      ctx, 10, {"couette.l2_err_velocity", "couette.rms_radial_velocity"}));
  // What one radial cell gave: 0/0 over no interior node.
  ctx.summary.set("couette.l2_err_velocity", std::numeric_limits<double>::quiet_NaN());
  try {
    mpm::check_error_measures(ctx, 10, {"couette.rms_radial_velocity", "couette.l2_err_velocity"});
    FAIL() << "a NaN error measure passed";
  } catch (const core::NumericalFailure& e) {  // the CLI's exit code 3
    EXPECT_EQ(e.variable, "couette.l2_err_velocity");
    EXPECT_NE(std::string(e.what()).find("couette.l2_err_velocity = nan"), std::string::npos)
        << e.what();
  }
}
