#include "core/process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <optional>
#include <thread>

#include "core/interrupt.hpp"

extern char** environ;

namespace granflow::core {

namespace {

// What the child reports through the close-on-exec pipe when it cannot get to exec.
enum class Step : int { chdir = 1, open_output = 2, exec = 3, setup = 4 };
struct ChildFailure {
  Step step;
  int error;
};

std::vector<std::string> child_environment(const ProcessOptions& options) {
  std::vector<std::string> env;
  if (options.environment) {
    env = *options.environment;
  } else {
    for (char** e = environ; e && *e; ++e) env.emplace_back(*e);
  }
  for (const auto& entry : options.set_environment) {
    const std::string name = entry.substr(0, entry.find('=') + 1);  // "NAME="
    std::erase_if(env, [&](const std::string& e) { return e.rfind(name, 0) == 0; });
    env.push_back(entry);
  }
  return env;
}

std::string describe(const ChildFailure& f, const std::string& program,
                     const std::string& directory, const std::string& output) {
  const char* why = std::strerror(f.error);
  switch (f.step) {
    case Step::chdir:
      return "cannot start " + program + ": cannot change to directory " + directory + ": " + why;
    case Step::open_output:
      return "cannot start " + program + ": cannot open " + output + ": " + why;
    case Step::setup:
      return "cannot start " + program + ": cannot set up its process group or input: " + why;
    case Step::exec:
      break;
  }
  return "cannot start " + program + ": " + why;
}

}  // namespace

ProcessResult run_process(const std::vector<std::string>& argv_in, const ProcessOptions& options) {
  if (argv_in.empty()) return {127, "cannot start a program: empty argument vector"};
  // Everything the child needs is prepared before fork: between fork and exec it only makes
  // async-signal-safe calls (rank 0 of a distributed sweep starts children from a second thread).
  std::vector<std::string> args = argv_in;
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::vector<std::string> env = child_environment(options);
  std::vector<char*> envp;
  for (auto& e : env) envp.push_back(e.data());
  envp.push_back(nullptr);
  // Absolute: the child changes directory before it opens the output file.
  const std::string output =
      options.output.empty() ? std::string() : std::filesystem::absolute(options.output).string();
  const std::string directory = options.directory.string();
  const int flags = O_WRONLY | O_CREAT | O_CLOEXEC | (options.append ? O_APPEND : O_TRUNC);

  int report[2];
  if (::pipe2(report, O_CLOEXEC) != 0)
    return {127, "cannot start " + args[0] + ": pipe: " + std::strerror(errno)};
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int err = errno;
    ::close(report[0]);
    ::close(report[1]);
    return {127, "cannot start " + args[0] + ": fork: " + std::strerror(err)};
  }
  if (pid == 0) {
    ::close(report[0]);
    auto fail = [&](Step step) {
      const ChildFailure f{step, errno};
      [[maybe_unused]] const auto written = ::write(report[1], &f, sizeof f);
      ::_exit(127);
    };
    // A process group of its own, so that granflow alone decides when it stops (an interrupted
    // run stops the whole group, mpirun and its ranks included); SIGTERM when granflow dies
    // without doing so (SIGKILL); no input (a child never reads the terminal).
    if (::setpgid(0, 0) != 0) fail(Step::setup);
    if (::prctl(PR_SET_PDEATHSIG, SIGTERM) != 0) fail(Step::setup);
    if (const int null = ::open("/dev/null", O_RDONLY); null < 0 || ::dup2(null, 0) < 0)
      fail(Step::setup);
    if (!directory.empty() && ::chdir(directory.c_str()) != 0) fail(Step::chdir);
    if (!output.empty()) {
      const int fd = ::open(output.c_str(), flags, 0644);
      if (fd < 0) fail(Step::open_output);
      ::dup2(fd, 1);
      ::dup2(fd, 2);
      ::close(fd);
    }
    ::execvpe(argv[0], argv.data(), envp.data());
    fail(Step::exec);
  }
  ::setpgid(pid, pid);  // also here, so the group exists before the parent may signal it
  ::close(report[1]);
  ChildFailure failure{};
  ssize_t got = 0;
  do {
    got = ::read(report[0], &failure, sizeof failure);
  } while (got < 0 && errno == EINTR);
  ::close(report[0]);

  // Waits in short sleeps so that an interrupted run (SIGINT/SIGTERM, core/interrupt.hpp) stops
  // the child's process group: SIGTERM, then SIGKILL if it is still there after a grace time.
  int status = 0;
  const bool running = got != static_cast<ssize_t>(sizeof failure);
  const auto interval = std::chrono::duration<double>(options.poll_seconds);
  const auto grace = std::chrono::seconds(10);
  auto last = std::chrono::steady_clock::now();
  std::optional<std::chrono::steady_clock::time_point> terminated;
  bool killed = false;
  while (true) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR)
      return {127, "waiting for " + args[0] + ": " + std::strerror(errno)};
    if (running && interrupted()) {
      const auto now = std::chrono::steady_clock::now();
      if (!terminated) {
        ::kill(-pid, SIGTERM);
        terminated = now;
      } else if (!killed && now - *terminated > grace) {
        ::kill(-pid, SIGKILL);
        killed = true;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (running && options.poll && std::chrono::steady_clock::now() - last >= interval) {
      last = std::chrono::steady_clock::now();
      options.poll();
    }
  }
  // The child is gone; anything it left in its group (a rank of mpirun) goes with it.
  if (terminated) ::kill(-pid, SIGKILL);
  if (got == static_cast<ssize_t>(sizeof failure))
    return {127, describe(failure, args[0], directory, output)};
  if (WIFEXITED(status)) return {WEXITSTATUS(status), ""};
  if (WIFSIGNALED(status)) return {128 + WTERMSIG(status), ""};
  return {1, ""};
}

std::string shell_quote(const std::string& word) {
  const bool plain = !word.empty() && word.find_first_not_of(
                                          "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                          "0123456789_./:,+@%-") == std::string::npos;
  if (plain) return word;
  std::string quoted = "'";
  for (char ch : word) quoted += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return quoted + "'";
}

std::string shell_line(const std::vector<std::string>& argv) {
  std::string line;
  for (const auto& word : argv) {
    if (!line.empty()) line += ' ';
    line += shell_quote(word);
  }
  return line;
}

}  // namespace granflow::core
