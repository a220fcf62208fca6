// SIGINT and SIGTERM stop a run at its next step boundary with readable files (core/interrupt.hpp):
// result.h5 readable, summary.json with run.interrupted = 1, a log line naming the signal, step
// and time, exit 128 + the signal, and no child process (granflow-dem, mpirun) left running.
// After SIGKILL result.h5 is still readable (flushed when created and at every field frame).
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "core/interrupt.hpp"
#include "core/process.hpp"
#include "core/result_file.hpp"
#include "core/run.hpp"
#include "tests/cli/granflow_child.hpp"

namespace fs = std::filesystem;
using granflow::test::GranflowChild;
using granflow::test::slurp;

namespace {

const fs::path source = GRANFLOW_SOURCE_DIR;

fs::path scratch(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("granflow_interrupt_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// The rheometer of CI run for 50x its shipped end time: minutes of work, stopped after ~1 s.
std::vector<std::string> long_rheometer(const fs::path& out) {
  return {"run",
          (source / "cases/mpm/rheometer_ci.yaml").string(),
          "--out",
          out.string(),
          "--quiet",
          "--set",
          "run.end_time=0.2",
          "--set",
          "run.profile_times=[0.001, 0.2]"};
}

// Signals a running rheometer once its solver has started and checks what it leaves.
void interrupt_rheometer(int sig, const std::string& name) {
  const fs::path dir = scratch(name);
  const fs::path run = dir / "run";
  GranflowChild child(long_rheometer(run), dir / "out.txt");
  ASSERT_GT(child.pid(), 0);
  ASSERT_TRUE(child.wait_for_text(run / "log.txt", "mpm:", std::chrono::seconds(60)))
      << child.output();
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  const auto signalled = std::chrono::steady_clock::now();
  child.signal(sig);
  EXPECT_EQ(child.wait(), 128 + sig) << child.output();
  // The next step boundary is a fraction of a millisecond away; writing the files takes the rest.
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - signalled).count(),
            20.0);
  const std::string log = slurp(run / "log.txt");
  EXPECT_NE(log.find("interrupted by " + name + " at step"), std::string::npos) << log;
  EXPECT_EQ(log.find("finished in"), std::string::npos) << log;
  const auto summary = granflow::core::Summary::read(run / "summary.json");
  EXPECT_EQ(summary.get("run.interrupted"), 1);
  EXPECT_TRUE(summary.non_finite().empty());
  const auto time = granflow::core::read_dataset(run / "result.h5", "/series/time");
  ASSERT_FALSE(time.empty());
  EXPECT_GT(time.back(), 0.0);
  EXPECT_LT(time.back(), 0.2);  // stopped early, and the series up to there is in the file
  EXPECT_EQ(granflow::core::read_string_attribute(run / "result.h5", "/", "kind"), "mpm");
  fs::remove_all(dir);
}

}  // namespace

TEST(Interrupt, SigintStopsAnMpmRunWithReadableResultsAndExit130) {
  interrupt_rheometer(SIGINT, "SIGINT");
}

TEST(Interrupt, SigtermStopsAnMpmRunWithReadableResultsAndExit143) {
  interrupt_rheometer(SIGTERM, "SIGTERM");
}

TEST(Interrupt, AfterSigkillResultH5IsStillReadable) {
  const fs::path dir = scratch("SIGKILL");
  const fs::path run = dir / "run";
  GranflowChild child(long_rheometer(run), dir / "out.txt");
  ASSERT_TRUE(child.wait_for_text(run / "log.txt", "mpm:", std::chrono::seconds(60)));
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  child.signal(SIGKILL);
  EXPECT_EQ(child.wait(), 128 + SIGKILL);
  // Flushed when created: the file opens and holds the run's attributes.
  EXPECT_EQ(granflow::core::read_string_attribute(run / "result.h5", "/", "kind"), "mpm");
  fs::remove_all(dir);
}

TEST(Interrupt, AnInterruptedRunStopsItsChildProcessGroup) {
  // run_process polls the interrupt flag: a child that would sleep for a minute is stopped with
  // SIGTERM at once (exit status 128 + 15), instead of outliving the run.
  granflow::core::set_interrupt_for_testing(SIGINT);
  const auto start = std::chrono::steady_clock::now();
  const auto r = granflow::core::run_process({"sleep", "60"});
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  granflow::core::set_interrupt_for_testing(0);
  EXPECT_TRUE(r.started()) << r.error;
  EXPECT_EQ(r.status, 128 + SIGTERM);
  EXPECT_LT(seconds, 5.0);
  // Without an interruption the same call waits for the child and returns its status.
  EXPECT_EQ(granflow::core::run_process({"false"}).status, 1);
}

#if GRANFLOW_HAVE_DEM
// A DEM run stopped by SIGTERM (ranks 1) or SIGINT (ranks 2, under mpirun): granflow-dem and
// mpirun are stopped with it, the samples so far stay, summary.json says interrupted.
void interrupt_dem(int sig, const std::string& name, int ranks) {
  const fs::path dir = scratch("dem_" + name);
  const fs::path run = dir / "run";
  GranflowChild child({"run", (source / "cases/dem/dry_point.yaml").string(), "--out", run.string(),
                       "--quiet", "--set", "dem.particles=200", "--set",
                       "dem.ranks=" + std::to_string(ranks), "--set", "strain.total=200"},
                      dir / "out.txt");
  ASSERT_TRUE(child.wait_for_text(run / "liggghts.out", "Step", std::chrono::seconds(120)))
      << child.output();
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  child.signal(sig);
  EXPECT_EQ(child.wait(), 128 + sig) << child.output();
  // Nothing of the run is left working in its directory (granflow-dem, mpirun, its ranks).
  std::vector<pid_t> left;
  for (int i = 0; i < 100; ++i) {
    left = granflow::test::processes_working_in(run);
    if (left.empty()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_TRUE(left.empty()) << left.size() << " processes still run in " << run;
  for (pid_t pid : left) ::kill(pid, SIGKILL);
  const auto summary = granflow::core::Summary::read(run / "summary.json");
  EXPECT_EQ(summary.get("run.interrupted"), 1);
  EXPECT_EQ(granflow::core::read_string_attribute(run / "result.h5", "/", "kind"), "dem");
  EXPECT_NE(slurp(run / "log.txt").find("stopped by " + name), std::string::npos);
  fs::remove_all(dir);
}

TEST(Interrupt, SigtermStopsADemRunAndItsDriver) { interrupt_dem(SIGTERM, "SIGTERM", 1); }

TEST(Interrupt, SigintStopsADemRunUnderMpirun) { interrupt_dem(SIGINT, "SIGINT", 2); }
#endif
