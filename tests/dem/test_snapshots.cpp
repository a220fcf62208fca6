// DEM particle snapshots (output.snapshot_strain): a 300-sphere dry shear over 1.2 strain on two
// MPI ranks writes snapshot_<step>.vtu at strain 0, 0.4, 0.8 indexed in snapshots.pvd, which
// VTK's own vtkXMLUnstructuredGridReader (the reader ParaView uses, python3-vtk9) and meshio open
// with one vertex per sphere, the documented arrays and the same values, and at the same steps
// snapshot_<step>.dump, the LAMMPS text dump OVITO opens, whose header parses and whose spheres
// and values are the .vtu's to its 6 digits, both listed in snapshots.csv
// (tests/dem/check_snapshots.py); the same run without snapshots gives the same series to the
// last digit (a dump only reads the state). ~10 s.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "core/process.hpp"
#include "tests/dem/cli_run.hpp"

namespace {

using granflow::dem::testing::fresh_directory;
using granflow::dem::testing::read;

int granflow_run(const std::filesystem::path& dir, const std::vector<std::string>& args) {
  std::vector<std::string> argv{GRANFLOW_CLI_PATH, "run",
                                std::string(GRANFLOW_SOURCE_DIR) + "/cases/dem/dry_point.yaml",
                                "--set", "dem.particles=300", "--set", "strain.total=1.2",
                                "--set", "dem.ranks=2"};
  argv.insert(argv.end(), args.begin(), args.end());
  granflow::core::ProcessOptions options;
  options.output = dir / "cli.txt";
  return granflow::core::run_process(argv, options).status;
}

TEST(DemSnapshots, ParticleFilesAReaderOpensAndTheRunIsUnchanged) {
  const auto dir = fresh_directory("snapshots");
  ASSERT_EQ(granflow_run(dir, {"--out", (dir / "with").string(), "--set",
                               "output.snapshot_strain=0.4"}),
            0)
      << read(dir / "cli.txt");
  ASSERT_EQ(granflow_run(dir, {"--out", (dir / "without").string(), "--set",
                               "output.snapshot_strain=0"}),
            0)
      << read(dir / "cli.txt");
  EXPECT_EQ(read(dir / "with" / "series.tsv"), read(dir / "without" / "series.tsv"));
  EXPECT_FALSE(std::filesystem::exists(dir / "without" / "snapshots.pvd"));
  // strain.total 1.2 = 3 intervals of 0.4, but the run ends on the last whole servo block
  // before 1.2 (shear_deck_timing), so the snapshots are at 0, 0.4, 0.8 (and not 1.2).
  granflow::core::ProcessOptions options;
  options.output = dir / "check.txt";
  const auto r = granflow::core::run_process(
      {"/usr/bin/python3", std::string(GRANFLOW_SOURCE_DIR) + "/tests/dem/check_snapshots.py",
       (dir / "with").string(), "300", "0.4", "3", "20"},
      options);
  EXPECT_EQ(r.status, 0) << read(dir / "check.txt");
}

}  // namespace
