#include "dem_coupling/kind/launch.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <thread>

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

std::string shell_line(const std::vector<std::string>& command) {
  std::string line;
  for (const auto& a : command) {
    if (!line.empty()) line += ' ';
    const bool plain = a.find_first_of(" '\"$\\*?;&|<>()") == std::string::npos && !a.empty();
    if (plain) {
      line += a;
      continue;
    }
    line += '\'';
    for (char c : a) line += c == '\'' ? std::string("'\\''") : std::string(1, c);
    line += '\'';
  }
  return line;
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
  // Absolute paths: the child changes directory before it opens the output file.
  const std::string dir = std::filesystem::absolute(directory).string();
  const std::string out = std::filesystem::absolute(output_file).string();
  std::vector<char*> argv;
  std::vector<std::string> args = command;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  // Everything the child needs is prepared before fork: between fork and exec it only makes
  // async-signal-safe calls (rank 0 of a distributed sweep forks from a second thread).
  std::vector<std::string> inherited;
  for (char** e = environ; *e; ++e) inherited.emplace_back(*e);
  std::vector<std::string> env =
      driver_environment(inherited, core::launched_by_mpirun(), ::geteuid() == 0);
  std::vector<char*> envp;
  for (auto& e : env) envp.push_back(e.data());
  envp.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error("cannot fork to launch granflow-dem");
  if (pid == 0) {
    if (::chdir(dir.c_str()) != 0) ::_exit(127);
    const int fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) ::_exit(127);
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    ::close(fd);
    ::execvpe(argv[0], argv.data(), envp.data());
    ::_exit(127);
  }
  int status = 0;
  const auto interval = std::chrono::duration<double>(poll_seconds);
  auto last = std::chrono::steady_clock::now();
  while (true) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0) throw std::runtime_error("waitpid failed for granflow-dem");
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (std::chrono::steady_clock::now() - last >= interval) {
      last = std::chrono::steady_clock::now();
      if (poll) poll();
    }
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return 1;
}

std::string first_error_line(const std::filesystem::path& output_file) {
  std::ifstream in(output_file);
  for (std::string line; std::getline(in, line);)
    if (line.find("ERROR") != std::string::npos) return line;
  return "";
}

}  // namespace granflow::dem
