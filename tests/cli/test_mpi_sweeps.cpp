// `mpirun -np 2 granflow run CASE.yaml` distributes the conditions of a sweep over the ranks
// (core/sweep_scheduler.hpp) and leaves the run directory of a serial run: the same files, the same
// summary values bit for bit (only timing fields differ), the same result.h5 tables and the same
// log lines; a failing condition is reported by rank 0 with the serial run's exit code, no hang.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <vector>

#include "core/result_file.hpp"
#include "core/run.hpp"

namespace fs = std::filesystem;

namespace {

const std::string granflow_exe = std::string(GRANFLOW_BINARY_DIR) + "/app/granflow";
const fs::path source = GRANFLOW_SOURCE_DIR;
// Two ranks on CI's two cores; --oversubscribe in case the runner exposes fewer slots. `timeout`
// turns a hang into exit 124 (a failed test) instead of a stuck CI job.
const std::string mpirun =
    std::string("timeout 120 ") + GRANFLOW_MPIEXEC + " --oversubscribe -np 2 ";

struct Output {
  int code;
  std::string text;
};

Output run(const std::string& command) {
  if (::geteuid() == 0) {  // CI runs as root (scripts/test exports the same)
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  }
  Output out{0, ""};
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  char buffer[4096];
  while (fgets(buffer, sizeof buffer, pipe)) out.text += buffer;
  const int status = pclose(pipe);
  out.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

fs::path scratch(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("granflow_mpi_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

// Timing fields: the only summary values allowed to differ between two runs of one case.
bool timing(const std::string& key) {
  return key.starts_with("cost.") &&
         (key.find("wall_s") != std::string::npos || key.find("per_s") != std::string::npos);
}

void expect_same_summary(const fs::path& serial, const fs::path& distributed) {
  const auto a = granflow::core::Summary::read(serial / "summary.json").values();
  const auto b = granflow::core::Summary::read(distributed / "summary.json").values();
  std::set<std::string> keys_a, keys_b;
  for (const auto& [key, value] : a) keys_a.insert(key);
  for (const auto& [key, value] : b) keys_b.insert(key);
  EXPECT_EQ(keys_a, keys_b);
  for (const auto& [key, value] : a) {
    if (timing(key) || !b.count(key)) continue;
    // Same inputs, same code, same machine: the values are identical, not merely close.
    if (std::isnan(value))
      EXPECT_TRUE(std::isnan(b.at(key))) << key;
    else
      EXPECT_EQ(value, b.at(key)) << key;
  }
}

std::set<std::string> files_of(const fs::path& dir) {
  std::set<std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    files.insert(fs::relative(entry.path(), dir).string());
  return files;
}

// log.txt without time stamps, without the scheduler's own lines and without the lines that
// report times (progress, ETA, costs), which differ from run to run anyway; the run directory's
// name is replaced by RUN_DIR.
std::vector<std::string> log_lines(const fs::path& dir) {
  std::ifstream in(dir / "log.txt");
  std::vector<std::string> lines;
  const std::regex stamp(R"(^\[\d\d:\d\d:\d\d\.\d\d\d\] )");
  for (std::string line; std::getline(in, line);) {
    if (!std::regex_search(line, stamp)) continue;  // plot script output
    line = std::regex_replace(line, stamp, "");
    bool skip = false;
    for (const char* timed : {"on rank", "MPI ranks", " s elapsed", "done in", "finished in",
                              "cost:", " s (", "granflow run "})
      skip = skip || line.find(timed) != std::string::npos;
    for (auto at = line.find(dir.string()); at != std::string::npos; at = line.find(dir.string()))
      line.replace(at, dir.string().size(), "RUN_DIR");
    if (!skip) lines.push_back(line);
  }
  return lines;
}

std::string read(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST(MpiSweeps, RevSweepOnTwoRanksWritesTheSerialRunDirectory) {
  const fs::path serial = scratch("rev_serial"), distributed = scratch("rev_mpi");
  const std::string sweep = (source / "cases/rev/simple_shear_sweep.yaml").string();
  const auto r1 = run(granflow_exe + " run " + sweep + " --quiet --out " + serial.string());
  ASSERT_EQ(r1.code, 0) << r1.text;
  const auto r2 =
      run(mpirun + granflow_exe + " run " + sweep + " --quiet --out " + distributed.string());
  ASSERT_EQ(r2.code, 0) << r2.text;
  expect_same_summary(serial, distributed);
  EXPECT_EQ(files_of(serial), files_of(distributed));
  // The steady table and a full series, element by element.
  for (const char* path :
       {"/steady/shear_rate", "/steady/friction", "/steady/solid_fraction",
        "/steady/granular_temperature", "/steady/steady_start_strain", "/conditions/8/series/time",
        "/conditions/3/series/granular_temperature"})
    EXPECT_EQ(granflow::core::read_dataset(serial / "result.h5", path),
              granflow::core::read_dataset(distributed / "result.h5", path))
        << path;
  EXPECT_EQ(log_lines(serial), log_lines(distributed));
  // Rank 0 logged where each condition ran. (Which rank runs which is up to the queue: a REV
  // condition takes milliseconds, rank 0 may be through several before rank 1 asks. The DEM test
  // below, with points of seconds, checks that rank 1 gets one.)
  const std::string log = read(distributed / "log.txt");
  EXPECT_NE(log.find("9 conditions on 2 MPI ranks"), std::string::npos) << log;
  for (int n = 0; n < 9; ++n)
    EXPECT_TRUE(std::regex_search(
        log, std::regex("condition " + std::to_string(n) + ": finished on rank [01] in")))
        << n << "\n"
        << log;
  fs::remove_all(serial);
  fs::remove_all(distributed);
}

TEST(MpiSweeps, NumericalFailureOnTwoRanksExitsThreeLikeTheSerialRun) {
  // No temperature at t = 0 under constant pressure: every condition fails at step 0; the first
  // one stops the run (exit 3) as in a serial run, and the rank busy with another is released.
  const fs::path serial = scratch("fail_serial"), distributed = scratch("fail_mpi");
  const std::string sweep = (source / "cases/rev/simple_shear_sweep.yaml").string() +
                            " --set initial.granular_temperature=0 --quiet --out ";
  const auto r1 = run(granflow_exe + " run " + sweep + serial.string());
  const auto r2 = run(mpirun + granflow_exe + " run " + sweep + distributed.string());
  EXPECT_EQ(r1.code, 3) << r1.text;
  EXPECT_EQ(r2.code, 3) << r2.text;
  const std::string message = "numerical failure at step 0, REV point: solid_fraction";
  EXPECT_NE(r2.text.find(message), std::string::npos) << r2.text;
  EXPECT_NE(read(distributed / "log.txt").find(message), std::string::npos);
  expect_same_summary(serial, distributed);
  EXPECT_EQ(granflow::core::read_dataset(serial / "result.h5", "/conditions/0/series/time"),
            granflow::core::read_dataset(distributed / "result.h5", "/conditions/0/series/time"));
  fs::remove_all(serial);
  fs::remove_all(distributed);
}

TEST(MpiSweeps, BadInputOnTwoRanksExitsTwoWithoutRunning) {
  const fs::path out = scratch("bad");
  const auto r = run(mpirun + granflow_exe + " run " +
                     (source / "cases/rev/simple_shear_sweep.yaml").string() +
                     " --set material.restitution=1.5 --out " + out.string());
  EXPECT_EQ(r.code, 2) << r.text;
  EXPECT_NE(r.text.find("material.restitution"), std::string::npos) << r.text;
  EXPECT_FALSE(fs::exists(out));
  // An existing run directory: rank 0 refuses it, rank 1 (already serving) is released.
  fs::create_directories(out);
  const auto again =
      run(mpirun + granflow_exe + " run " +
          (source / "cases/rev/simple_shear_sweep.yaml").string() + " --out " + out.string());
  EXPECT_EQ(again.code, 2) << again.text;
  EXPECT_NE(again.text.find("exists"), std::string::npos) << again.text;
  fs::remove_all(out);
}

#if GRANFLOW_HAVE_DEM
// A tiny dry DEM sweep: 100 spheres, 0.5 strain units, two shear rates, one LIGGGHTS rank each.
// Point 0 (rank 0) has 2.4 times the steps of point 1 (rank 1): rank 1 is done and leaves while
// rank 0 still runs its point, the order in which a `leaving` message once stalled rank 0.
fs::path tiny_dem_sweep(const fs::path& dir) {
  fs::create_directories(dir);
  std::ofstream(dir / "tiny_dem_sweep.yaml") << R"(kind: dem
name: tiny_dem_sweep
material:
  diameter: 1.0e-3
  particle_density: 2500
  restitution: 0.7
  particle_friction: 0.5
dem:
  particles: 100
  compression_steps: 1000
  ranks: 1
control:
  mode: constant_pressure
  normal_stress: 100
  solid_fraction: 0.57
shear_rate: 20
strain:
  total: 0.5
  sample: 0.005
output:
  profile_bins: 4
sweep:
  shear_rate: [20, 80]
)";
  return dir / "tiny_dem_sweep.yaml";
}

// LIGGGHTS started by a rank of an mpirun (its OMPI_*/PMIX_* variables scrubbed) gives the
// serial run's numbers: the same seed and deck, the same binary, so the same samples.
TEST(MpiSweeps, TinyDemSweepOnTwoRanksGivesTheSerialValues) {
  const fs::path dir = scratch("dem");
  const std::string sweep = tiny_dem_sweep(dir).string() + " --quiet --out ";
  const auto r1 = run(granflow_exe + " run " + sweep + (dir / "serial").string());
  ASSERT_EQ(r1.code, 0) << r1.text;
  const auto r2 = run(mpirun + granflow_exe + " run " + sweep + (dir / "mpi").string());
  ASSERT_EQ(r2.code, 0) << r2.text;
  expect_same_summary(dir / "serial", dir / "mpi");
  EXPECT_EQ(files_of(dir / "serial"), files_of(dir / "mpi"));
  for (const char* point : {"point_0", "point_1"})
    EXPECT_EQ(read(dir / "serial" / point / "series.tsv"), read(dir / "mpi" / point / "series.tsv"))
        << point;
  EXPECT_EQ(log_lines(dir / "serial"), log_lines(dir / "mpi"));
  EXPECT_TRUE(std::regex_search(read(dir / "mpi" / "log.txt"),
                                std::regex("condition \\d: finished on rank 1")));
  fs::remove_all(dir);
}

// kind: pair under mpirun: its DEM points are shared out, rank 0 alone runs the continuum side
// (a rank > 0 that went on would read a dataset that is not there and fail the job).
TEST(MpiSweeps, TinyPairOnTwoRanksGivesTheSerialTable) {
  const fs::path dir = scratch("pair");
  fs::create_directories(dir);
  std::ofstream(dir / "tiny_pair.yaml") << R"(kind: pair
name: tiny_pair
material:
  diameter: 1.0e-3
  particle_density: 2500
  restitution: 0.7
  particle_friction: 0.5
collisional:
  jamming_fraction: 0.587
dem:
  particles: 100
  compression_steps: 1000
control:
  mode: constant_pressure
  normal_stress: 100
  solid_fraction: 0.57
shear_rate: 20
strain:
  total: 0.5
  sample: 0.005
output:
  profile_bins: 4
sweep:
  shear_rate: [20, 80]
)";
  const std::string pair = (dir / "tiny_pair.yaml").string() + " --quiet --out ";
  const auto r1 = run(granflow_exe + " run " + pair + (dir / "serial").string());
  ASSERT_EQ(r1.code, 0) << r1.text;
  const auto r2 = run(mpirun + granflow_exe + " run " + pair + (dir / "mpi").string());
  ASSERT_EQ(r2.code, 0) << r2.text;
  expect_same_summary(dir / "serial", dir / "mpi");
  expect_same_summary(dir / "serial" / "dem", dir / "mpi" / "dem");
  EXPECT_EQ(files_of(dir / "serial"), files_of(dir / "mpi"));
  EXPECT_TRUE(std::regex_search(read(dir / "mpi" / "dem" / "log.txt"),
                                std::regex("condition 1: finished on rank 1")));
  fs::remove_all(dir);
}

// granflow-dem fails (a stand-in driver that exits with status 7 after 1 s, so that rank 1 asks for
// work while rank 0 runs point 0): each point fails on the rank that ran it, rank 0 reports both,
// the sweep goes on and exits 4 (external program failed) like the serial run.
TEST(MpiSweeps, FailedDemPointsOnBothRanksAreReportedByRankZero) {
  const fs::path dir = scratch("dem_fail");
  const fs::path driver = dir / "failing-granflow-dem";
  const fs::path sweep = tiny_dem_sweep(dir);
  std::ofstream(driver) << "#!/bin/sh\necho 'ERROR: stand-in driver'\nsleep 1\nexit 7\n";
  fs::permissions(driver, fs::perms::owner_all);
  const auto r = run("GRANFLOW_DEM_DRIVER=" + driver.string() + " " + mpirun + granflow_exe +
                     " run " + sweep.string() + " --quiet --out " + (dir / "mpi").string());
  EXPECT_EQ(r.code, 4) << r.text;
  const std::string log = read(dir / "mpi" / "log.txt");
  for (const char* point : {"point 0 ", "point 1 "})
    EXPECT_TRUE(std::regex_search(
        log, std::regex(std::string(point) +
                        ".*granflow-dem exited with status 7: ERROR: stand-in driver")))
        << point << "\n"
        << log;
  EXPECT_TRUE(std::regex_search(log, std::regex("condition 0: finished on rank 0"))) << log;
  EXPECT_TRUE(std::regex_search(log, std::regex("condition 1: finished on rank 1"))) << log;
  fs::remove_all(dir);
}
#endif
