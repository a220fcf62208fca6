// Case-file schema: the declared tree of keys a case kind accepts, with types, units, bounds,
// choices, defaults and documentation. The validator (case.hpp) checks a YAML case against it,
// and docs/cases.md is generated from it (granflow schema --markdown), so the two cannot drift.
#pragma once

#include <deque>
#include <optional>
#include <string>
#include <vector>

namespace granflow::core {

enum class ValueType { number, integer, boolean, string, choice, number_list, section };

const char* to_string(ValueType type);

// One key of the case tree. Fluent setters return *this so a schema reads like a table:
//   material.number("diameter", "m", "mean grain diameter d").required().greater_than(0);
class Field {
 public:
  Field(std::string key, ValueType type, std::string unit, std::string doc);

  Field& required();
  Field& default_value(std::string yaml_scalar);   // stored as YAML text, validated like input
  Field& greater_than(double bound);               // value > bound
  Field& at_least(double bound);                   // value >= bound
  Field& less_than(double bound);                  // value < bound
  Field& at_most(double bound);                    // value <= bound
  Field& choices(std::vector<std::string> names);  // for ValueType::choice
  Field& sweepable();                              // may be listed under `sweep:`
  // value <= limits.<name> of the case (limits_section(): a size bound the user may raise)
  Field& limited_by(std::string limit_name);

  // Children of a section. References stay valid (deque), so fragments can be built in place.
  Field& section(std::string key, std::string doc);
  Field& number(std::string key, std::string unit, std::string doc);
  Field& integer(std::string key, std::string doc);
  Field& boolean(std::string key, std::string doc);
  Field& string(std::string key, std::string doc);
  Field& choice(std::string key, std::vector<std::string> names, std::string doc);
  Field& number_list(std::string key, std::string unit, std::string doc);
  Field& add(Field child);  // append a prebuilt fragment (e.g. a shared material section)

  const std::string& key() const { return key_; }
  ValueType type() const { return type_; }
  const std::string& unit() const { return unit_; }
  const std::string& doc() const { return doc_; }
  bool is_required() const { return required_; }
  bool is_sweepable() const { return sweepable_; }
  const std::optional<std::string>& default_text() const { return default_; }
  const std::vector<std::string>& choice_names() const { return choices_; }
  const std::string& limit_name() const { return limit_; }  // empty: not limited_by
  const std::deque<Field>& children() const { return children_; }
  const Field* child(const std::string& key) const;

  // "> 0", "in (0, 1]", "one of: a, b" ... used in error messages and docs.
  std::string expectation() const;
  // Check a number against the bounds; returns false if outside. Subnormal numbers (nonzero,
  // below 2.2e-308 in magnitude) are outside every range: they underflow in any arithmetic.
  bool within_bounds(double value) const;

  // Integer fields: the scalar text is read as an integer exactly, never through a double
  // that could overflow. Accepted: decimal digits with an optional sign that fit int64, or a
  // number in floating notation (1e6, 2.0) that is a whole number of at most 2^53 in magnitude
  // (so it is exact; a larger one within range is `inexact`). The value must lie within the
  // bounds; a bound the schema does not state is that of an int (-2^31 .. 2^31-1), so every
  // integer key fits the int it is stored in.
  enum class IntegerStatus { ok, not_integer, out_of_range, inexact };
  IntegerStatus parse_integer(const std::string& text, long long& value) const;
  // Smallest/largest accepted integer (stated bounds, or the int limits when not stated).
  long long integer_min() const;
  long long integer_max() const;
  // " (at most 2147483647)" etc. when an implicit int limit applies, for out-of-range messages.
  std::string integer_limit_note() const;

 private:
  std::string key_;
  ValueType type_;
  std::string unit_;
  std::string doc_;
  bool required_ = false;
  bool sweepable_ = false;
  std::optional<std::string> default_;
  std::optional<double> lower_, upper_;
  bool lower_inclusive_ = false, upper_inclusive_ = false;
  std::vector<std::string> choices_;
  std::string limit_;
  std::deque<Field> children_;
};

// A whole case kind's schema is its root section.
using Schema = Field;
Schema make_root_schema(std::string doc);

// Size limits: the `limits:` section every case kind accepts (core reserves the key, as it does
// `sweep:` and `include:`). A case may ask for far more than a machine can do (a 1000 x 1000
// sweep, 3e9 spheres, 1e5 MPI ranks, 1e16 time steps); granflow refuses it before anything is
// expanded or allocated, and a user who means it raises the bound in the case file or with
// `--set limits.NAME=...`. Keys: max_conditions (sweep conditions, the product of the list
// lengths), max_particles (dem.particles), max_ranks (dem.ranks; default 4 x the hardware
// threads of this machine, at least 4), max_steps (time steps a DEM run implies).
const Field& limits_section();
// The default of limits.max_ranks on this machine.
long long default_max_ranks();

// Markdown reference of one schema (used for docs/cases.md).
std::string schema_markdown(const Schema& schema, const std::string& title);

}  // namespace granflow::core
