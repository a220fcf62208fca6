// Test support: run granflow-dem (1 or 2 ranks) on a deck in a fresh directory under the build
// tree and read its series.
#pragma once

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "dem_coupling/kind/series_table.hpp"

namespace granflow::dem::testing {

inline std::filesystem::path fresh_directory(const std::string& name) {
  const auto dir = std::filesystem::path(GRANFLOW_BINARY_DIR) / "test-dem" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// The start of a hand-written deck for the driver: the gf_* variables it reads (no shear, no
// servo; sampling every `sample_every` of `total_steps` steps) and the granular atom setup with
// periodic boundaries in SI units. The test adds the box, atoms, contact law and computes.
inline std::string driver_deck_header(long total_steps, long sample_every, double particle_density,
                                      int profile_bins = 2) {
  return fmt::format(R"(variable gf_shear_rate equal 0
variable gf_total_steps equal {}
variable gf_sample_every equal {}
variable gf_constant_pressure equal 0
variable gf_normal_stress equal 0
variable gf_servo_gain equal 0
variable gf_servo_max_strain equal 0
variable gf_servo_every equal {}
variable gf_profile_bins equal {}
variable gf_particle_density equal {}
atom_style      granular
atom_modify     map array
boundary        p p p
newton          off
communicate     single vel yes
units           si
)",
                     total_steps, sample_every, sample_every, profile_bins, particle_density);
}

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
