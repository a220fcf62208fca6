// The granflow executable run on the cases of cases/mpm/ by the MPM end-to-end tests: started
// from an argument vector (no shell), stdout+stderr captured in a file.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/process.hpp"

namespace granflow::test {

struct Output {
  int code;
  std::string text;
};

// A fresh directory test_scratch/<name> of the build tree.
inline std::filesystem::path mpm_scratch(const std::string& name) {
  const auto dir = std::filesystem::path(GRANFLOW_BINARY_DIR) / "test_scratch" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// granflow ARGS with its output in `output_file`: the exit code and that output.
inline Output run_granflow(const std::vector<std::string>& args,
                           const std::filesystem::path& output_file) {
  std::vector<std::string> argv = {std::string(GRANFLOW_BINARY_DIR) + "/app/granflow"};
  argv.insert(argv.end(), args.begin(), args.end());
  core::ProcessOptions options;
  options.output = output_file;
  const core::ProcessResult r = core::run_process(argv, options);
  std::ifstream in(output_file);
  std::stringstream text;
  text << in.rdbuf();
  return {r.status, r.error + text.str()};
}

inline std::string mpm_case(const std::string& file) {
  return (std::filesystem::path(GRANFLOW_SOURCE_DIR) / "cases" / "mpm" / file).string();
}

}  // namespace granflow::test
