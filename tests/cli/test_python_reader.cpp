// The Python reader (analysis/python/granflow_results.py) on tiny runs of every kind this build
// has, made here through the granflow program: rev, mpm (Terzaghi), dem and pair (one tiny pair:
// its DEM run sits in pair/dem), calibrate (on that DEM run). tests/cli/check_results_reader.py
// opens each with the reader and checks kinds, tables, units, the types of result.h5
// (schema_version, str attributes, integer flags), that docs/results.md lists every dataset with
// its unit, and `granflow export --csv` against the reader's tables.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/process.hpp"
#include "core/run.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path binary = fs::path(GRANFLOW_BINARY_DIR) / "app" / "granflow";
const fs::path source = GRANFLOW_SOURCE_DIR;

std::string read(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// granflow ARGS..., output to LOG; the exit status.
int granflow(const std::vector<std::string>& args, const fs::path& log) {
  std::vector<std::string> argv{binary.string()};
  argv.insert(argv.end(), args.begin(), args.end());
  granflow::core::ProcessOptions options;
  options.output = log;
  return granflow::core::run_process(argv, options).status;
}

// A pair small enough for seconds: 200 spheres, 2 strain units, two shear rates.
const char* tiny_pair = R"(kind: pair
name: reader_pair
material: {diameter: 1.0e-3, particle_density: 2500, restitution: 0.7, particle_friction: 0.5}
collisional: {jamming_fraction: 0.587}
dem: {particles: 200, compression_steps: 2000}
control: {mode: constant_pressure, normal_stress: 100, solid_fraction: 0.57}
shear_rate: 20
strain: {total: 2, sample: 0.01}
sweep: {shear_rate: [20, 40]}
)";

TEST(PythonReader, OpensTheTinyRunOfEveryKind) {
  const fs::path work = fs::path(GRANFLOW_BINARY_DIR) / "test_python_reader";
  fs::remove_all(work);
  fs::create_directories(work);
  // --granflow: `granflow export RUN --csv` is checked against the reader's tables.
  std::vector<std::string> checks{"/usr/bin/python3",
                                  (source / "tests/cli/check_results_reader.py").string(),
                                  "--granflow", binary.string()};

  ASSERT_EQ(granflow({"run", (source / "cases/rev/simple_shear_dry.yaml").string(), "--out",
                      (work / "rev").string(), "--quiet"},
                     work / "rev.log"),
            0)
      << read(work / "rev.log");
  checks.insert(checks.end(), {(work / "rev").string(), "rev"});

#ifdef GRANFLOW_HAVE_MPM
  ASSERT_EQ(granflow({"run", (source / "cases/mpm/terzaghi.yaml").string(), "--out",
                      (work / "mpm").string(), "--quiet"},
                     work / "mpm.log"),
            0)
      << read(work / "mpm.log");
  checks.insert(checks.end(), {(work / "mpm").string(), "mpm"});
#endif

#ifdef GRANFLOW_HAVE_DEM
  std::ofstream(work / "pair.yaml") << tiny_pair;
  ASSERT_EQ(granflow({"run", (work / "pair.yaml").string(), "--out", (work / "pair").string(),
                      "--quiet"},
                     work / "pair.log"),
            0)
      << read(work / "pair.log");
  checks.insert(checks.end(), {(work / "pair").string(), "pair", (work / "pair" / "dem").string(),
                               "dem"});
  std::ofstream(work / "calibrate.yaml")
      << "kind: calibrate\nname: reader_calibrate\n"
         "material: {diameter: 1.0e-3, particle_density: 2500, restitution: 0.7, "
         "particle_friction: 0.5}\n"
         "data: {files: '"
      << (work / "pair" / "dem" / "result.h5").string()
      << "', particle_friction: 0.5, observables: friction}\n"
         "fit: {parameters: restitution}\nholdout: {mode: none}\n";
  ASSERT_EQ(granflow({"run", (work / "calibrate.yaml").string(), "--out",
                      (work / "calibrate").string(), "--quiet"},
                     work / "calibrate.log"),
            0)
      << read(work / "calibrate.log");
  checks.insert(checks.end(), {(work / "calibrate").string(), "calibrate"});
#endif

  granflow::core::ProcessOptions options;
  options.output = work / "reader.log";
  const auto r = granflow::core::run_process(checks, options);
  EXPECT_EQ(r.status, 0) << read(work / "reader.log");
}

}  // namespace
