#include "core/schema.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <thread>

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
Field& Field::limited_by(std::string limit_name) {
  if (!limits_section().child(limit_name))
    throw std::logic_error("schema: " + key_ + " limited by an unknown limit " + limit_name);
  limit_ = std::move(limit_name);
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
  if (!limit_.empty()) what += (lower_ || upper_ ? " and <= limits." : " <= limits.") + limit_;
  if (!unit_.empty()) what += " [" + unit_ + "]";
  return what;
}

bool Field::within_bounds(double value) const {
  if (!std::isfinite(value)) return false;
  if (value != 0 && std::abs(value) < std::numeric_limits<double>::min()) return false;
  if (lower_ && (lower_inclusive_ ? value < *lower_ : value <= *lower_)) return false;
  if (upper_ && (upper_inclusive_ ? value > *upper_ : value >= *upper_)) return false;
  return true;
}

namespace {
constexpr long long kIntMin = std::numeric_limits<int>::min();
constexpr long long kIntMax = std::numeric_limits<int>::max();
constexpr double kTwo63 = 9223372036854775808.0;  // 2^63
constexpr double kTwo53 = 9007199254740992.0;     // 2^53: doubles are exact whole numbers below
}  // namespace

long long Field::integer_min() const {
  if (!lower_) return kIntMin;
  const double b = lower_inclusive_ ? std::ceil(*lower_) : std::floor(*lower_) + 1;
  if (b <= -kTwo63) return std::numeric_limits<long long>::min();
  if (b >= kTwo63) return std::numeric_limits<long long>::max();
  return static_cast<long long>(b);
}

long long Field::integer_max() const {
  if (!upper_) return kIntMax;
  const double b = upper_inclusive_ ? std::floor(*upper_) : std::ceil(*upper_) - 1;
  if (b >= kTwo63) return std::numeric_limits<long long>::max();
  if (b <= -kTwo63) return std::numeric_limits<long long>::min();
  return static_cast<long long>(b);
}

std::string Field::integer_limit_note() const {
  if (!lower_ && !upper_) return fmt::format(" (in [{}, {}])", kIntMin, kIntMax);
  if (!upper_) return fmt::format(" (at most {})", kIntMax);
  if (!lower_) return fmt::format(" (at least {})", kIntMin);
  return "";
}

Field::IntegerStatus Field::parse_integer(const std::string& text, long long& value) const {
  std::string_view s(text);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);  // from_chars takes no '+'
  if (s.empty() || s.front() == '+') return IntegerStatus::not_integer;
  const char* first = s.data();
  const char* last = s.data() + s.size();
  const std::size_t digits_from = s.front() == '-' ? 1 : 0;
  const bool plain_digits =
      s.size() > digits_from &&
      s.find_first_not_of("0123456789", digits_from) == std::string_view::npos;
  if (plain_digits) {
    long long v = 0;
    const auto [end, ec] = std::from_chars(first, last, v);
    if (ec == std::errc::result_out_of_range) return IntegerStatus::out_of_range;
    if (ec != std::errc() || end != last) return IntegerStatus::not_integer;
    value = v;
  } else {
    double d = 0;
    const auto [end, ec] = std::from_chars(first, last, d);
    if (ec == std::errc::result_out_of_range && end == last) return IntegerStatus::out_of_range;
    if (ec != std::errc() || end != last || !std::isfinite(d) || std::floor(d) != d)
      return IntegerStatus::not_integer;
    if (std::abs(d) >= kTwo63) return IntegerStatus::out_of_range;  // beyond int64
    value = static_cast<long long>(d);  // exact: d is a whole number within int64
    if (value < integer_min() || value > integer_max()) return IntegerStatus::out_of_range;
    // 9007199254740993.0 reads as ...992: beyond 2^53 only digits say which integer is meant
    if (std::abs(d) > kTwo53) return IntegerStatus::inexact;
    return IntegerStatus::ok;
  }
  if (value < integer_min() || value > integer_max()) return IntegerStatus::out_of_range;
  return IntegerStatus::ok;
}

Schema make_root_schema(std::string doc) {
  return Field("", ValueType::section, "", std::move(doc));
}

long long default_max_ranks() {
  return 4 * std::max(1LL, static_cast<long long>(std::thread::hardware_concurrency()));
}

const Field& limits_section() {
  static const Field limits = [] {
    Field l("limits", ValueType::section, "",
            "size bounds, checked before anything is expanded, allocated or started; raise one "
            "(here or with --set limits.KEY=N) to run beyond it on purpose");
    l.integer("max_conditions",
              "most conditions a sweep may have: the product of its list lengths, refused "
              "before the conditions are built (each takes memory in check and a run)")
        .default_value("10000")
        .at_least(1);
    l.integer("max_particles",
              "most spheres of a DEM run (dem.particles); 1e6 spheres sheared over strain 20 at "
              "25 600 steps per unit strain take about a day at the 7e6 particle-steps/s "
              "measured on one core (docs/performance.md)")
        .default_value("1000000")
        .at_least(1);
    l.integer("max_ranks",
              "most MPI ranks of one DEM run (dem.ranks); default 4 x the hardware threads of "
              "the machine that checks the case (at least 4): granflow-dem is started with "
              "mpirun --oversubscribe, which lifts Open MPI's own bound")
        .at_least(1);
    l.number("max_steps", "",
             "most time steps a DEM run may take: dem.compression_steps + strain.total / "
             "(shear_rate × Δt) with the Δt the deck will use; 1e10 steps of 1000 spheres take "
             "about two weeks at 7e6 particle-steps/s")
        .default_value("1e10")
        .greater_than(0);
    return l;
  }();
  return limits;
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
  // every kind accepts the size limits (limits_section)
  const Field& limits = limits_section();
  out << "| `limits` | section | | | " << limits.doc() << " |\n";
  markdown_rows(limits, "limits", out);
  out << "\n";
  return out.str();
}

}  // namespace granflow::core
