// Test support: the granflow program run on a DEM case in a fresh directory of the build tree
// (tests/dem/test_steady_flags.cpp, test_frozen_flag.cpp). Needs GRANFLOW_CLI_PATH.
#pragma once

#include <fmt/format.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/dem/scratch_dir.hpp"

namespace granflow::dem::testing {

// `granflow ARGS` in `dir`, its output in dir/cli.txt; the exit status.
inline int run_cli(const std::string& args, const std::filesystem::path& dir) {
  const std::string cmd =
      fmt::format("cd '{}' && '{}' {} > cli.txt 2>&1", dir.string(), GRANFLOW_CLI_PATH, args);
  const int raw = std::system(cmd.c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : 128;
}

inline std::string read(const std::filesystem::path& file) {
  std::ifstream in(file);
  return {std::istreambuf_iterator<char>(in), {}};
}

}  // namespace granflow::dem::testing
