// Test support: a fresh directory under the build tree for one DEM test (test-dem/NAME).
#pragma once

#include <filesystem>
#include <string>

namespace granflow::dem::testing {

inline std::filesystem::path fresh_directory(const std::string& name) {
  const auto dir = std::filesystem::path(GRANFLOW_BINARY_DIR) / "test-dem" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace granflow::dem::testing
