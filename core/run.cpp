#include "core/run.hpp"

#include <fmt/format.h>
#include <spdlog/sinks/basic_file_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <sys/stat.h>

#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>

#include "core/file_io.hpp"
#include "core/interrupt.hpp"
#include "core/process.hpp"

#ifndef GRANFLOW_SOURCE_DIR
#define GRANFLOW_SOURCE_DIR "."
#endif

namespace granflow::core {

namespace {

namespace fs = std::filesystem;

// `a` is `b` or one of its ancestors (both absolute and normal).
bool contains(const fs::path& a, const fs::path& b) {
  auto ia = a.begin(), ib = b.begin();
  for (; ia != a.end() && ib != b.end(); ++ia, ++ib) {
    if (ia->empty()) continue;  // the trailing "" of "dir/"
    if (*ia != *ib) return false;
  }
  for (; ia != a.end(); ++ia)
    if (!ia->empty()) return false;
  return true;
}

fs::path canonical_or_lexical(const fs::path& p) {
  std::error_code ec;
  fs::path c = fs::weakly_canonical(fs::absolute(p, ec), ec);
  if (ec) c = fs::absolute(p, ec).lexically_normal();
  return c;
}

// A run directory written before the marker existed: log.txt and granflow's own case.yaml.
bool legacy_run_directory(const fs::path& dir) {
  std::ifstream in(dir / "case.yaml");
  std::string first;
  std::getline(in, first);
  return first == "# resolved case as run by granflow (defaults filled in)" &&
         fs::exists(dir / "log.txt");
}

}  // namespace

std::string protected_path(const std::filesystem::path& dir) {
  const std::string name = dir.filename().string();
  if (dir.empty() || name == "." || name == "..") return "is . or ..; --force never replaces it";
  const fs::path target = canonical_or_lexical(dir);
  if (target == target.root_path()) return "is the root directory; --force never replaces it";
  if (const char* home = std::getenv("HOME"); home && *home)
    if (contains(target, canonical_or_lexical(home)))
      return "is your home directory or one of its ancestors; --force never replaces it";
  std::error_code ec;
  if (const fs::path cwd = fs::current_path(ec); !ec && contains(target, canonical_or_lexical(cwd)))
    return "is the working directory or one of its ancestors; --force never replaces it";
  if (contains(target, canonical_or_lexical(source_dir())))
    return "holds the granflow source tree; --force never replaces it";
  return "";
}

std::string force_refusal(const std::filesystem::path& dir) {
  if (std::string why = protected_path(dir); !why.empty()) return why;
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    return "is not a directory, so not a granflow run directory; --force replaces only those "
           "(remove it yourself or choose --out DIR)";
  if (!fs::exists(dir / run_marker, ec) && !fs::exists(dir / study_marker, ec) &&
      !legacy_run_directory(dir))
    return fmt::format(
        "has no {} marker, so granflow did not create it; --force replaces only granflow run "
        "directories (remove it yourself or choose --out DIR)",
        run_marker);
  return "";
}

RunDirectory::RunDirectory(const std::filesystem::path& dir, bool force) : dir_(dir) {
  std::error_code ec;
  if (fs::exists(fs::symlink_status(dir_, ec))) {
    if (!force)
      throw CaseError(
          fmt::format("{}: the run directory exists; a previous run is never overwritten "
                      "(choose --out DIR, or pass --force to replace it)",
                      dir_.string()));
    if (const std::string why = force_refusal(dir_); !why.empty())
      throw CaseError(fmt::format("{}: {}", dir_.string(), why));
    fs::remove_all(dir_, ec);
    if (ec)
      throw CaseError(
          fmt::format("{}: cannot remove the previous run: {}", dir_.string(), ec.message()));
  }
  if (const fs::path parent = dir_.parent_path(); !parent.empty()) {
    fs::create_directories(parent, ec);
    if (ec)
      throw CaseError(fmt::format("{}: cannot create the parent directory {}: {}", dir_.string(),
                                  parent.string(), ec.message()));
  }
  // mkdir fails if the directory exists: of two runs started at once into the same new
  // directory, exactly one gets it and the other is refused here.
  if (::mkdir(dir_.c_str(), 0777) != 0) {
    if (errno == EEXIST)
      throw CaseError(fmt::format(
          "{}: the run directory exists (created by another process just now); a previous run "
          "is never overwritten (choose --out DIR, or pass --force to replace it)",
          dir_.string()));
    throw CaseError(fmt::format("{}: cannot create the run directory: {}", dir_.string(),
                                std::strerror(errno)));
  }
  write_text_file(dir_ / run_marker,
                  "granflow run directory (granflow run --force may replace it)\n");
}

std::vector<std::string> Summary::non_finite() const {
  std::vector<std::string> keys;
  for (const auto& [key, value] : values_)
    if (!std::isfinite(value)) keys.push_back(key);
  return keys;
}

void Summary::write(const std::filesystem::path& file) const {
  std::string out = "{\n";
  std::size_t written = 0, finite = values_.size() - non_finite().size();
  for (const auto& [key, value] : values_) {
    if (!std::isfinite(value)) continue;
    std::string escaped;
    for (char ch : key) {
      if (ch == '"' || ch == '\\') escaped += '\\';
      escaped += ch;
    }
    out += fmt::format("  \"{}\": {:.17g}{}", escaped, value, ++written < finite ? ",\n" : "\n");
  }
  out += "}\n";
  write_text_file(file, out);
}

Summary Summary::read(const std::filesystem::path& file) {
  // summary.json is flat {"name": number|null, ...}; this reads exactly what write() writes and
  // refuses anything else (an empty, truncated or foreign file) with the byte where it stopped.
  std::ifstream in(file);
  if (!in)
    throw std::runtime_error(
        fmt::format("{}: cannot open: {}", file.string(), std::strerror(errno)));
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  std::size_t pos = 0;
  const auto fail = [&](const char* expected) -> void {
    throw std::runtime_error(fmt::format(
        "{}: not a granflow summary.json (byte {} of {}: expected {}); the run may have been "
        "interrupted while writing it",
        file.string(), pos, s.size(), expected));
  };
  const auto skip_space = [&] {
    while (pos < s.size() && std::isspace(static_cast<unsigned char>(s[pos]))) ++pos;
  };
  Summary summary;
  skip_space();
  if (pos >= s.size() || s[pos] != '{') fail("'{'");
  ++pos;
  skip_space();
  bool first = true;
  while (true) {
    skip_space();
    if (pos < s.size() && s[pos] == '}') {
      ++pos;
      break;
    }
    if (!first) {
      if (pos >= s.size() || s[pos] != ',') fail("',' or '}'");
      ++pos;
      skip_space();
    }
    first = false;
    if (pos >= s.size() || s[pos] != '"') fail("a quoted key");
    ++pos;
    std::string key;
    while (pos < s.size() && s[pos] != '"') {
      if (s[pos] == '\\') ++pos;
      if (pos < s.size()) key += s[pos++];
    }
    if (pos >= s.size()) fail("the closing quote of a key");
    ++pos;
    skip_space();
    if (pos >= s.size() || s[pos] != ':') fail("':'");
    ++pos;
    skip_space();
    if (s.compare(pos, 4, "null") == 0) {
      summary.set(key, std::nan(""));
      pos += 4;
      continue;
    }
    const char* begin = s.c_str() + pos;
    char* end = nullptr;
    const double value = std::strtod(begin, &end);
    if (end == begin) fail("a number or null");
    summary.set(key, value);
    pos += static_cast<std::size_t>(end - begin);
  }
  skip_space();
  if (pos != s.size()) fail("the end of the file after '}'");
  return summary;
}

Progress::Progress(std::shared_ptr<spdlog::logger> log, std::string label, double total,
                   double interval_s)
    : log_(std::move(log)),
      label_(std::move(label)),
      total_(total),
      interval_(interval_s),
      start_(std::chrono::steady_clock::now()),
      last_(start_) {}

void Progress::update(double done) {
  const auto now = std::chrono::steady_clock::now();
  if (std::chrono::duration<double>(now - last_).count() < interval_) return;
  last_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double fraction = total_ > 0 ? std::min(1.0, done / total_) : 0.0;
  const double eta = fraction > 0 ? elapsed * (1 - fraction) / fraction : 0.0;
  if (log_)
    log_->info("{}: {:5.1f} % ({:.4g} / {:.4g}), {:.1f} s elapsed, ETA {:.1f} s", label_,
               100 * fraction, done, total_, elapsed, eta);
}

void Progress::finish() {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (log_) log_->info("{}: done in {:.2f} s", label_, elapsed);
}

std::filesystem::path source_dir() {
  if (const char* home = std::getenv("GRANFLOW_HOME"); home && *home) return home;
  return GRANFLOW_SOURCE_DIR;
}

std::string python_interpreter() {
  // Debian's interpreter has python3-matplotlib/python3-h5py; a python3 earlier on PATH (pyenv,
  // venv) may not.
  if (const char* env = std::getenv("GRANFLOW_PYTHON"); env && *env) return env;
  if (std::filesystem::exists("/usr/bin/python3")) return "/usr/bin/python3";
  return "python3";
}

static std::shared_ptr<spdlog::logger> make_logger(const std::filesystem::path& file, bool quiet) {
  std::vector<spdlog::sink_ptr> sinks;
  sinks.push_back(std::make_shared<spdlog::sinks::basic_file_sink_mt>(file.string(), true));
  auto console = std::make_shared<spdlog::sinks::stderr_color_sink_mt>();
  console->set_level(quiet ? spdlog::level::warn : spdlog::level::info);
  sinks.push_back(console);
  auto logger = std::make_shared<spdlog::logger>("granflow", sinks.begin(), sinks.end());
  logger->set_pattern("[%H:%M:%S.%e] %^%l%$ %v");
  logger->set_level(spdlog::level::info);
  logger->flush_on(spdlog::level::info);
  return logger;
}

RunContext::RunContext(const Case& c, const std::filesystem::path& dir, bool force, bool quiet)
    : run_case(c),
      directory(dir, force),
      log(make_logger(directory / "log.txt", quiet)),
      result(directory / "result.h5"),
      started(std::chrono::steady_clock::now()) {
  write_text_file(directory / "case.yaml",
                  "# resolved case as run by granflow (defaults filled in)\n" + c.resolved_yaml());
  result.attribute("/", "case_name", c.name());
  result.attribute("/", "kind", c.kind());
  result.attribute("/", "granflow_version", std::string("0.1.0"));
  result.flush();  // readable from the start, even if the process is killed (SIGKILL)
}

RunContext::~RunContext() = default;

double RunContext::wall_seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
}

void RunContext::plot(const std::string& script) {
  const auto path = source_dir() / "analysis" / "plots" / script;
  if (interrupted()) {
    log->info("interrupted: not plotting with {} (rerun: {} {} {})", script,
              shell_quote(python_interpreter()), shell_quote(path.string()),
              shell_quote(directory.path().string()));
    return;
  }
  if (!std::filesystem::exists(path)) {
    record_plot_failure();
    log->warn("plot script {} not found; no PNG written", path.string());
    return;
  }
  result.flush();
  // result.h5 is still open for writing (flushed above): read it without HDF5's file lock.
  ProcessOptions options;
  options.output = directory / "log.txt";
  options.append = true;
  options.set_environment = {"HDF5_USE_FILE_LOCKING=FALSE"};
  const ProcessResult r =
      run_process({python_interpreter(), path.string(), directory.path().string()}, options);
  if (!r.ok()) record_plot_failure();
  if (!r.started())
    log->warn("plotting with {} failed: {}; data in result.h5 is complete", script, r.error);
  else if (r.status != 0)
    log->warn(
        "plotting with {} failed (exit {}; its own message is at the end of log.txt); data in "
        "result.h5 is complete",
        script, r.status);
}

void RunContext::finish() {
  summary.set("cost.wall_s", wall_seconds());
  result.close();
  summary.write(directory / "summary.json");
}

namespace {
std::atomic<bool> plot_failure_recorded{false};
}  // namespace

void record_plot_failure() { plot_failure_recorded = true; }
bool plot_failed() { return plot_failure_recorded; }
bool strict_plots() {
  const char* env = std::getenv("GRANFLOW_STRICT_PLOTS");
  return env && *env && std::string_view(env) != "0";
}

}  // namespace granflow::core
