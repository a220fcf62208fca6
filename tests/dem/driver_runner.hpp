// Test support: run granflow-dem (1 or 2 ranks) on a deck in a fresh directory under the build
// tree and read its series.
#pragma once

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "dem_coupling/kind/series_table.hpp"
#include "tests/dem/driver_deck.hpp"
#include "tests/dem/scratch_dir.hpp"

namespace granflow::dem::testing {

struct DriverRun {
  int status = -1;
  std::string output;  // stdout + stderr
  SeriesTable series;
};

// Runs `granflow-dem in.granflow` in `dir` (deck and data already there).
inline DriverRun run_driver(const std::filesystem::path& dir, int ranks = 1) {
  std::string launcher;
  if (ranks > 1)
    // Root in CI containers: Open MPI refuses root unless both variables are set.
    launcher = fmt::format(
        "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun --oversubscribe -np {} ",
        ranks);
  const std::string command = fmt::format("cd '{}' && {}'{}' in.granflow -log none > out.txt 2>&1",
                                          dir.string(), launcher, GRANFLOW_DEM_DRIVER_PATH);
  DriverRun run;
  const int raw = std::system(command.c_str());
  run.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128;
  std::ifstream in(dir / "out.txt");
  run.output.assign(std::istreambuf_iterator<char>(in), {});
  run.series = read_series_table(dir / "series.tsv");
  return run;
}

}  // namespace granflow::dem::testing
