#include "core/case.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <sstream>
#include <system_error>

#include "core/case_file_text.hpp"

namespace granflow::core {
namespace {

std::vector<std::string> split_path(std::string_view path) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (start <= path.size()) {
    const auto dot = path.find('.', start);
    const auto end = dot == std::string_view::npos ? path.size() : dot;
    parts.emplace_back(path.substr(start, end - start));
    if (dot == std::string_view::npos) break;
    start = dot + 1;
  }
  return parts;
}

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
  for (const auto& part : split_path(path)) {
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

}  // namespace

// ------------------------------------------------------------------------------------------
struct Validator {
  const std::string& origin;
  const std::vector<std::pair<std::string, std::string>>& override_locations;
  std::vector<std::pair<std::string, std::string>>& locations;

  std::string where(const std::string& path, const YAML::Node& node) const {
    // the last entry wins: --set is recorded after the included files' keys
    for (auto it = override_locations.rbegin(); it != override_locations.rend(); ++it)
      if (it->first == path || path.rfind(it->first + ".", 0) == 0) return it->second;
    if (node.IsDefined() && node.Mark().line >= 0)
      return fmt::format("{}:{}", origin, node.Mark().line + 1);
    return origin;
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
            std::string names, best;
            std::size_t best_distance = 4;  // suggest only close matches
            for (const auto& c : field.children()) {
              names += (names.empty() ? "" : ", ") + c.key();
              const auto d = edit_distance(key, c.key());
              if (d < best_distance) best_distance = d, best = c.key();
            }
            fail(child_path, item.first,
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
        if (!field.within_bounds(value))
          fail(path, node,
               fmt::format("value {} is outside the physical range; {}", node.as<std::string>(),
                           expected));
        return YAML::Node(value);
      }
      case ValueType::integer: {
        // read exactly (schema.hpp): 1e20 or 3.5 are refused, never wrapped or truncated
        long long value = 0;
        const auto status = node.IsScalar() ? field.parse_integer(node.as<std::string>(), value)
                                            : Field::IntegerStatus::not_integer;
        if (status == Field::IntegerStatus::not_integer)
          fail(path, node, "not an integer; " + expected);
        if (status == Field::IntegerStatus::out_of_range)
          fail(path, node,
               fmt::format("value {} is out of range; {}{}", node.as<std::string>(), expected,
                           field.integer_limit_note()));
        if (status == Field::IntegerStatus::inexact)
          fail(path, node,
               fmt::format("value {} in floating-point notation is beyond 2^53 and may not be "
                           "exact; expected the {} written in digits",
                           node.as<std::string>(), field.expectation()));
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
          fail(path, node, fmt::format("unknown name '{}'; {}", value, expected));
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

// ------------------------------------------------------------------------------------------
// `include: FILE` (or a list of files), relative to the including file: their sections are merged
// into the case before validation, so a calibrated parameter file (kind: calibrate writes one)
// can be used by rev and mpm cases directly. A key given in both files is an error naming both
// places (no silent precedence); --set still overrides everything. Included files may not
// include further files.
namespace {

void merge_node(YAML::Node target, const YAML::Node& source, const std::string& path,
                const std::string& file, const std::string& origin,
                std::vector<std::pair<std::string, std::string>>& locations) {
  for (const auto& item : source) {
    const auto key = item.first.as<std::string>();
    const std::string child_path = join(path, key);
    const std::string where = fmt::format("{}:{}", file, item.first.Mark().line + 1);
    YAML::Node existing = target[key];
    if (existing.IsDefined() && existing.IsMap() && item.second.IsMap()) {
      merge_node(existing, item.second, child_path, file, origin, locations);
      continue;
    }
    if (existing.IsDefined())
      throw CaseError(
          fmt::format("{}: {}: given both here and in {}:{}; expected it in one file only", where,
                      child_path, origin, existing.Mark().line + 1));
    target[key] = item.second;
    std::function<void(const YAML::Node&, const std::string&)> record = [&](const YAML::Node& n,
                                                                            const std::string& p) {
      if (n.IsMap()) {
        for (const auto& sub : n) record(sub.second, join(p, sub.first.as<std::string>()));
      } else {
        locations.emplace_back(p, fmt::format("{}:{}", file, n.Mark().line + 1));
      }
    };
    record(item.second, child_path);
  }
}

}  // namespace

void Case::merge_includes(YAML::Node& raw, const std::string& origin,
                          std::vector<std::pair<std::string, std::string>>& locations) {
  const YAML::Node include = raw["include"];
  if (!include.IsDefined()) return;
  const std::string at = fmt::format("{}:{}", origin, include.Mark().line + 1);
  std::vector<std::string> files;
  if (include.IsScalar()) {
    files.push_back(include.as<std::string>());
  } else if (include.IsSequence()) {
    for (const auto& f : include) {
      if (!f.IsScalar())
        throw CaseError(at + ": include: expected a file name or a list of file names");
      files.push_back(f.as<std::string>());
    }
  } else {
    throw CaseError(at + ": include: expected a file name or a list of file names");
  }
  raw.remove("include");
  const std::filesystem::path base = std::filesystem::path(origin).parent_path();
  for (const auto& name : files) {
    const std::filesystem::path file =
        std::filesystem::path(name).is_absolute() ? std::filesystem::path(name) : base / name;
    std::string text;
    switch (read_regular_file(file, text)) {
      case ReadStatus::ok:
        break;
      case ReadStatus::cannot_open:
        throw CaseError(fmt::format("{}: include: cannot open '{}'", at, file.string()));
      case ReadStatus::not_regular:
        throw CaseError(fmt::format("{}: not a regular file (included at {})", file.string(), at));
    }
    YAML::Node included;
    try {
      refuse_duplicate_keys(text, file.string());  // located in the included file
      included = YAML::Load(text);
    } catch (const YAML::ParserException& e) {
      throw CaseError(
          fmt::format("{}:{}: YAML syntax error: {}", file.string(), e.mark.line + 1, e.msg));
    }
    if (!included.IsMap())
      throw CaseError(
          fmt::format("{}:1: (top level): expected a map of case sections", file.string()));
    if (included["include"].IsDefined())
      throw CaseError(fmt::format("{}:{}: include: an included file may not include further files",
                                  file.string(), included["include"].Mark().line + 1));
    for (const char* header : {"kind", "test", "name"})
      if (included[header].IsDefined())
        throw CaseError(
            fmt::format("{}:{}: {}: not allowed in an included file; expected only "
                        "parameter sections",
                        file.string(), included[header].Mark().line + 1, header));
    merge_node(raw, included, "", file.string(), origin, locations);
  }
}

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
  YAML::Node raw;
  try {
    refuse_duplicate_keys(yaml_text, origin);
    raw = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    throw CaseError(fmt::format("{}:{}: YAML syntax error: {}", origin, e.mark.line + 1, e.msg));
  }
  if (!raw.IsMap())
    throw CaseError(fmt::format("{}:1: (top level): expected a map of keys", origin));

  // --set key.path=value: same validation as the file. Keys merged from `include:` files are
  // located in their own file through the same list (exact leaf paths).
  std::vector<std::pair<std::string, std::string>> override_locations;
  merge_includes(raw, origin, override_locations);
  for (const auto& item : overrides) {
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0)
      throw CaseError(fmt::format("--set {}: expected key.path=value", item));
    const std::string path = item.substr(0, eq);
    YAML::Node value;
    try {
      // a map value given on the command line follows the same rule as the file
      if (const auto dup = find_duplicate_key(item.substr(eq + 1), path))
        throw CaseError(
            fmt::format("--set {}: {}: given twice; expected each key once", item, dup->path));
      value = YAML::Load(item.substr(eq + 1));
    } catch (const YAML::Exception& e) {
      throw CaseError(fmt::format("--set {}: the value is not valid YAML: {}", item, e.what()));
    }
    // sweep.<key.path>=[...]: the rest of the path is one sweep key (flat, as in the file)
    if (path.rfind("sweep.", 0) == 0 && path.size() > 6) {
      if (!raw["sweep"].IsDefined() || raw["sweep"].IsNull())
        raw["sweep"] = YAML::Node(YAML::NodeType::Map);
      raw["sweep"][path.substr(6)] = value;
      override_locations.emplace_back(path, "--set " + item);
      continue;
    }
    const auto parts = split_path(path);
    std::vector<YAML::Node> chain{raw};
    for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
      YAML::Node next = chain.back()[parts[i]];
      if (!next.IsDefined() || next.IsNull()) {
        chain.back()[parts[i]] = YAML::Node(YAML::NodeType::Map);
        next = chain.back()[parts[i]];
      }
      chain.push_back(next);
    }
    chain.back()[parts.back()] = value;
    override_locations.emplace_back(path, "--set " + item);
  }

  Case c;
  c.origin_ = origin;
  c.schema_ = &schema;

  // sweep: { key.path: [values...] }, validated against the schema field of each path.
  YAML::Node sweep = raw["sweep"];
  if (sweep.IsDefined()) {
    const int line = sweep.Mark().line + 1;
    if (!sweep.IsMap())
      throw CaseError(
          fmt::format("{}:{}: sweep: expected a map of key.path: [values]", origin, line));
    for (const auto& item : sweep) {
      const auto key = item.first.as<std::string>();
      const Field* field = schema_field(schema, key);
      // Mark line is -1 when the key came from --set.
      const std::string at = item.first.Mark().line >= 0
                                 ? fmt::format("{}:{}", origin, item.first.Mark().line + 1)
                                 : "--set sweep." + key;
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
        collect(schema, "");
        throw CaseError(fmt::format("{}: sweep.{}: not a sweepable key; expected one of: {}", at,
                                    key, sweepable.empty() ? "(none)" : sweepable));
      }
      if (!item.second.IsSequence() || item.second.size() == 0)
        throw CaseError(fmt::format("{}: sweep.{}: expected a non-empty list of numbers", at, key));
      std::vector<double> values;
      for (std::size_t i = 0; i < item.second.size(); ++i) {
        const YAML::Node entry = item.second[i];
        double v = 0;
        bool ok = false;
        std::string note;
        if (field->type() == ValueType::integer) {
          // integer keys (e.g. dem.seed) take whole numbers within range only, read exactly
          long long n = 0;
          const auto status = entry.IsScalar() ? field->parse_integer(entry.as<std::string>(), n)
                                               : Field::IntegerStatus::not_integer;
          ok = status == Field::IntegerStatus::ok;
          if (status == Field::IntegerStatus::out_of_range) note = field->integer_limit_note();
          if (status == Field::IntegerStatus::inexact) note = " written in digits";
          v = static_cast<double>(n);
        } else {
          ok = parse_number(entry, v) && field->within_bounds(v);
        }
        if (!ok)
          throw CaseError(fmt::format("{}:{}: sweep.{}[{}]: expected {}{}", origin,
                                      entry.Mark().line + 1, key, i, field->expectation(), note));
        values.push_back(v);
      }
      c.sweep_keys_.push_back(key);
      c.sweep_values_.push_back(std::move(values));
    }
    raw.remove("sweep");
  }

  Validator validator{origin, override_locations, c.locations_};
  c.root_ = validator.check(schema, raw, "");
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

static YAML::Node lookup(const YAML::Node& root, std::string_view path) {
  YAML::Node node = root;  // yaml-cpp nodes are handles; reassigning a copy is safe for reading
  for (const auto& part : split_path(path)) {
    if (!node.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    YAML::Node next = node[part];
    if (!next.IsDefined()) return YAML::Node(YAML::NodeType::Undefined);
    node.reset(next);
  }
  return node;
}

static YAML::Node required_value(const Case& c, const YAML::Node& root, std::string_view path,
                                 ValueType type) {
  const Field* field = schema_field(c.schema(), path);
  if (!field) throw std::logic_error(fmt::format("case: '{}' is not in the schema", path));
  if (field->type() != type && !(type == ValueType::string && field->type() == ValueType::choice))
    throw std::logic_error(fmt::format("case: '{}' is a {}, not a {}", path,
                                       to_string(field->type()), to_string(type)));
  YAML::Node node = lookup(root, path);
  if (!node.IsDefined())
    throw std::logic_error(
        fmt::format("case: '{}' is optional and not given; check has() first", path));
  return node;
}

double Case::number(std::string_view path) const {
  return required_value(*this, root_, path, ValueType::number).as<double>();
}
long Case::integer(std::string_view path) const {
  return required_value(*this, root_, path, ValueType::integer).as<long>();
}
bool Case::boolean(std::string_view path) const {
  return required_value(*this, root_, path, ValueType::boolean).as<bool>();
}
std::string Case::string(std::string_view path) const {
  return required_value(*this, root_, path, ValueType::string).as<std::string>();
}
std::vector<double> Case::number_list(std::string_view path) const {
  return required_value(*this, root_, path, ValueType::number_list).as<std::vector<double>>();
}
bool Case::has(std::string_view path) const { return lookup(root_, path).IsDefined(); }

std::string Case::location(std::string_view path) const {
  // Swept keys point at the sweep entry.
  for (const auto& [key, value] : condition_)
    if (key == path) return fmt::format("{} (sweep {}={})", origin_, key, value);
  for (auto it = locations_.rbegin(); it != locations_.rend(); ++it)
    if (it->first == path) return it->second;
  return origin_;
}

void Case::fail(std::string_view path, std::string_view expected) const {
  throw CaseError(fmt::format("{}: {}: {}", location(path), path, expected));
}

std::string Case::resolved_yaml() const {
  YAML::Emitter out;
  out << root_;
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
  std::vector<Case> out;
  std::vector<std::size_t> index(sweep_keys_.size(), 0);
  while (true) {
    Case c = *this;
    c.root_ = YAML::Clone(root_);
    c.sweep_keys_.clear();
    c.sweep_values_.clear();
    for (std::size_t k = 0; k < sweep_keys_.size(); ++k) {
      const double value = sweep_values_[k][index[k]];
      const auto parts = split_path(sweep_keys_[k]);
      YAML::Node node = c.root_;
      for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
        if (!node[parts[i]].IsDefined()) node[parts[i]] = YAML::Node(YAML::NodeType::Map);
        node.reset(node[parts[i]]);
      }
      if (value == std::floor(value) && std::abs(value) < 9.0e15)
        node[parts.back()] = static_cast<long long>(value);  // integer keys read back as such
      else
        node[parts.back()] = value;
      c.condition_.emplace_back(sweep_keys_[k], value);
    }
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

std::pair<std::string, std::string> peek_kind(const std::filesystem::path& file) {
  const std::string text = read_case_file(file);  // a FIFO or directory is refused here
  YAML::Node raw;
  try {
    raw = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw CaseError(
        fmt::format("{}:{}: YAML syntax error: {}", file.string(), e.mark.line + 1, e.msg));
  }
  if (!raw.IsMap() || !raw["kind"].IsDefined() || !raw["kind"].IsScalar())
    throw CaseError(
        fmt::format("{}:1: kind: missing required key; expected the case kind "
                    "(rev, dem, mpm, pair, calibrate)",
                    file.string()));
  std::string test;
  if (raw["test"].IsDefined() && raw["test"].IsScalar()) test = raw["test"].as<std::string>();
  return {raw["kind"].as<std::string>(), test};
}

}  // namespace granflow::core
