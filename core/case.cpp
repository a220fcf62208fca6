#include "core/case.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <system_error>

#include "core/case_file_text.hpp"

namespace granflow::core {

namespace {

std::string join(const std::string& prefix, const std::string& key) {
  return prefix.empty() ? key : prefix + "." + key;
}

// Levenshtein distance, for "did you mean" on misspelled keys.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

const Field* schema_field(const Schema& schema, std::string_view path) {
  const Field* field = &schema;
  for (const auto& part : split_key_path(path)) {
    if (field->type() != ValueType::section) return nullptr;
    field = field->child(part);
    if (!field) return nullptr;
  }
  return field;
}

bool parse_number(const YAML::Node& node, double& value) {
  if (!node.IsScalar()) return false;
  try {
    value = node.as<double>();
  } catch (const YAML::Exception&) {
    return false;
  }
  return std::isfinite(value);
}

using Limits = std::map<std::string, double, std::less<>>;

// Why `value` (written `text`) is above the field's limits.<name> ("" when it is not).
std::string limit_problem(const Field& field, double value, const std::string& text,
                          const Limits& limits) {
  if (field.limit_name().empty() || value <= limits.at(field.limit_name())) return "";
  return fmt::format(
      "value {} is above limits.{} = {:g}; expected {} (raise limits.{} in the case, or with "
      "--set limits.{}=N, to run it on purpose)",
      text, field.limit_name(), limits.at(field.limit_name()), field.expectation(),
      field.limit_name(), field.limit_name());
}

bool subnormal(double value) {
  return value != 0 && std::abs(value) < std::numeric_limits<double>::min();
}

// Why a finite `value` is refused for a number field ("" when accepted).
std::string number_problem(const Field& field, double value, const std::string& text,
                           const Limits& limits) {
  if (subnormal(value))
    return fmt::format(
        "value {} is below 2.2e-308, the smallest normal double, and underflows in arithmetic; "
        "expected {}",
        text, field.expectation());
  if (!field.within_bounds(value))
    return fmt::format("value {} is outside the physical range; expected {}", text,
                       field.expectation());
  return limit_problem(field, value, text, limits);
}

}  // namespace

// ------------------------------------------------------------------------------------------
struct Validator {
  const std::string& origin;
  const std::vector<std::pair<std::string, std::string>>& override_locations;
  std::vector<std::pair<std::string, std::string>>& locations;
  const Limits& limits;

  std::string where(const std::string& path, const YAML::Node& node) const {
    return locate(origin, override_locations, path, node);
  }

  [[noreturn]] void fail(const std::string& path, const YAML::Node& node,
                         const std::string& problem) const {
    throw CaseError(
        fmt::format("{}: {}: {}", where(path, node), path.empty() ? "(top level)" : path, problem));
  }

  YAML::Node check(const Field& field, const YAML::Node& node, const std::string& path) {
    locations.emplace_back(path, where(path, node));
    const std::string expected = "expected " + field.expectation();
    switch (field.type()) {
      case ValueType::section: {
        if (!node.IsMap()) fail(path, node, "expected a section (a map of keys)");
        YAML::Node out(YAML::NodeType::Map);
        for (const auto& item : node) {
          const auto key = item.first.as<std::string>();
          const Field* child = field.child(key);
          const std::string child_path = join(path, key);
          if (!child) {
            const std::string shown = join(path, shorten(key));  // any text can be a key
            std::string names, best;
            std::size_t best_distance = 4;  // suggest only close matches
            for (const auto& c : field.children()) {
              names += (names.empty() ? "" : ", ") + c.key();
              const auto d = edit_distance(key, c.key());
              if (d < best_distance) best_distance = d, best = c.key();
            }
            fail(shown, item.first,
                 fmt::format("unknown key; expected one of: {}{}", names,
                             best.empty() ? "" : fmt::format(" (did you mean '{}'?)", best)));
          }
          out[key] = check(*child, item.second, child_path);
        }
        for (const auto& c : field.children()) {
          if (out[c.key()].IsDefined()) continue;
          const std::string child_path = join(path, c.key());
          if (c.is_required())
            fail(child_path, node,
                 "missing required key; expected " + c.expectation() +
                     (c.doc().empty() ? "" : " (" + c.doc() + ")"));
          if (c.default_text()) {
            out[c.key()] = check(c, YAML::Load(*c.default_text()), child_path);
          } else if (c.type() == ValueType::section) {
            // An absent optional section is filled from its children's defaults if it has any
            // required child it stays absent (the kind decides whether it is needed).
            bool any_required = false;
            for (const auto& g : c.children()) any_required |= g.is_required();
            if (!any_required) out[c.key()] = check(c, YAML::Node(YAML::NodeType::Map), child_path);
          }
        }
        return out;
      }
      case ValueType::number: {
        double value = 0;
        if (!parse_number(node, value)) fail(path, node, "not a number; " + expected);
        if (const auto problem = number_problem(field, value, shorten(node.Scalar()), limits);
            !problem.empty())
          fail(path, node, problem);
        return YAML::Node(value);
      }
      case ValueType::integer: {
        // read exactly (schema.hpp): 1e20 or 3.5 are refused, never wrapped or truncated
        long long value = 0;
        const auto status = node.IsScalar() ? field.parse_integer(node.as<std::string>(), value)
                                            : Field::IntegerStatus::not_integer;
        if (status == Field::IntegerStatus::not_integer)
          fail(path, node, "not an integer; " + expected);
        // beyond its limit (also when beyond an int): the limit is the bound to name
        double approximate = 0;
        if (status != Field::IntegerStatus::ok && parse_number(node, approximate))
          if (const auto problem =
                  limit_problem(field, approximate, shorten(node.Scalar()), limits);
              !problem.empty())
            fail(path, node, problem);
        if (status == Field::IntegerStatus::out_of_range)
          fail(path, node,
               fmt::format("value {} is out of range; {}{}", shorten(node.Scalar()), expected,
                           field.integer_limit_note()));
        if (status == Field::IntegerStatus::inexact)
          fail(path, node,
               fmt::format("value {} in floating-point notation is beyond 2^53 and may not be "
                           "exact; expected the {} written in digits",
                           shorten(node.Scalar()), field.expectation()));
        if (const auto problem =
                limit_problem(field, double(value), shorten(node.Scalar()), limits);
            !problem.empty())
          fail(path, node, problem);
        return YAML::Node(value);
      }
      case ValueType::boolean: {
        bool value = false;
        if (!node.IsScalar() || !YAML::convert<bool>::decode(node, value))
          fail(path, node, "not a boolean; expected true or false");
        return YAML::Node(value);
      }
      case ValueType::string: {
        if (!node.IsScalar()) fail(path, node, "expected a string");
        return YAML::Node(node.as<std::string>());
      }
      case ValueType::choice: {
        if (!node.IsScalar()) fail(path, node, expected);
        const auto value = node.as<std::string>();
        const auto& names = field.choice_names();
        if (std::find(names.begin(), names.end(), value) == names.end())
          fail(path, node, fmt::format("unknown name '{}'; {}", shorten(value), expected));
        return YAML::Node(value);
      }
      case ValueType::number_list: {
        if (!node.IsSequence() || node.size() == 0)
          fail(path, node, "expected a non-empty list of numbers, e.g. [1, 2, 3]");
        YAML::Node out(YAML::NodeType::Sequence);
        for (std::size_t i = 0; i < node.size(); ++i) {
          double value = 0;
          if (!parse_number(node[i], value) || !field.within_bounds(value))
            fail(fmt::format("{}[{}]", path, i), node[i], "expected " + field.expectation());
          out.push_back(value);
        }
        return out;
      }
    }
    fail(path, node, "unsupported schema type");
  }
};

Case Case::load(const std::filesystem::path& file, const std::vector<std::string>& overrides,
                const Schema& schema) {
  Case c = parse(read_case_file(file), file.string(), overrides, schema);
  if (!c.root_["name"].IsDefined() || c.root_["name"].as<std::string>().empty()) {
    c.name_ = file.stem().string();
    c.root_["name"] = c.name_;
  }
  return c;
}

Case Case::parse(const std::string& yaml_text, const std::string& origin,
                 const std::vector<std::string>& overrides, const Schema& schema) {
  YAML::Node raw = load_case_yaml(yaml_text, origin);
  if (!raw.IsMap())
    throw CaseError(fmt::format("{}:1: (top level): expected a map of keys", origin));

  // --set key.path=value: same validation as the file. Keys merged from `include:` files are
  // located in their own file through the same list (exact leaf paths).
  std::vector<std::pair<std::string, std::string>> override_locations;
  merge_includes(raw, origin, override_locations);  // case_file_text.hpp
  for (const auto& item : overrides) apply_override(raw, item, origin, schema, override_locations);

  Case c;
  c.origin_ = origin;
  c.schema_ = &schema;
  Validator validator{origin, override_locations, *c.locations_, c.limits_};

  // limits: (limits_section) first: the sweep and the keys below are checked against them.
  const bool limits_given = raw["limits"].IsDefined();
  const YAML::Node limits = validator.check(
      limits_section(), limits_given ? raw["limits"] : YAML::Node(YAML::NodeType::Map), "limits");
  raw.remove("limits");
  for (const auto& field : limits_section().children())
    c.limits_[field.key()] = limits[field.key()].IsDefined()
                                 ? limits[field.key()].as<double>()
                                 : static_cast<double>(default_max_ranks());  // max_ranks

  c.read_sweep(raw, validator);
  raw.remove("sweep");

  c.root_ = validator.check(schema, raw, "");
  if (limits_given) c.root_["limits"] = limits;  // in case.yaml only when the case set them
  c.kind_ = c.root_["kind"].IsDefined() ? c.root_["kind"].as<std::string>() : "";
  c.name_ = c.root_["name"].IsDefined() ? c.root_["name"].as<std::string>() : "";
  // `name:` is the run directory runs/<name>/ and appears in files granflow writes: a plain file
  // name only.
  constexpr const char* plain_name =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789._-";
  if (!c.name_.empty() && (c.name_ == "." || c.name_ == ".." ||
                           c.name_.find_first_not_of(plain_name) != std::string::npos))
    c.fail("name",
           "expected a plain file name ([A-Za-z0-9._-]+, not . or ..); it names the run "
           "directory runs/<name>/");
  return c;
}

// sweep: { key.path: [values...] }, each key a sweepable number or integer of the schema, each
// list of distinct values within the key's bounds, and at most limits.max_conditions conditions
// in all: refused here, before expand_sweep builds one case per condition.
void Case::read_sweep(const YAML::Node& raw, const Validator& validator) {
  const YAML::Node sweep = raw["sweep"];
  if (!sweep.IsDefined()) return;
  if (!sweep.IsMap())
    throw CaseError(fmt::format("{}: sweep: expected a map of key.path: [values]",
                                validator.where("sweep", sweep)));
  double conditions = 1;
  std::string sizes, largest_at;
  std::size_t largest = 0;
  for (const auto& item : sweep) {
    const auto key = item.first.as<std::string>();
    const Field* field = schema_field(*schema_, key);
    const std::string at = validator.where("sweep." + key, item.first);
    const bool numeric =
        field && (field->type() == ValueType::number || field->type() == ValueType::integer);
    if (!numeric || !field->is_sweepable()) {
      std::string sweepable;
      std::function<void(const Field&, const std::string&)> collect = [&](const Field& f,
                                                                          const std::string& p) {
        for (const auto& ch : f.children()) {
          if (ch.type() == ValueType::section)
            collect(ch, join(p, ch.key()));
          else if (ch.is_sweepable())
            sweepable += (sweepable.empty() ? "" : ", ") + join(p, ch.key());
        }
      };
      collect(*schema_, "");
      throw CaseError(fmt::format("{}: sweep.{}: not a sweepable key; expected one of: {}", at,
                                  shorten(key), sweepable.empty() ? "(none)" : sweepable));
    }
    if (!item.second.IsSequence() || item.second.size() == 0)
      throw CaseError(fmt::format("{}: sweep.{}: expected a non-empty list of numbers", at, key));
    std::vector<double> values;
    std::map<double, std::size_t> seen;  // value -> its first index
    for (std::size_t i = 0; i < item.second.size(); ++i) {
      const YAML::Node entry = item.second[i];
      const std::string entry_at = validator.where("sweep." + key, entry);
      double v = 0;
      std::string problem;
      if (field->type() == ValueType::integer) {
        // integer keys (e.g. dem.seed) take whole numbers within range only, read exactly
        long long n = 0;
        const auto status = entry.IsScalar() ? field->parse_integer(entry.as<std::string>(), n)
                                             : Field::IntegerStatus::not_integer;
        if (status != Field::IntegerStatus::ok)
          problem = "expected " + field->expectation() +
                    (status == Field::IntegerStatus::out_of_range ? field->integer_limit_note()
                     : status == Field::IntegerStatus::inexact    ? " written in digits"
                                                                  : "");
        v = static_cast<double>(n);
      } else if (!parse_number(entry, v) || !(field->within_bounds(v) || subnormal(v))) {
        problem = "expected " + field->expectation();
      }
      if (problem.empty()) problem = number_problem(*field, v, entry.as<std::string>(), limits_);
      if (!problem.empty())
        throw CaseError(fmt::format("{}: sweep.{}[{}]: {}", entry_at, key, i, problem));
      if (const auto [it, fresh] = seen.emplace(v, i); !fresh)
        throw CaseError(fmt::format(
            "{}: sweep.{}[{}]: value {:g} is listed twice (also [{}]); expected distinct values "
            "(a repeated condition runs the same point again)",
            entry_at, key, i, v, it->second));
      values.push_back(v);
    }
    conditions *= double(values.size());
    sizes += fmt::format("{}{} values of {}", sizes.empty() ? "" : " x ", values.size(), key);
    if (values.size() > largest) largest = values.size(), largest_at = at;
    sweep_keys_.push_back(key);
    sweep_values_.push_back(std::move(values));
  }
  if (conditions > limits_.at("max_conditions"))
    throw CaseError(fmt::format(
        "{}: sweep: {} = {:.15g} conditions; expected at most limits.max_conditions = {:g} (raise "
        "limits.max_conditions in the case, or with --set limits.max_conditions=N, to run them "
        "on purpose)",
        largest_at, sizes, conditions, limits_.at("max_conditions")));
}

static YAML::Node lookup(const YAML::Node& root, std::string_view path) {
  YAML::Node node = root;  // yaml-cpp nodes are handles; reassigning a copy is safe for reading
  for (const auto& part : split_key_path(path)) {
    if (!node.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    const YAML::Node& map = node;  // const access: a missing key adds no pending entry
    const YAML::Node next = map[part];
    if (!next.IsDefined()) return YAML::Node(YAML::NodeType::Undefined);
    node.reset(next);
  }
  return node;
}

// A swept value as a node: whole numbers as integers (integer keys read back as such).
static YAML::Node condition_node(double value) {
  if (value == std::floor(value) && std::abs(value) < 9.0e15)
    return YAML::Node(static_cast<long long>(value));
  return YAML::Node(value);
}

YAML::Node Case::value_node(std::string_view path) const {
  for (const auto& [key, value] : condition_)
    if (key == path) return condition_node(value);
  return lookup(root_, path);
}

static YAML::Node required_value(const Case& c, std::string_view path, ValueType type) {
  const Field* field = schema_field(c.schema(), path);
  if (!field) throw std::logic_error(fmt::format("case: '{}' is not in the schema", path));
  if (field->type() != type && !(type == ValueType::string && field->type() == ValueType::choice))
    throw std::logic_error(fmt::format("case: '{}' is a {}, not a {}", path,
                                       to_string(field->type()), to_string(type)));
  YAML::Node node = c.value_node(path);
  // A required key is absent only with its section (an optional section with required keys
  // stays absent, the kind decides whether it needs it): the kind needs it, so the case is
  // missing it.
  if (!node.IsDefined() && field->is_required()) {
    const auto dot = path.rfind('.');
    c.fail(path, fmt::format("missing required key{}; expected {}{}",
                             dot == std::string_view::npos
                                 ? ""
                                 : fmt::format(" (with its section {})", path.substr(0, dot)),
                             field->expectation(),
                             field->doc().empty() ? "" : " (" + field->doc() + ")"));
  }
  if (!node.IsDefined())
    throw std::logic_error(
        fmt::format("case: '{}' is optional and not given; check has() first", path));
  return node;
}

double Case::number(std::string_view path) const {
  return required_value(*this, path, ValueType::number).as<double>();
}
long Case::integer(std::string_view path) const {
  return required_value(*this, path, ValueType::integer).as<long>();
}
bool Case::boolean(std::string_view path) const {
  return required_value(*this, path, ValueType::boolean).as<bool>();
}
std::string Case::string(std::string_view path) const {
  return required_value(*this, path, ValueType::string).as<std::string>();
}
std::vector<double> Case::number_list(std::string_view path) const {
  return required_value(*this, path, ValueType::number_list).as<std::vector<double>>();
}
bool Case::has(std::string_view path) const { return value_node(path).IsDefined(); }

double Case::limit(std::string_view name) const {
  const auto it = limits_.find(name);
  if (it == limits_.end())
    throw std::logic_error(fmt::format("case: limits.{} is not a size limit", name));
  return it->second;
}

std::string Case::location(std::string_view path) const {
  // Swept keys point at the sweep entry.
  for (const auto& [key, value] : condition_)
    if (key == path) return fmt::format("{} (sweep {}={})", origin_, key, value);
  for (auto it = locations_->rbegin(); it != locations_->rend(); ++it)
    if (it->first == path) return it->second;
  return origin_;
}

void Case::fail(std::string_view path, std::string_view expected) const {
  throw CaseError(fmt::format("{}: {}: {}", location(path), path, expected));
}

std::string Case::resolved_yaml() const {
  YAML::Emitter out;
  if (condition_.empty()) {
    out << root_;
  } else {  // a condition of a sweep: its values written into a copy of the tree
    YAML::Node root = YAML::Clone(root_);
    for (const auto& [key, value] : condition_) {
      const auto parts = split_key_path(key);
      YAML::Node node = root;
      for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
        if (!node[parts[i]].IsDefined()) node[parts[i]] = YAML::Node(YAML::NodeType::Map);
        node.reset(node[parts[i]]);
      }
      node[parts.back()] = condition_node(value);
    }
    out << root;
  }
  std::string text = out.c_str();
  if (!condition_.empty()) {
    text += "\n# sweep condition:";
    for (const auto& [k, v] : condition_) text += fmt::format(" {}={:g}", k, v);
    text += "\n";
  } else if (!sweep_keys_.empty()) {
    text += "\nsweep:\n";
    for (std::size_t i = 0; i < sweep_keys_.size(); ++i) {
      text += "  " + sweep_keys_[i] + ": [";
      for (std::size_t j = 0; j < sweep_values_[i].size(); ++j)
        text += fmt::format("{}{:g}", j ? ", " : "", sweep_values_[i][j]);
      text += "]\n";
    }
  }
  return text + "\n";
}

std::vector<Case> Case::expand_sweep() const {
  if (sweep_keys_.empty()) return {*this};
  // The conditions share this case's tree and locations (both read-only from here on): a
  // condition holds only its swept values, read first by the accessors (value_node).
  Case base = *this;
  base.sweep_keys_.clear();
  base.sweep_values_.clear();
  std::vector<Case> out;
  std::vector<std::size_t> index(sweep_keys_.size(), 0);
  while (true) {
    Case c = base;
    for (std::size_t k = 0; k < sweep_keys_.size(); ++k)
      c.condition_.emplace_back(sweep_keys_[k], sweep_values_[k][index[k]]);
    out.push_back(std::move(c));
    // odometer: the last key varies fastest
    std::size_t k = sweep_keys_.size();
    while (k > 0) {
      --k;
      if (++index[k] < sweep_values_[k].size()) break;
      index[k] = 0;
      if (k == 0) return out;
    }
  }
}

}  // namespace granflow::core
