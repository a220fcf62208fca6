// A validated case: a YAML file (plus --set overrides) checked against the schema of its kind.
// Every error names file:line, the key path and what was expected, and is thrown as CaseError
// (the CLI turns it into one line on stderr and exit code 2, before anything runs).
// A case may start with `include: FILE` (or a list): parameter sections from another file, e.g.
// the calibrated.yaml a `kind: calibrate` run writes, merged before validation.
#pragma once

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/schema.hpp"

namespace granflow::core {

class CaseError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

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

  // Cross-field checks in a kind's validator: throw a CaseError located at `path`.
  [[noreturn]] void fail(std::string_view path, std::string_view expected) const;
  std::string location(std::string_view path) const;  // "file:line" (or "--set key=value")

  const std::string& name() const { return name_; }  // `name:` or the file stem
  const std::string& kind() const { return kind_; }
  const std::string& origin() const { return origin_; }
  const Schema& schema() const { return *schema_; }

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
  static void merge_includes(YAML::Node& raw, const std::string& origin,
                             std::vector<std::pair<std::string, std::string>>& locations);

  YAML::Node root_;     // validated tree with defaults filled in
  std::string origin_;  // file name for messages
  std::string name_, kind_;
  const Schema* schema_ = nullptr;
  std::vector<std::string> sweep_keys_;
  std::vector<std::vector<double>> sweep_values_;
  std::vector<std::pair<std::string, double>> condition_;
  // key path -> where it came from ("file:line" or "--set ...")
  std::vector<std::pair<std::string, std::string>> locations_;
};

// Peek `kind:` (and `test:` if present) without validating the rest; throws CaseError.
std::pair<std::string, std::string> peek_kind(const std::filesystem::path& file);

}  // namespace granflow::core
