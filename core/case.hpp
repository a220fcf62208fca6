// A validated case: a YAML file (plus --set overrides) checked against the schema of its kind.
// Every error names file:line, the key path and what was expected, and is thrown as CaseError
// (the CLI turns it into one line on stderr and exit code 2, before anything runs).
// A case may start with `include: FILE` (or a list): parameter sections from another file, e.g.
// the calibrated.yaml a `kind: calibrate` run writes, merged before validation.
#pragma once

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/schema.hpp"

namespace granflow::core {

struct Validator;

// One line whatever the input echoed in it: control characters and bytes that are not UTF-8
// are written as escapes (\n, \t, \xNN).
class CaseError : public std::runtime_error {
 public:
  explicit CaseError(const std::string& message);
};

// Input text to echo in a message: at most `max_chars` bytes (cut on a UTF-8 boundary, "..."
// marks the cut).
std::string shorten(std::string_view text, std::size_t max_chars = 80);

class Case {
 public:
  // Parse and validate. `overrides` are "key.path=value" strings (--set); `schema` is the schema
  // of the case's kind. Throws CaseError.
  static Case load(const std::filesystem::path& file, const std::vector<std::string>& overrides,
                   const Schema& schema);
  // Same from YAML text (tests; `origin` plays the role of the file name).
  static Case parse(const std::string& yaml_text, const std::string& origin,
                    const std::vector<std::string>& overrides, const Schema& schema);

  // Typed access to validated values (defaults filled in). The path must exist in the schema;
  // asking for an unknown path is a programming error (std::logic_error).
  double number(std::string_view path) const;
  long integer(std::string_view path) const;
  bool boolean(std::string_view path) const;
  std::string string(std::string_view path) const;  // also for choices
  std::vector<double> number_list(std::string_view path) const;
  bool has(std::string_view path) const;  // given in the file/overrides or has a default
  // The node at `path` (a swept value of this condition first); undefined when absent.
  YAML::Node value_node(std::string_view path) const;

  // Cross-field checks in a kind's validator: throw a CaseError located at `path`.
  [[noreturn]] void fail(std::string_view path, std::string_view expected) const;
  std::string location(std::string_view path) const;  // "file:line" (or "--set key=value")

  const std::string& name() const { return name_; }  // `name:` or the file stem
  const std::string& kind() const { return kind_; }
  const std::string& origin() const { return origin_; }
  const Schema& schema() const { return *schema_; }
  // A size bound of limits_section() (e.g. "max_steps"): the case's `limits.NAME` or its default.
  double limit(std::string_view name) const;

  // The resolved case (defaults filled, overrides applied, no sweep) for the run's case.yaml.
  std::string resolved_yaml() const;

  // A case with `sweep:` expands into one case per condition (Cartesian product of the listed
  // key paths, first key varying slowest). A case without sweep returns itself (one entry).
  bool is_sweep() const { return !sweep_keys_.empty(); }
  std::vector<Case> expand_sweep() const;
  const std::vector<std::string>& sweep_keys() const { return sweep_keys_; }
  // Values of the swept keys for this expanded condition (empty if not from a sweep).
  const std::vector<std::pair<std::string, double>>& condition() const { return condition_; }

 private:
  Case() = default;
  void read_sweep(const YAML::Node& raw, const Validator& validator);

  YAML::Node root_;     // validated tree with defaults filled in (shared by the conditions)
  std::string origin_;  // file name for messages
  std::string name_, kind_;
  const Schema* schema_ = nullptr;
  std::vector<std::string> sweep_keys_;
  std::vector<std::vector<double>> sweep_values_;
  std::vector<std::pair<std::string, double>> condition_;
  // key path -> where it came from ("file:line" or "--set ..."); shared by the conditions
  std::shared_ptr<std::vector<std::pair<std::string, std::string>>> locations_ =
      std::make_shared<std::vector<std::pair<std::string, std::string>>>();
  std::map<std::string, double, std::less<>> limits_;  // limits_section() values of this case
};

// Peek `kind:` (and `test:` if present) without validating the rest; throws CaseError.
std::pair<std::string, std::string> peek_kind(const std::filesystem::path& file);

}  // namespace granflow::core
