// Restart of MPM runs through the granflow command (output.checkpoint, output.restart_from;
// continuum/mpm/restart.hpp):
//  * a checkpoint that cannot be used (missing, a directory, not HDF5, truncated, an HDF5 file that
//    is no checkpoint), one written by another case, and one at or past the end of the run are
//    refused with exit code 2 and one line naming output.restart_from, the file and the reason;
//  * a restarted run's summary equals the uninterrupted run's, key by key (cost.* aside): the
//    state continues bit for bit and the history accumulators (series, peaks, averaging sums,
//    isochrone errors) come from the checkpoint, so the comparison is exact (EXPECT_EQ).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/process.hpp"
#include "core/run.hpp"
#include "tests/mpm/mpm_cli.hpp"

namespace fs = std::filesystem;
using namespace granflow;

namespace {

using test::mpm_case;
using test::Output;
using test::run_granflow;

fs::path scratch(const std::string& name) { return test::mpm_scratch("mpm_restart_" + name); }

// `granflow run CASE --quiet --out DIR --set numerics.threads=1 --set output.frames=0 --set ...`
Output run(const std::string& file, const fs::path& out, std::vector<std::string> sets) {
  std::vector<std::string> args = {"run", mpm_case(file), "--quiet", "--out", out.string()};
  sets.insert(sets.begin(), {"numerics.threads=1", "output.frames=0"});
  for (const auto& s : sets) {
    args.push_back("--set");
    args.push_back(s);
  }
  fs::path log = out;
  log += ".log";
  return run_granflow(args, log);
}

bool one_line(const std::string& text) {
  return !text.empty() && text.find('\n') == text.size() - 1;
}

// Every summary key but cost.* (wall times and what is derived from them) equal, bit for bit.
void expect_same_summary(const fs::path& a, const fs::path& b) {
  const core::Summary x = core::Summary::read(a / "summary.json");
  const core::Summary y = core::Summary::read(b / "summary.json");
  int compared = 0;
  for (const auto& [key, value] : x.values()) {
    if (key.rfind("cost.", 0) == 0) continue;
    ASSERT_TRUE(y.contains(key)) << key;
    EXPECT_EQ(y.get(key), value) << key;
    ++compared;
  }
  EXPECT_EQ(x.values().size(), y.values().size());
  EXPECT_GT(compared, 10);
}

// A Couette checkpoint at t = 0.2 s (5 x 32 cells, 2 x 2 points per cell: 640 liquid points), in a
// directory of each test's own (ctest runs the tests of this fixture in parallel processes).
class MpmRestartCouette : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = scratch(std::string("couette_") +
                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
    const Output r = run("couette.yaml", dir_ / "half",
                         {"output.checkpoint=true", "run.end_time=0.2", "run.average_from=0.1"});
    ASSERT_EQ(r.code, 0) << r.text;
  }
  fs::path checkpoint() const { return dir_ / "half" / "checkpoint.h5"; }
  const fs::path& dir() const { return dir_; }

  // A restart from `file` with `sets`: exit 2 and one line naming the key and `words`.
  void expect_refused(const fs::path& file, const std::string& name, std::vector<std::string> sets,
                      const std::vector<std::string>& words) const {
    sets.push_back("output.restart_from=" + file.string());
    const Output r = run("couette.yaml", dir() / name, sets);
    EXPECT_EQ(r.code, core::exit_bad_input) << name << ": " << r.text;
    EXPECT_TRUE(one_line(r.text)) << name << ": " << r.text;
    EXPECT_NE(r.text.find("output.restart_from: " + file.string() + ": "), std::string::npos)
        << name << ": " << r.text;
    for (const auto& w : words)
      EXPECT_NE(r.text.find(w), std::string::npos) << name << ": " << r.text;
    EXPECT_FALSE(fs::exists(dir() / name)) << name << ": refused before the run directory exists";
  }

 private:
  fs::path dir_;
};

}  // namespace

TEST_F(MpmRestartCouette, UnusableCheckpointFilesAreRefusedWithTheReason) {
  // Missing (was: exit 134, an uncaught H5::FileIException).
  expect_refused(dir() / "no_such_dir" / "checkpoint.h5", "missing", {}, {"no such file"});
  expect_refused(dir(), "directory", {}, {"a directory"});
  const fs::path text = dir() / "notes.txt";
  std::ofstream(text) << "not a checkpoint\n";
  expect_refused(text, "text", {}, {"not an HDF5 file"});
  // Truncated to its first 4 KiB (was: exit 134).
  const fs::path cut = dir() / "truncated.h5";
  {
    std::ifstream in(checkpoint(), std::ios::binary);
    std::string bytes(4096, '\0');
    in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    std::ofstream(cut, std::ios::binary).write(bytes.data(), in.gcount());
  }
  expect_refused(cut, "truncated", {}, {"unreadable HDF5 file (", "truncated"});
  // An HDF5 file of granflow that is no checkpoint: the run's result.h5.
  expect_refused(dir() / "half" / "result.h5", "foreign", {},
                 {"not a granflow MPM checkpoint (no /clock)"});
}

TEST_F(MpmRestartCouette, TheCheckpointIsReadByRunNotByCheck) {
  // As every file a case reads (KindEntry::check_inputs): `granflow check` validates the case,
  // the checkpoint may not exist yet.
  const fs::path missing = dir() / "later" / "checkpoint.h5";
  const Output r = run_granflow(
      {"check", mpm_case("couette.yaml"), "--set", "output.restart_from=" + missing.string()},
      dir() / "check.log");
  EXPECT_EQ(r.code, core::exit_ok) << r.text;
}

TEST_F(MpmRestartCouette, AnotherCaseIsRefusedNamingTheFirstDifferingKey) {
  // Same point count, another annulus (was: accepted, RMS error 0.59 reported as the result).
  expect_refused(checkpoint(), "outer_radius", {"geometry.outer_radius=3.0"},
                 {"written by another case: geometry.outer_radius is 3 here, 2 in the checkpoint",
                  "it may change only run.end_time, output.*"});
  expect_refused(checkpoint(), "viscosity", {"liquid.viscosity=500"},
                 {"liquid.viscosity is 500 here, 1000 in the checkpoint"});
  // Another kind (was: exit 1, "internal error: checkpoint: 'x' has 0 values").
  const fs::path out = dir() / "rheometer";
  const Output r =
      run_granflow({"run", mpm_case("rheometer_ci.yaml"), "--quiet", "--out", out.string(), "--set",
                    "output.restart_from=" + checkpoint().string()},
                   dir() / "rheometer.log");
  EXPECT_EQ(r.code, core::exit_bad_input) << r.text;
  EXPECT_NE(r.text.find("output.restart_from: " + checkpoint().string() +
                        ": written by another case: test is rheometer here, couette in the "
                        "checkpoint"),
            std::string::npos)
      << r.text;
  EXPECT_TRUE(one_line(r.text)) << r.text;
}

TEST_F(MpmRestartCouette, CheckpointAtOrPastTheEndIsRefused) {
  // Was: exit 0 after 0 steps, an error "averaged over t in [0.2, 0.5] s" over no samples.
  expect_refused(
      checkpoint(), "past_end", {"run.end_time=0.1", "run.average_from=0.05"},
      {"the checkpoint is at t = 0.1999", "at or past the end of this run", "from run.end_time"});
  expect_refused(checkpoint(), "at_end", {"run.end_time=0.2", "run.average_from=0.1"},
                 {"at or past the end of this run"});
  // An averaging window that started before the checkpoint must be the checkpoint's (its sums).
  expect_refused(checkpoint(), "window", {"run.end_time=0.3", "run.average_from=0.15"},
                 {"run.average_from = 0.15 s starts the averaging window before the checkpoint",
                  "expected run.average_from: 0.1"});
}

TEST_F(MpmRestartCouette, RestartInsideTheAveragingWindowEqualsTheUninterruptedRun) {
  // Window 0.1-0.3 s across the checkpoint at 0.2 s: the restarted run continues the sums.
  const Output full =
      run("couette.yaml", dir() / "full", {"run.end_time=0.3", "run.average_from=0.1"});
  ASSERT_EQ(full.code, 0) << full.text;
  const Output restarted = run(
      "couette.yaml", dir() / "restarted",
      {"run.end_time=0.3", "run.average_from=0.1", "output.restart_from=" + checkpoint().string()});
  ASSERT_EQ(restarted.code, 0) << restarted.text;
  expect_same_summary(dir() / "full", dir() / "restarted");
  // A window that starts after the checkpoint starts from zero sums.
  const Output late =
      run("couette.yaml", dir() / "late_full", {"run.end_time=0.3", "run.average_from=0.25"});
  ASSERT_EQ(late.code, 0) << late.text;
  const Output late_restart = run("couette.yaml", dir() / "late_restarted",
                                  {"run.end_time=0.3", "run.average_from=0.25",
                                   "output.restart_from=" + checkpoint().string()});
  ASSERT_EQ(late_restart.code, 0) << late_restart.text;
  expect_same_summary(dir() / "late_full", dir() / "late_restarted");
}

TEST(MpmRestart, TerzaghiRestartKeepsTheIsochronesCheckedBeforeIt) {
  // terzaghi.l2_err_pressure and .settlement_err are maxima over the isochrones: the restarted
  // run must include those checked before its checkpoint (T_v = 0.05).
  const fs::path dir = scratch("terzaghi");
  ASSERT_EQ(run("terzaghi.yaml", dir / "full", {"run.isochrones=[0.05, 0.2]"}).code, 0);
  const Output half =
      run("terzaghi.yaml", dir / "half", {"run.isochrones=[0.05]", "output.checkpoint=true"});
  ASSERT_EQ(half.code, 0) << half.text;
  const std::string from = "output.restart_from=" + (dir / "half" / "checkpoint.h5").string();
  const Output restarted =
      run("terzaghi.yaml", dir / "restarted", {"run.isochrones=[0.05, 0.2]", from});
  ASSERT_EQ(restarted.code, 0) << restarted.text;
  expect_same_summary(dir / "full", dir / "restarted");
  // The checked isochrones come first.
  const Output other = run("terzaghi.yaml", dir / "other", {"run.isochrones=[0.1, 0.2]", from});
  EXPECT_EQ(other.code, core::exit_bad_input) << other.text;
  EXPECT_NE(other.text.find("run.isochrones is [0.1, 0.2]; a restart keeps the isochrones "
                            "checked before the checkpoint, [0.05], first"),
            std::string::npos)
      << other.text;
}

TEST(MpmRestart, RheometerSummaryEqualsTheUninterruptedRun) {
  // cases/mpm/rheometer_ci.yaml to 4 ms against 2 ms + a restart to 4 ms (the reliability probe's
  // commands). The peak of τ̄ (≈ 0.65 ms) lies before the checkpoint: a summary over the
  // restarted part alone had peak.tau 538 Pa instead of 32.6 kPa, time.peak 2.0 ms instead of
  // 0.65 ms, final.gamma 0.027 instead of 0.042, loading.inertia_ratio 31 instead of 0.51.
  const fs::path dir = scratch("rheometer");
  const Output full = run("rheometer_ci.yaml", dir / "full", {});
  ASSERT_EQ(full.code, 0) << full.text;
  const Output half =
      run("rheometer_ci.yaml", dir / "half",
          {"output.checkpoint=true", "run.end_time=0.002", "run.profile_times=[0.001, 0.002]"});
  ASSERT_EQ(half.code, 0) << half.text;
  const Output restarted =
      run("rheometer_ci.yaml", dir / "restarted",
          {"output.restart_from=" + (dir / "half" / "checkpoint.h5").string()});
  ASSERT_EQ(restarted.code, 0) << restarted.text;
  expect_same_summary(dir / "full", dir / "restarted");
  const core::Summary s = core::Summary::read(dir / "restarted" / "summary.json");
  EXPECT_LT(s.get("time.peak"), 0.002);  // the peak came from the checkpoint's history
  // Another sampling interval changes the history itself: refused.
  const Output other = run(
      "rheometer_ci.yaml", dir / "other",
      {"run.sample_every=10", "output.restart_from=" + (dir / "half" / "checkpoint.h5").string()});
  EXPECT_EQ(other.code, core::exit_bad_input) << other.text;
  EXPECT_NE(other.text.find("run.sample_every is 10 here, 5 in the checkpoint"), std::string::npos)
      << other.text;
}
