#include "dem_coupling/kind/launch.hpp"

#include <unistd.h>

#include <cstdlib>
#include <fstream>

#include "core/process.hpp"
#include "core/sweep_scheduler.hpp"

extern char** environ;

namespace granflow::dem {

std::filesystem::path driver_path() {
  if (const char* env = std::getenv("GRANFLOW_DEM_DRIVER"); env && *env) return env;
  return GRANFLOW_DEM_DRIVER;
}

std::vector<std::string> driver_command(int ranks, const std::string& deck_name) {
  std::vector<std::string> cmd;
  if (ranks > 1) {
    cmd = {"mpirun", "--oversubscribe"};
    if (::geteuid() == 0) cmd.push_back("--allow-run-as-root");
    cmd.insert(cmd.end(), {"-np", std::to_string(ranks)});
  }
  cmd.push_back(driver_path().string());
  cmd.push_back(deck_name);
  return cmd;
}

std::vector<std::string> driver_environment(const std::vector<std::string>& inherited,
                                            bool inside_mpi_job, bool root) {
  auto starts = [](const std::string& entry, const char* prefix) {
    return entry.rfind(prefix, 0) == 0;
  };
  std::vector<std::string> env;
  for (const auto& entry : inherited) {
    if (root && starts(entry, "OMPI_ALLOW_RUN_AS_ROOT")) continue;  // set below
    if (inside_mpi_job && (starts(entry, "OMPI_") || starts(entry, "PMIX_"))) continue;
    env.push_back(entry);
  }
  if (root) {
    env.push_back("OMPI_ALLOW_RUN_AS_ROOT=1");
    env.push_back("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1");
  }
  return env;
}

int run_in_directory(const std::vector<std::string>& command,
                     const std::filesystem::path& directory,
                     const std::filesystem::path& output_file, const std::function<void()>& poll,
                     double poll_seconds) {
  std::vector<std::string> inherited;
  for (char** e = environ; *e; ++e) inherited.emplace_back(*e);
  core::ProcessOptions options;
  options.directory = std::filesystem::absolute(directory);
  options.output = std::filesystem::absolute(output_file);
  options.environment = driver_environment(inherited, core::launched_by_mpirun(), ::geteuid() == 0);
  options.poll = poll;
  options.poll_seconds = poll_seconds;
  const core::ProcessResult r = core::run_process(command, options);
  if (!r.started())  // said where the run's errors are looked for (first_error_line)
    std::ofstream(output_file, std::ios::app) << "ERROR: granflow: " << r.error << "\n";
  return r.status;
}

std::string first_error_line(const std::filesystem::path& output_file) {
  std::ifstream in(output_file);
  for (std::string line; std::getline(in, line);)
    if (line.find("ERROR") != std::string::npos) return line;
  return "";
}

}  // namespace granflow::dem
