// What every run has: its directory (never overwritten silently), log, result.h5, summary.json,
// progress reporting, cost accounting, and the numerical-failure stop
// (core/numerical_failure.hpp).
#pragma once

#include <spdlog/logger.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/case.hpp"
#include "core/numerical_failure.hpp"
#include "core/result_file.hpp"

namespace granflow::core {

// Exit codes of the CLI.
enum ExitCode : int {
  exit_ok = 0,
  exit_failure = 1,
  exit_bad_input = 2,
  exit_numerical = 3,
  exit_external = 4,
  exit_io = 5  // an output could not be written (the line names the path and the system's reason)
};
// An interrupted run exits 128 + the signal: 130 (SIGINT), 143 (SIGTERM); core/interrupt.hpp.

// Written into every run directory when it is created; --force replaces only directories that
// hold it (or a closure study's study_marker, or a run directory of a granflow from before the
// marker: log.txt and granflow's own case.yaml).
inline constexpr const char* run_marker = ".granflow-run";
inline constexpr const char* study_marker = ".granflow-study";

// Why `dir` may never be deleted by --force, whatever it holds ("" when it is not protected): .
// or .., /, $HOME, the working directory, the source tree (source_dir()) or an ancestor of these.
std::string protected_path(const std::filesystem::path& dir);

// Why --force may not replace the existing `dir` ("" when it may): never ., .., /, $HOME, the
// working directory, the source tree or an ancestor of these; else only a granflow run directory.
std::string force_refusal(const std::filesystem::path& dir);

// A run directory: default runs/<case-name>/. Existing directories are refused unless `force`,
// and with `force` unless force_refusal allows it (CaseError naming the path and why). Created
// atomically (parents first; the directory itself with a mkdir that fails if it exists), with
// run_marker in it.
class RunDirectory {
 public:
  RunDirectory(const std::filesystem::path& dir, bool force);
  const std::filesystem::path& path() const { return dir_; }
  std::filesystem::path operator/(const std::string& file) const { return dir_ / file; }

 private:
  std::filesystem::path dir_;
};

// summary.json: flat "name": number map, written sorted by key. Only finite numbers are written:
// non_finite() lists the others, which the CLI reports as a numerical failure (exit 3) instead.
class Summary {
 public:
  void set(const std::string& key, double value) { values_[key] = value; }
  bool contains(const std::string& key) const { return values_.count(key) != 0; }
  double get(const std::string& key) const { return values_.at(key); }
  const std::map<std::string, double>& values() const { return values_; }
  std::vector<std::string> non_finite() const;
  // Atomically (a reader sees the previous file or the whole new one); IoError on failure.
  void write(const std::filesystem::path& file) const;
  static Summary read(const std::filesystem::path& file);

 private:
  std::map<std::string, double> values_;
};

// Progress with ETA for long loops: logs at most every `interval` seconds.
class Progress {
 public:
  Progress(std::shared_ptr<spdlog::logger> log, std::string label, double total,
           double interval_s = 5.0);
  void update(double done);  // cheap when nothing is printed
  void finish();

 private:
  std::shared_ptr<spdlog::logger> log_;
  std::string label_;
  double total_;
  double interval_;
  std::chrono::steady_clock::time_point start_, last_;
};

// Everything a kind's run function gets. Created by the CLI.
struct RunContext {
  RunContext(const Case& run_case, const std::filesystem::path& dir, bool force, bool quiet);
  ~RunContext();

  const Case& run_case;
  RunDirectory directory;
  std::shared_ptr<spdlog::logger> log;  // log.txt + stderr
  ResultFile result;                    // result.h5
  Summary summary;                      // summary.json (written by finish())
  std::chrono::steady_clock::time_point started;

  double wall_seconds() const;
  // Run a plot script analysis/plots/<script> on this run directory (python3 + matplotlib).
  // A missing matplotlib is a logged warning, not a failed run.
  void plot(const std::string& script);
  // Write summary.json (adds cost.wall_s) and close result.h5. Called on success, on failure and
  // on interruption; throws IoError when either cannot be written.
  void finish();
};

// The source tree (for plot scripts), set at build time, overridable by GRANFLOW_HOME.
std::filesystem::path source_dir();

// The Python interpreter for plots and study scripts: GRANFLOW_PYTHON, else Debian's
// /usr/bin/python3 (it has python3-matplotlib and python3-h5py), else python3 on PATH.
std::string python_interpreter();

// Plot scripts. A plot that fails while the data was written is a warning and the run still exits
// 0 (the PNG can be made again from result.h5), unless GRANFLOW_STRICT_PLOTS is set to a value
// other than 0: then the run exits 4 (exit_external), so that the tests (which set it on every
// test) fail when a plot script breaks. Every plot failure in this process is recorded here.
void record_plot_failure();
bool plot_failed();
bool strict_plots();

}  // namespace granflow::core
