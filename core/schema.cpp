#include "core/schema.hpp"

#include <fmt/format.h>

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace granflow::core {

const char* to_string(ValueType type) {
  switch (type) {
    case ValueType::number:
      return "number";
    case ValueType::integer:
      return "integer";
    case ValueType::boolean:
      return "boolean (true/false)";
    case ValueType::string:
      return "string";
    case ValueType::choice:
      return "name";
    case ValueType::number_list:
      return "list of numbers";
    case ValueType::section:
      return "section (a map of keys)";
  }
  return "?";
}

Field::Field(std::string key, ValueType type, std::string unit, std::string doc)
    : key_(std::move(key)), type_(type), unit_(std::move(unit)), doc_(std::move(doc)) {}

Field& Field::required() {
  required_ = true;
  return *this;
}
Field& Field::default_value(std::string yaml_scalar) {
  default_ = std::move(yaml_scalar);
  return *this;
}
Field& Field::greater_than(double bound) {
  lower_ = bound;
  lower_inclusive_ = false;
  return *this;
}
Field& Field::at_least(double bound) {
  lower_ = bound;
  lower_inclusive_ = true;
  return *this;
}
Field& Field::less_than(double bound) {
  upper_ = bound;
  upper_inclusive_ = false;
  return *this;
}
Field& Field::at_most(double bound) {
  upper_ = bound;
  upper_inclusive_ = true;
  return *this;
}
Field& Field::choices(std::vector<std::string> names) {
  choices_ = std::move(names);
  return *this;
}
Field& Field::sweepable() {
  sweepable_ = true;
  return *this;
}

Field& Field::add(Field child) {
  if (type_ != ValueType::section) throw std::logic_error("schema: add() on a non-section " + key_);
  for (auto& existing : children_)
    if (existing.key_ == child.key_) {
      existing = std::move(child);  // a later fragment overrides an earlier one of the same key
      return existing;
    }
  children_.push_back(std::move(child));
  return children_.back();
}
Field& Field::section(std::string key, std::string doc) {
  return add(Field(std::move(key), ValueType::section, "", std::move(doc)));
}
Field& Field::number(std::string key, std::string unit, std::string doc) {
  return add(Field(std::move(key), ValueType::number, std::move(unit), std::move(doc)));
}
Field& Field::integer(std::string key, std::string doc) {
  return add(Field(std::move(key), ValueType::integer, "", std::move(doc)));
}
Field& Field::boolean(std::string key, std::string doc) {
  return add(Field(std::move(key), ValueType::boolean, "", std::move(doc)));
}
Field& Field::string(std::string key, std::string doc) {
  return add(Field(std::move(key), ValueType::string, "", std::move(doc)));
}
Field& Field::choice(std::string key, std::vector<std::string> names, std::string doc) {
  return add(Field(std::move(key), ValueType::choice, "", std::move(doc)))
      .choices(std::move(names));
}
Field& Field::number_list(std::string key, std::string unit, std::string doc) {
  return add(Field(std::move(key), ValueType::number_list, std::move(unit), std::move(doc)));
}

const Field* Field::child(const std::string& key) const {
  for (const auto& c : children_)
    if (c.key_ == key) return &c;
  return nullptr;
}

static std::string format_bound(double v) { return fmt::format("{:g}", v); }

std::string Field::expectation() const {
  std::string what = to_string(type_);
  if (type_ == ValueType::choice) {
    what = "one of: ";
    for (std::size_t i = 0; i < choices_.size(); ++i) what += (i ? ", " : "") + choices_[i];
    return what;
  }
  if (lower_ && upper_) {
    what += fmt::format(" in {}{}, {}{}", lower_inclusive_ ? "[" : "(", format_bound(*lower_),
                        format_bound(*upper_), upper_inclusive_ ? "]" : ")");
  } else if (lower_) {
    what += fmt::format(" {} {}", lower_inclusive_ ? ">=" : ">", format_bound(*lower_));
  } else if (upper_) {
    what += fmt::format(" {} {}", upper_inclusive_ ? "<=" : "<", format_bound(*upper_));
  }
  if (!unit_.empty()) what += " [" + unit_ + "]";
  return what;
}

bool Field::within_bounds(double value) const {
  if (!std::isfinite(value)) return false;
  if (lower_ && (lower_inclusive_ ? value < *lower_ : value <= *lower_)) return false;
  if (upper_ && (upper_inclusive_ ? value > *upper_ : value >= *upper_)) return false;
  return true;
}

Schema make_root_schema(std::string doc) {
  return Field("", ValueType::section, "", std::move(doc));
}

static void markdown_rows(const Field& field, const std::string& prefix, std::ostringstream& out) {
  for (const auto& c : field.children()) {
    const std::string path = prefix.empty() ? c.key() : prefix + "." + c.key();
    if (c.type() == ValueType::section) {
      out << "| `" << path << "` | section | | | " << c.doc() << " |\n";
      markdown_rows(c, path, out);
      continue;
    }
    std::string req = c.is_required()
                          ? "required"
                          : (c.default_text() ? "`" + *c.default_text() + "`" : "optional");
    std::string doc = c.doc();
    if (c.is_sweepable()) doc += " (sweepable)";
    out << "| `" << path << "` | " << c.expectation() << " | "
        << (c.unit().empty() ? "-" : c.unit()) << " | " << req << " | " << doc << " |\n";
  }
}

std::string schema_markdown(const Schema& schema, const std::string& title) {
  std::ostringstream out;
  out << "### " << title << "\n\n" << schema.doc() << "\n\n";
  out << "| key | expected | unit | default | meaning |\n|---|---|---|---|---|\n";
  markdown_rows(schema, "", out);
  out << "\n";
  return out.str();
}

}  // namespace granflow::core
