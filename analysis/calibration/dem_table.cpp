#include "analysis/calibration/dem_table.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <set>

#include "core/case.hpp"

namespace granflow::calibration {

const std::vector<std::string>& table_quantities() {
  static const std::vector<std::string> names = {
      "shear_rate",           "normal_stress",      "pressure",
      "shear_stress",         "friction",           "solid_fraction",
      "granular_temperature", "scaled_temperature", "inertial_number",
      "particle_friction",    "viscosity"};
  return names;
}

TableError::TableError(int line_, std::string key_, const std::string& problem)
    : std::runtime_error(problem), line(line_), key(std::move(key_)) {}

namespace {

std::string trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return "";
  const auto last = text.find_last_not_of(" \t\r");
  return std::string(text.substr(first, last - first + 1));
}

// CSV (a comma in the header) or whitespace-separated fields; CSV fields trimmed and unquoted.
std::vector<std::string> split_fields(const std::string& line, bool csv) {
  std::vector<std::string> out;
  if (csv) {
    std::size_t start = 0;
    while (true) {
      const auto comma = line.find(',', start);
      std::string field = trim(std::string_view(line).substr(start, comma - start));
      if (field.size() >= 2 && field.front() == '"' && field.back() == '"')
        field = field.substr(1, field.size() - 2);
      out.push_back(field);
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  } else {
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
      if (i >= line.size()) break;
      std::size_t j = i;
      while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
      out.push_back(line.substr(i, j - i));
      i = j;
    }
  }
  return out;
}

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

struct Metadata {
  std::string value;
  int line = 0;
};

// The table's own value of `key` and the case's: the one given, equal if both; TableError if they
// disagree. `choices`: the accepted names.
std::string agreed(const std::string& key, const std::string& from_case, const Metadata& stated,
                   const std::vector<std::string>& choices) {
  if (!stated.value.empty()) {
    bool known = false;
    for (const auto& c : choices) known = known || c == stated.value;
    if (!known)
      throw TableError(stated.line, "data.table",
                       fmt::format("'# {}: {}': expected one of {}", key,
                                   core::shorten(stated.value), join(choices)));
    if (!from_case.empty() && from_case != stated.value)
      throw TableError(stated.line, "data." + key,
                       fmt::format("the case says {} but the table states '# {}: {}'", from_case,
                                   key, stated.value));
    return stated.value;
  }
  return from_case;
}

}  // namespace

DemTable read_dem_table(const TableSpec& spec) {
  std::ifstream in(spec.file);
  if (!in)
    throw std::runtime_error(
        fmt::format("{}: cannot read the table ({})", spec.file.string(), std::strerror(errno)));
  // ---- lines: '#' comments (with the table's metadata), one header, data rows
  std::map<std::string, Metadata> meta;
  std::vector<std::string> header;
  int header_line = 0;
  bool csv = false;
  std::vector<std::pair<int, std::vector<std::string>>> rows;
  std::string text;
  for (int number = 1; std::getline(in, text); ++number) {
    const std::string t = trim(text);
    if (t.empty()) continue;
    if (t[0] == '#') {
      const auto colon = t.find(':');
      if (colon == std::string::npos) continue;
      const std::string key = trim(std::string_view(t).substr(1, colon - 1));
      if (key != "protocol" && key != "units" && key != "particle_friction") continue;
      const std::string value = trim(std::string_view(t).substr(colon + 1));
      if (meta.count(key) && meta[key].value != value)
        throw TableError(number, "data.table",
                         fmt::format("'# {}: {}' disagrees with line {} ('{}')", key,
                                     core::shorten(value), meta[key].line, meta[key].value));
      meta[key] = {value, number};
      continue;
    }
    if (header.empty()) {
      csv = t.find(',') != std::string::npos;
      header = split_fields(t, csv);
      header_line = number;
      std::set<std::string> seen;
      for (const auto& name : header) {
        if (name.empty())
          throw TableError(number, "data.table", "header: an empty column name; expected names");
        if (!seen.insert(name).second)
          throw TableError(number, "data.table",
                           fmt::format("header: column '{}' named twice", core::shorten(name)));
      }
      continue;
    }
    auto fields = split_fields(t, csv);
    if (fields.size() != header.size())
      throw TableError(number, "data.table",
                       fmt::format("{} fields where the header (line {}) names {} columns",
                                   fields.size(), header_line, header.size()));
    rows.emplace_back(number, std::move(fields));
  }
  if (header.empty())
    throw TableError(0, "data.table", "no header row; expected one row of column names");
  if (rows.empty()) throw TableError(header_line, "data.table", "no data rows after the header");

  // ---- columns: data.columns, else the quantity's own name; errors: data.errors, else NAME_err
  const auto find = [&](const std::string& name) {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return static_cast<int>(i);
    return -1;
  };
  for (const auto& [map, group] :
       {std::pair{&spec.columns, "columns"}, std::pair{&spec.errors, "errors"}})
    for (const auto& [quantity, name] : *map)
      if (find(name) < 0)
        throw TableError(
            header_line, fmt::format("data.{}.{}", group, quantity),
            fmt::format("column '{}' is not in the header of {}; expected one of: {}",
                        core::shorten(name), spec.file.filename().string(), join(header)));
  std::map<std::string, int> column, error;
  std::set<int> read;
  for (const auto& q : table_quantities()) {
    const auto it = spec.columns.find(q);
    const int c = find(it != spec.columns.end() ? it->second : q);
    if (c < 0) continue;
    column[q] = c, read.insert(c);
    const auto e = spec.errors.find(q);
    int ec = e != spec.errors.end() ? find(e->second) : find(header[c] + "_err");
    if (ec < 0) ec = find(q + "_err");
    if (ec >= 0) error[q] = ec, read.insert(ec);
  }
  const auto has = [&](const std::string& q) { return column.count(q) > 0; };

  DemTable out;
  // ---- protocol and units: the case's, the table's own, or inferred from the columns
  const std::string sigma_name = has("normal_stress") ? "normal_stress" : "pressure";
  const bool sigma_column = has("normal_stress") || has("pressure");
  std::string protocol =
      agreed("protocol", spec.protocol, meta["protocol"], {"constant_pressure", "constant_volume"});
  out.units = agreed("units", spec.units, meta["units"], {"si", "dimensionless"});
  if (out.units.empty()) out.units = "si", out.derived.push_back("units: si (not given)");
  const bool reduced = out.units == "dimensionless";
  const bool rate_known = has("shear_rate") || reduced;
  const bool stress_known = sigma_column || (has("inertial_number") && rate_known);
  if (protocol.empty()) {
    if (stress_known == has("solid_fraction"))
      throw TableError(
          0, "data.protocol",
          fmt::format("not given and not inferable for {} (it has {}); expected data.protocol: "
                      "constant_pressure or constant_volume, or a line '# protocol: NAME' in it",
                      spec.file.filename().string(),
                      stress_known ? "both the normal stress and φ" : "neither σ_yy nor φ"));
    protocol = stress_known ? "constant_pressure" : "constant_volume";
    out.derived.push_back(fmt::format("protocol: {} (inferred: the table has no {})", protocol,
                                      stress_known ? "solid_fraction" : "normal stress"));
  }
  out.set.protocol = parse_protocol(protocol);
  const bool volume = out.set.protocol == Protocol::constant_volume;
  const double d = reduced ? 1.0 : spec.diameter, rho = reduced ? 1.0 : spec.particle_density;
  out.set.diameter = d, out.set.particle_density = rho;

  // ---- what is required, what is derived
  const bool rate_from_I = !rate_known && sigma_column && has("inertial_number");
  if (!rate_known && !rate_from_I)
    throw TableError(header_line, "data.columns",
                     fmt::format("missing column: the shear rate (shear_rate, or inertial_number "
                                 "with normal_stress or pressure); {} has: {}",
                                 spec.file.filename().string(), join(header)));
  const bool stress_from_I = !sigma_column && has("inertial_number");
  if (!volume && !sigma_column && !stress_from_I)
    throw TableError(header_line, "data.columns",
                     fmt::format("missing column: constant_pressure needs the normal stress "
                                 "(normal_stress, pressure, or inertial_number with the shear "
                                 "rate); {} has: {}",
                                 spec.file.filename().string(), join(header)));
  if (volume && !has("solid_fraction"))
    throw TableError(header_line, "data.columns",
                     fmt::format("missing column: constant_volume needs solid_fraction; {} has: {}",
                                 spec.file.filename().string(), join(header)));
  const auto note = [&](bool when, const std::string& what) {
    if (when) out.derived.push_back(what);
  };
  note(reduced && !has("shear_rate"), "shear_rate = 1 (dimensionless)");
  note(rate_from_I, "shear_rate = inertial_number sqrt(σ_yy/ρ_p)/d");
  note(!has("normal_stress") && has("pressure"), "normal_stress = pressure (tr σ/3 taken as σ_yy)");
  note(stress_from_I, "normal_stress = ρ_p (γ̇ d/inertial_number)²");
  note(!has("friction") && has("shear_stress") && (sigma_column || stress_from_I),
       "friction = shear_stress/normal_stress");
  note(!has("scaled_temperature") && has("granular_temperature"),
       "scaled_temperature = granular_temperature/(d γ̇)²");
  note(!has("inertial_number") && (sigma_column || stress_from_I),
       "inertial_number = γ̇ d/sqrt(σ_yy/ρ_p)");
  for (std::size_t i = 0; i < header.size(); ++i)
    if (!read.count(static_cast<int>(i))) out.unused.push_back(header[i]);

  // ---- rows
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto& [line, fields] = rows[r];
    // A used column's value: a finite number within the quantity's range.
    const auto number = [&, line = line, &fields = fields](int c, const std::string& quantity,
                                                           const char* range, auto accept) {
      const std::string& f = fields[static_cast<std::size_t>(c)];
      const std::string& name = header[static_cast<std::size_t>(c)];
      const std::string column =
          name == quantity ? fmt::format("'{}'", name) : fmt::format("'{}' ({})", name, quantity);
      double v = NAN;
      const auto [end, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
      if (ec != std::errc() || end != f.data() + f.size() || !std::isfinite(v))
        throw TableError(
            line, "data.table",
            fmt::format("column {}: expected a finite number, got '{}'", column, core::shorten(f)));
      if (!accept(v))
        throw TableError(line, "data.table",
                         fmt::format("column {}: expected {}, got {}", column, range, f));
      return v;
    };
    const auto positive = [](double v) { return v > 0; };
    const auto non_negative = [](double v) { return v >= 0; };
    const auto any = [](double) { return true; };
    std::map<std::string, double> v, e;
    for (const auto& [q, c] : column) {
      if (q == "solid_fraction")
        v[q] = number(c, q, "φ in (0, 0.74]", [](double x) { return x > 0 && x <= 0.74; });
      else if (q == "normal_stress" || q == "pressure" || q == "shear_rate" ||
               q == "inertial_number")
        v[q] = number(c, q, "a value > 0", positive);
      else if (q == "granular_temperature" || q == "scaled_temperature" ||
               q == "particle_friction" || q == "viscosity")
        v[q] = number(c, q, "a value >= 0", non_negative);
      else
        v[q] = number(c, q, "a number", any);
      if (error.count(q)) e[q] = number(error[q], q + " error", "a value >= 0", non_negative);
    }
    const auto err = [&](const std::string& q) { return e.count(q) ? e[q] : 0.0; };
    DataPoint p;
    p.protocol = out.set.protocol;
    p.source = spec.source_index;
    p.row = static_cast<int>(r);
    p.line = line;
    if (reduced && has("shear_rate") && std::abs(v["shear_rate"] - 1) > 1e-12)
      throw TableError(line, "data.units",
                       fmt::format("a dimensionless table (d = ρ_p = γ̇ = 1) with shear_rate {}: "
                                   "expected 1, or data.units: si",
                                   v["shear_rate"]));
    double sigma = sigma_column ? v[sigma_name] : NAN;
    double sigma_rel_err = sigma_column ? err(sigma_name) / sigma : 0.0;
    p.shear_rate = has("shear_rate") ? v["shear_rate"]
                   : reduced         ? 1.0
                                     : v["inertial_number"] * std::sqrt(sigma / rho) / d;
    if (stress_from_I) {
      const double I = v["inertial_number"];
      sigma = rho * std::pow(p.shear_rate * d / I, 2);
      sigma_rel_err = 2 * err("inertial_number") / I;
    }
    p.normal_stress = sigma;
    p.inertial_number =
        has("inertial_number") ? v["inertial_number"] : p.shear_rate * d / std::sqrt(sigma / rho);
    p.particle_friction =
        has("particle_friction") ? v["particle_friction"] : spec.particle_friction;
    if (!has("particle_friction") && !meta["particle_friction"].value.empty()) {
      const std::string& text = meta["particle_friction"].value;
      double mu_p = NAN;
      const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), mu_p);
      if (ec != std::errc() || end != text.data() + text.size() || !(mu_p >= 0))
        throw TableError(
            meta["particle_friction"].line, "data.table",
            fmt::format("'# particle_friction: {}': expected a number >= 0", core::shorten(text)));
      p.particle_friction = mu_p;
    }
    if (has("viscosity")) p.liquid_viscosity = v["viscosity"];
    // friction
    if (has("friction")) {
      p.value[0] = v["friction"], p.error[0] = err("friction");
    } else if (has("shear_stress") && std::isfinite(sigma)) {
      const double tau = v["shear_stress"];
      p.value[0] = tau / sigma;
      const double tau_rel = tau != 0 ? err("shear_stress") / std::abs(tau) : 0.0;
      p.error[0] =
          std::abs(p.value[0]) * std::sqrt(tau_rel * tau_rel + sigma_rel_err * sigma_rel_err);
    } else {
      p.value[0] = NAN;
    }
    // solid fraction
    p.value[1] = has("solid_fraction") ? v["solid_fraction"] : NAN;
    p.error[1] = err("solid_fraction");
    // scaled temperature: its own error, else T's relative error (as read_dem_dataset)
    const double T = has("granular_temperature") ? v["granular_temperature"] : NAN;
    if (has("scaled_temperature"))
      p.value[2] = v["scaled_temperature"];
    else
      p.value[2] = T / (d * d * p.shear_rate * p.shear_rate);
    if (e.count("scaled_temperature"))
      p.error[2] = e["scaled_temperature"];
    else if (e.count("granular_temperature") && T > 0)
      p.error[2] = e["granular_temperature"] * p.value[2] / T;
    else
      p.error[2] = 0.0;
    // scaled pressure
    p.value[3] = sigma / (rho * d * d * p.shear_rate * p.shear_rate);
    p.error[3] = std::isfinite(sigma) ? p.value[3] * sigma_rel_err : 0.0;
    out.set.points.push_back(p);
  }
  // ---- which errors each observable carries (for the report)
  const auto from = [&](const std::string& q) {
    return error.count(q) ? fmt::format("'{}'", header[static_cast<std::size_t>(error[q])]) : "";
  };
  const auto list = [](std::vector<std::string> parts) {
    std::string s;
    for (const auto& x : parts)
      if (!x.empty()) s += (s.empty() ? "" : " and ") + x;
    return s.empty() ? std::string("none") : s;
  };
  out.errors = {"friction: " + (has("friction") ? list({from("friction")})
                                                : list({from("shear_stress"), from(sigma_name)})),
                "solid_fraction: " + list({from("solid_fraction")}),
                "scaled_temperature: " + (error.count("scaled_temperature")
                                              ? list({from("scaled_temperature")})
                                              : list({from("granular_temperature")})),
                "scaled_pressure: " +
                    (sigma_column ? list({from(sigma_name)}) : list({from("inertial_number")}))};
  return out;
}

}  // namespace granflow::calibration
