// Fuzz of the case check: seeded random mutations of the shipped case files (lines deleted,
// duplicated or swapped, values swapped between lines, random bytes, huge, negative, empty or
// odd values, truncation), each validated as `granflow check` validates it (peek_kind, the kind
// registry's schema, Case::load, the kind's cross-check on every condition). Every mutation must
// end "valid" or in a CaseError, never in another exception, a crash or more than kBound
// seconds; a subset also runs the granflow binary (no shell, under `timeout`), which must agree:
// exit 0 or exit 2 with one line. Reproducible: the seed is fixed, and a failing input is kept
// in the scratch directory the test prints.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <random>
#include <sstream>
#include <thread>
#include <typeinfo>

#include "app/registry.hpp"
#include "core/case.hpp"
#include "core/kind_registry.hpp"
#include "core/process.hpp"

namespace fs = std::filesystem;
using namespace granflow;

namespace {

constexpr std::uint64_t kSeed = 20250101;
constexpr int kMutations = 10000;
constexpr int kBinaryEvery = 50;  // 200 of them also through the granflow binary
// A check does no work in proportion to the input's numbers: the shipped cases take ~1 ms
// in-process and ~0.1 s as a process; 2 s leaves room for a loaded 2-core machine.
constexpr double kBound = 2.0;

const fs::path source = GRANFLOW_SOURCE_DIR;
const std::string granflow_binary = std::string(GRANFLOW_BINARY_DIR) + "/app/granflow";

std::string read(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// ---- validation as app/main.cpp load_and_check does it
enum class Outcome { valid, case_error, other };

struct Verdict {
  Outcome outcome = Outcome::valid;
  std::string message;
  double seconds = 0;
};

Verdict validate(const core::KindRegistry& registry, const fs::path& file) {
  Verdict v;
  const auto start = std::chrono::steady_clock::now();
  try {
    const auto [kind, test] = core::peek_kind(file);
    const core::KindEntry& entry = registry.find(kind, test, file.string());
    const core::Case c = core::Case::load(file, {}, entry.schema);
    if (entry.check)
      for (const auto& condition : c.expand_sweep()) entry.check(condition);
  } catch (const core::CaseError& e) {
    v.outcome = Outcome::case_error;
    v.message = e.what();
  } catch (const std::exception& e) {
    v.outcome = Outcome::other;
    v.message = std::string(typeid(e).name()) + ": " + e.what();
  } catch (...) {
    v.outcome = Outcome::other;
    v.message = "an exception that is not a std::exception";
  }
  v.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return v;
}

// ---- mutations of a case file's text
std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start < text.size()) {
    const auto end = text.find('\n', start);
    lines.push_back(text.substr(start, end == std::string::npos ? end : end - start));
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return lines;
}

std::string join_lines(const std::vector<std::string>& lines) {
  std::string text;
  for (const auto& l : lines) text += l + "\n";
  return text;
}

// [begin, end) of the value of a `key: value  # comment` line; begin == end when none
std::pair<std::size_t, std::size_t> value_span(const std::string& line) {
  const auto colon = line.find(": ");
  if (colon == std::string::npos || line.find_first_not_of(' ') == colon) return {0, 0};
  const auto begin = line.find_first_not_of(' ', colon + 1);
  if (begin == std::string::npos || line[begin] == '#') return {0, 0};
  auto end = line.find(" #", begin);
  if (end == std::string::npos) end = line.size();
  while (end > begin && line[end - 1] == ' ') --end;
  return {begin, end};
}

const char* const kOperators[] = {"delete line",  "duplicate line", "swap lines", "swap values",
                                  "random bytes", "huge number",    "negative",   "empty value",
                                  "odd value",    "truncate",       "odd key",    "tab indent",
                                  "list element", "include"};
constexpr int kOperatorCount = int(std::size(kOperators));

class Mutator {
 public:
  explicit Mutator(std::uint64_t seed) : rng_(seed) {}

  std::size_t below(std::size_t n) { return n == 0 ? 0 : std::size_t(rng_() % n); }

  // Applies operator `op` to `text`.
  std::string apply(int op, const std::string& text) {
    auto lines = split_lines(text);
    if (lines.empty()) return text;
    const std::size_t i = below(lines.size());
    switch (op) {
      case 0:
        lines.erase(lines.begin() + long(i));
        break;
      case 1:
        lines.insert(lines.begin() + long(i), lines[i]);
        break;
      case 2:
        std::swap(lines[i], lines[below(lines.size())]);
        break;
      case 3: {
        const auto with_value = value_lines(lines);
        if (with_value.size() < 2) break;
        const auto a = with_value[below(with_value.size())];
        const auto b = with_value[below(with_value.size())];
        const auto [ab, ae] = value_span(lines[a]);
        const auto [bb, be] = value_span(lines[b]);
        const std::string va = lines[a].substr(ab, ae - ab), vb = lines[b].substr(bb, be - bb);
        lines[a].replace(ab, ae - ab, vb);
        lines[b].replace(bb, be - bb, va);
        break;
      }
      case 4: {
        std::string bytes;
        for (std::size_t n = 1 + below(8); n > 0; --n) bytes += char(below(256));
        std::string out = join_lines(lines);
        return out.insert(below(out.size() + 1), bytes);
      }
      case 5:
        return replace_value(
            lines, {"1e300", "-1e300", "1e20", "9.3e18", "2147483648", "4294967296", "1e-320",
                    "1.7976931348623157e308", "1e10", "123456789012345678901234567890", "1e400"});
      case 6: {
        const auto with_value = value_lines(lines);
        if (with_value.empty()) break;
        const auto a = with_value[below(with_value.size())];
        const auto [b, e] = value_span(lines[a]);
        lines[a].insert(b, below(2) ? "-" : "-1");
        if (e > b && below(2)) lines[a].replace(b, e - b + 1, "-1");
        break;
      }
      case 7:
        return replace_value(lines, {"", "\"\"", "~", "null"});
      case 8:
        return replace_value(lines, {"abc", "[]", "{}", "[1, 2", ".nan", ".inf", "-.inf", "*a",
                                     "&a 1", "0x10", "true", "[1e300, 1e300]", "{a: 1}", "0",
                                     "1e-300", "[0, 0, 0]", "2.5", "'1e5'", "!!str 3"});
      case 9: {
        const std::string out = join_lines(lines);
        return out.substr(0, below(out.size()));
      }
      case 10: {  // a key YAML allows and a case does not, with the indentation of line i
        const std::string indent = lines[i].substr(0, lines[i].find_first_not_of(' '));
        const char* const keys[] = {"[a]: 1", "{a: 1}: 2", "? [b]\n: 3", "~: 4",         "1: 5",
                                    "---",    "...",       "<<: *x",     "x: &x {a: 1}", "\"\": 6"};
        lines.insert(lines.begin() + long(i), indent + keys[below(std::size(keys))]);
        break;
      }
      case 11:
        if (lines[i].rfind("  ", 0) == 0) lines[i].replace(0, 2, "\t");
        break;
      case 12: {  // an element of a flow list [a, b, c]
        std::vector<std::size_t> with_list;
        for (std::size_t k = 0; k < lines.size(); ++k)
          if (lines[k].find('[') != std::string::npos && lines[k].find(']') != std::string::npos)
            with_list.push_back(k);
        if (with_list.empty()) break;
        std::string& line = lines[with_list[below(with_list.size())]];
        const auto open = line.find('['), close = line.find(']', open);
        if (close == std::string::npos) break;
        std::vector<std::size_t> commas{open};
        for (auto c = line.find(',', open); c < close; c = line.find(',', c + 1))
          commas.push_back(c);
        commas.push_back(close);
        const std::size_t e = below(commas.size() - 1);
        const char* const values[] = {" 1e300",  " -1", " 0", " abc",  " []",
                                      " 1e-320", "",    " 5", " 5, 5", " 1e400"};
        line.replace(commas[e] + 1, commas[e + 1] - commas[e] - 1,
                     values[below(std::size(values))]);
        break;
      }
      default:
        break;
    }
    return join_lines(lines);
  }

 private:
  std::vector<std::size_t> value_lines(const std::vector<std::string>& lines) {
    std::vector<std::size_t> out;
    for (std::size_t k = 0; k < lines.size(); ++k)
      if (const auto [b, e] = value_span(lines[k]); e > b) out.push_back(k);
    return out;
  }

  std::string replace_value(std::vector<std::string> lines,
                            const std::vector<std::string>& choices) {
    const auto with_value = value_lines(lines);
    if (!with_value.empty()) {
      const auto a = with_value[below(with_value.size())];
      const auto [b, e] = value_span(lines[a]);
      lines[a].replace(b, e - b, choices[below(choices.size())]);
    }
    return join_lines(lines);
  }

  std::mt19937_64 rng_;
};

// ---- crash and hang reports name the mutation (its input stays on disk)
volatile std::sig_atomic_t current_mutation = -1;
char current_file[512] = {};
std::atomic<double> mutation_started{0};

void on_crash(int sig) {
  const char head[] = "\nfuzz: the check crashed or hung (over 30 s) on mutation ";
  char number[24];
  int n = 0;
  for (long m = current_mutation < 0 ? 0 : current_mutation; n == 0 || m > 0; m /= 10)
    number[n++] = char('0' + m % 10);
  (void)!::write(2, head, sizeof head - 1);
  while (n > 0) (void)!::write(2, &number[--n], 1);
  const char mid[] = "; its input: ";
  (void)!::write(2, mid, sizeof mid - 1);
  (void)!::write(2, current_file, std::strlen(current_file));
  (void)!::write(2, "\n", 1);
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// A fresh copy of cases/ (so that includes resolve as for the originals) in a scratch directory.
fs::path scratch_cases() {
  const fs::path dir = fs::temp_directory_path() / ("granflow_fuzz_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::copy(source / "cases", dir / "cases", fs::copy_options::recursive);
  return dir;
}

// The case files of `granflow check` (closure_study_*.yaml are `study closures` inputs).
std::vector<fs::path> shipped_cases(const fs::path& cases) {
  std::vector<fs::path> out;
  for (const auto& sub : {"rev", "mpm", "dem", "pair", "calibrate"})
    for (const auto& entry : fs::directory_iterator(cases / sub))
      if (entry.path().extension() == ".yaml" &&
          entry.path().filename().string().rfind("closure_study_", 0) != 0)
        out.push_back(entry.path());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST(FuzzCheck, MutatedShippedCasesAreValidOrOneCaseError) {
  const auto start = std::chrono::steady_clock::now();
  const core::KindRegistry registry = app::make_registry();
  const fs::path dir = scratch_cases();
  const auto cases = shipped_cases(dir / "cases");
  ASSERT_GE(cases.size(), 30u);
  std::vector<std::string> originals;
  for (const auto& c : cases) {
    originals.push_back(read(c));
    const auto v = validate(registry, c);
    ASSERT_EQ(v.outcome, Outcome::valid) << c << ": " << v.message;
  }

  for (int sig : {SIGSEGV, SIGABRT, SIGFPE, SIGBUS, SIGILL}) std::signal(sig, on_crash);
  // A hang in-process cannot be interrupted: a watchdog names the mutation and stops the test.
  std::atomic<bool> done{false};
  std::thread watchdog([&] {
    while (!done) {
      const double started = mutation_started;
      if (started > 0 && now_seconds() - started > 30.0) {
        on_crash(SIGALRM);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  });

  Mutator mutator(kSeed);
  std::map<std::string, int> outcomes, operators;
  std::vector<std::string> failures;
  double slowest = 0;
  int slowest_index = -1, binary_runs = 0;
  double binary_slowest = 0, in_process_total = 0, binary_total = 0;
  for (int m = 0; m < kMutations; ++m) {
    const std::size_t k = mutator.below(cases.size());
    std::string text = originals[k];
    const int count = 1 + int(mutator.below(10) >= 6) + int(mutator.below(10) >= 9);
    std::string ops;
    for (int n = 0; n < count; ++n) {
      const int op = int(mutator.below(kOperatorCount));
      if (op == 13) {  // mutate the file the case includes (a copy beside it) instead
        const auto at = text.find("\ninclude: ");
        if (at == std::string::npos) continue;
        const auto end = text.find_first_of(" \n", at + 10);
        const std::string name = text.substr(at + 10, end - at - 10);
        const fs::path included = cases[k].parent_path() / name;
        const fs::path copy = included.parent_path() / ("fuzz_" + included.filename().string());
        if (!fs::is_regular_file(included)) continue;
        fs::remove(copy);
        std::ofstream(copy, std::ios::binary)
            << mutator.apply(int(mutator.below(13)), read(included));
        text.replace(at + 10, end - at - 10,
                     (fs::path(name).parent_path() / copy.filename()).string());
      } else {
        text = mutator.apply(op, text);
      }
      ops += (ops.empty() ? "" : " + ") + std::string(kOperators[op]);
      ++operators[kOperators[op]];
    }
    const fs::path file = cases[k].parent_path() / ("fuzz_" + cases[k].filename().string());
    // a new file each time: ext4 writes back a file truncated and rewritten at close (3 ms each)
    fs::remove(file);
    std::ofstream(file, std::ios::binary) << text;
    current_mutation = m;
    std::snprintf(current_file, sizeof current_file, "%s", file.c_str());
    mutation_started = now_seconds();
    const Verdict v = validate(registry, file);
    mutation_started = 0;
    const std::string label =
        fmt::format("mutation {} of {} ({})", m, cases[k].filename().string(), ops);
    auto keep = [&](const std::string& why) {
      const fs::path kept = dir / fmt::format("failure_{}.yaml", m);
      fs::copy_file(file, kept, fs::copy_options::overwrite_existing);
      failures.push_back(fmt::format("{}: {} (input: {})", label, why, kept.string()));
    };
    outcomes[v.outcome == Outcome::valid        ? "valid"
             : v.outcome == Outcome::case_error ? "CaseError"
                                                : "other"]++;
    if (v.outcome == Outcome::other) keep("not a CaseError: " + v.message);
    if (v.outcome == Outcome::case_error && std::strchr(v.message.c_str(), '\n') != nullptr)
      keep("a CaseError of more than one line: " + v.message);
    if (v.seconds > kBound)
      keep(fmt::format("took {:.2f} s (bound {} s): {}", v.seconds, kBound, v.message));
    if (v.seconds > slowest) slowest = v.seconds, slowest_index = m;
    in_process_total += v.seconds;

    if (m % kBinaryEvery == 0) {
      // the real command, without a shell, bounded by coreutils' timeout
      const fs::path out = dir / "binary_output.txt";
      core::ProcessOptions options;
      options.output = out;
      const auto t0 = std::chrono::steady_clock::now();
      const auto r = core::run_process(
          {"timeout", "-s", "KILL", "20", granflow_binary, "check", file.string()}, options);
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      binary_slowest = std::max(binary_slowest, seconds);
      binary_total += seconds;
      ++binary_runs;
      const std::string said = read(out);
      const int expected = v.outcome == Outcome::valid ? 0 : 2;
      if (!r.started() || r.status != expected)
        keep(fmt::format("granflow check exited {} (in-process: {}): {}{}", r.status,
                         v.outcome == Outcome::valid ? "valid" : v.message, r.error, said));
      else if (r.status == 2 &&
               (said.rfind("error: ", 0) != 0 || std::count(said.begin(), said.end(), '\n') != 1))
        keep("granflow check did not print one error line: " + said);
      if (seconds > kBound)
        keep(fmt::format("granflow check took {:.2f} s (bound {} s)", seconds, kBound));
    }
  }
  done = true;
  watchdog.join();
  for (int sig : {SIGSEGV, SIGABRT, SIGFPE, SIGBUS, SIGILL}) std::signal(sig, SIG_DFL);

  const double total =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::string stats = fmt::format(
      "fuzz: {} mutations of {} case files (seed {}): {} valid, {} CaseError, {} other; "
      "in-process checks {:.1f} s, slowest {:.3f} s (mutation {}); {} through the binary "
      "{:.1f} s, slowest {:.2f} s; total {:.1f} s\nfuzz: operators:",
      kMutations, cases.size(), kSeed, outcomes["valid"], outcomes["CaseError"], outcomes["other"],
      in_process_total, slowest, slowest_index, binary_runs, binary_total, binary_slowest, total);
  for (const auto& [name, n] : operators) stats += fmt::format(" {} {},", name, n);
  std::cout << stats << "\n";
  RecordProperty("statistics", stats);
  EXPECT_TRUE(failures.empty()) << failures.size() << " failures, the first ones:\n"
                                <<
      [&] {
        std::string s;
        for (std::size_t i = 0; i < std::min<std::size_t>(failures.size(), 20); ++i)
          s += failures[i] + "\n";
        return s;
      }();
  // the mutations must reach both outcomes, or they test nothing
  EXPECT_GT(outcomes["valid"], kMutations / 20);
  EXPECT_GT(outcomes["CaseError"], kMutations / 2);
  EXPECT_LT(total, 120.0) << "the fuzz test is meant to take under two minutes";
  if (failures.empty()) fs::remove_all(dir);
}

// Inputs the fuzz found that ended in another exception than a CaseError (std::logic_error from a
// kind reading a required key of an absent section, YAML::BadConversion from a key that is a
// list), or that passed silently (a second YAML document was ignored): each is now one CaseError.
TEST(FuzzCheck, InputsTheFuzzFoundGiveOneCaseError) {
  const core::KindRegistry registry = app::make_registry();
  const fs::path dir =
      fs::temp_directory_path() / ("granflow_fuzz_found_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string dry = read(source / "cases/rev/simple_shear_dry.yaml");
  const std::vector<std::pair<std::string, std::string>> found = {
      // a truncated file: the material section (with required keys) is absent
      {"kind: rev\ntest: simple_shear\ndescription: dry\n",
       "truncated.yaml: material.diameter: missing required key (with its section material); "
       "expected number > 0 [m]"},
      {"kind: calibrate\nname: c\n",
       "truncated2.yaml: fit.parameters: missing required key (with its section fit)"},
      {dry + "[a]: 1\n", "complex_key.yaml:26: (top level): a key that is a list or a map"},
      {dry + "loading2:\n  ? [b]\n  : 3\n", "complex_key2.yaml:27: loading2: a key that is a list"},
      {dry + "---\nloading:\n  shear_rate: 1\n",
       "second_document.yaml:27: YAML syntax error: a second document (after ---)"},
      {"kind: [rev]\n", "kind_list.yaml:1: kind: expected a name"},
  };
  const char* const names[] = {"truncated.yaml",    "truncated2.yaml",      "complex_key.yaml",
                               "complex_key2.yaml", "second_document.yaml", "kind_list.yaml"};
  for (std::size_t i = 0; i < found.size(); ++i) {
    const fs::path file = dir / names[i];
    std::ofstream(file) << found[i].first;
    const Verdict v = validate(registry, file);
    EXPECT_EQ(v.outcome, Outcome::case_error) << names[i] << ": " << v.message;
    EXPECT_EQ(v.message.rfind((dir / found[i].second).string(), 0), 0)
        << names[i] << ": " << v.message;
  }
  fs::remove_all(dir);
}
