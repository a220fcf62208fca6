// The granflow executable as a child process the test can signal: started from an argument
// vector (no shell), stdout+stderr to a file, its pid known so that SIGINT/SIGTERM/SIGKILL can be
// sent while it runs.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace granflow::test {

inline std::string slurp(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class GranflowChild {
 public:
  GranflowChild(const std::vector<std::string>& args, const std::filesystem::path& output)
      : output_(output) {
    std::vector<std::string> words = {std::string(GRANFLOW_BINARY_DIR) + "/app/granflow"};
    words.insert(words.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, output.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    if (posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
  }
  ~GranflowChild() {
    if (pid_ > 0 && !done_) {
      ::kill(pid_, SIGKILL);
      wait();
    }
  }
  pid_t pid() const { return pid_; }
  void signal(int sig) const { ::kill(pid_, sig); }
  // Waits up to `limit` for `file` to exist and hold `text`; false on time-out or exit.
  bool wait_for_text(const std::filesystem::path& file, const std::string& text,
                     std::chrono::seconds limit) {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < end) {
      if (slurp(file).find(text) != std::string::npos) return true;
      if (exited()) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return false;
  }
  // The exit code as a shell shows it: the status, or 128 + the signal that killed it.
  int wait() {
    if (done_) return code_;
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    done_ = true;
    code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return code_;
  }
  std::string output() const { return slurp(output_); }

 private:
  bool exited() {
    if (done_) return true;
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) != pid_) return false;
    done_ = true;
    code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return true;
  }
  std::filesystem::path output_;
  pid_t pid_ = -1;
  bool done_ = false;
  int code_ = -1;
};

// Processes whose working directory is `dir` or below it (a granflow-dem left running there).
inline std::vector<pid_t> processes_working_in(const std::filesystem::path& dir) {
  std::vector<pid_t> found;
  const std::string prefix = std::filesystem::weakly_canonical(dir).string();
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator("/proc", ec)) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::error_code link_ec;
    const auto cwd = std::filesystem::read_symlink(entry.path() / "cwd", link_ec);
    if (!link_ec && cwd.string().rfind(prefix, 0) == 0) found.push_back(std::stoi(name));
  }
  return found;
}

}  // namespace granflow::test
