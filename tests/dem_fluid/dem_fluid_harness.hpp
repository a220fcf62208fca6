// Helpers of the fix fluid/le verification tests: hand-written decks run by the granflow-dem
// driver binary of the build tree (1 or 2 MPI ranks), and their `fix print` tables.
#pragma once

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "tests/dem/driver_deck.hpp"

namespace granflow::dem::test {

inline const std::string driver = GRANFLOW_BINARY_DIR "/dem_coupling/granflow-dem";

// Parameters the driver reads after the deck (its shear stage is a single sampled step here:
// the physics of each test runs inside the deck), the material, and the contact model.
inline std::string deck_preamble(const std::string& region, double dt) {
  return granflow::dem::testing::driver_deck_header(1, 1, 2500, 1) +
         fmt::format(R"({region}
neighbor        0.0002 bin
neigh_modify    delay 0
fix m1 all property/global youngsModulus peratomtype 1.e7
fix m2 all property/global poissonsRatio peratomtype 0.3
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.7
fix m4 all property/global coefficientFriction peratomtypepair 1 0.5
pair_style      gran model hertz tangential history
pair_coeff      * *
timestep        {dt:.17g}
compute         gf_virial all pressure thermo_temp virial
thermo_style    custom step atoms c_gf_virial[2]
thermo          100000
)",
                     fmt::arg("region", region), fmt::arg("dt", dt));
}

struct RunResult {
  int exit_code = -1;
  std::string output;  // stdout + stderr of the driver
};

// Writes `deck` to dir/in.test and runs the driver there with `ranks` MPI ranks.
inline RunResult run_deck(const std::filesystem::path& dir, const std::string& deck, int ranks) {
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "in.test") << deck;
  std::string launcher;
  if (ranks > 1)
    launcher = fmt::format(
        "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
        "OMPI_MCA_rmaps_base_oversubscribe=1 "
        "mpirun -np {} --oversubscribe ",
        ranks);
  const std::string command = fmt::format(
      "cd '{}' && {}'{}' in.test -log log.txt -screen none "
      "> run.out 2>&1",
      dir.string(), launcher, driver);
  RunResult r;
  const int status = std::system(command.c_str());
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(dir / "run.out");
  std::stringstream ss;
  ss << in.rdbuf();
  r.output = ss.str();
  return r;
}

// Rows of numbers of a `fix print` / `fix ave/time` file ('#' lines skipped).
inline std::vector<std::vector<double>> read_table(const std::filesystem::path& file) {
  std::vector<std::vector<double>> rows;
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::vector<double> row;
    double v;
    while (ls >> v) row.push_back(v);
    if (!row.empty()) rows.push_back(row);
  }
  return rows;
}

inline std::filesystem::path test_dir(const std::string& name) {
  return std::filesystem::path(GRANFLOW_BINARY_DIR) / "tests" / "dem_fluid" / "runs" / name;
}

}  // namespace granflow::dem::test
