// Child processes without a shell: every program granflow starts (plot scripts, study scripts,
// granflow-dem, mpirun) is started from an argument vector, so no path, case name or option
// value is ever parsed by /bin/sh. Command lines shown to the user (a "rerun by hand" log line)
// are quoted with shell_quote, the one quoting function of the project.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace granflow::core {

struct ProcessOptions {
  // Empty: the child inherits this process's stdout/stderr. Otherwise both go to this file
  // (created 0644; truncated, or appended to when `append`). A relative path is taken relative
  // to this process's working directory, not to `directory`.
  std::filesystem::path output;
  bool append = false;
  // Empty: this process's working directory. Otherwise the child changes to it before exec.
  std::filesystem::path directory;
  // The child's whole environment (NAME=value entries); unset: this process's environment.
  std::optional<std::vector<std::string>> environment;
  // NAME=value entries set on top of the environment above (replacing the same NAME).
  std::vector<std::string> set_environment;
  // Called about every `poll_seconds` while the child runs (progress reports); may be empty.
  std::function<void()> poll;
  double poll_seconds = 2.0;
};

struct ProcessResult {
  // The exit status of the child; 128 + N when it was killed by signal N; 127 when it could not
  // be started (then `error` says why).
  int status = 0;
  // Empty when the program ran; else "cannot start PROGRAM: strerror" (or the chdir/open step
  // that failed, with its path).
  std::string error;
  bool started() const { return error.empty(); }
  bool ok() const { return started() && status == 0; }
};

// Starts argv[0] (searched on PATH when it has no '/') with arguments argv[1..], waits for it and
// returns its status. Never uses a shell. Safe to call from any thread (only async-signal-safe
// calls between fork and exec). An empty argv is an error result, not an exception.
ProcessResult run_process(const std::vector<std::string>& argv, const ProcessOptions& options = {});

// POSIX shell quoting of one word: unchanged when it is made only of characters that no shell
// treats specially ([A-Za-z0-9_./:,+@%-], non-empty), else in single quotes with each ' written
// as '\''. `sh -c "printf %s $(shell_quote(x))"` prints x exactly, for any x without NUL.
std::string shell_quote(const std::string& word);

// The words of `argv`, each shell_quote'd, joined by spaces (a command line to copy and paste).
std::string shell_line(const std::vector<std::string>& argv);

}  // namespace granflow::core
