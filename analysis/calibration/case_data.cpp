// Reading a calibrate case: its model sections, its DEM data (granflow result.h5 files and text
// tables from any code, dem_table.hpp), the error model and the training / held-out split.
#include <fmt/format.h>

#include <cmath>
#include <sstream>

#include "analysis/calibration/calibration.hpp"
#include "analysis/calibration/dem_table.hpp"
#include "continuum/sections/model_sections.hpp"

namespace granflow::calibration {

std::vector<std::string> split_names(const std::string& text) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(text);
  while (in >> item) {
    std::istringstream parts(item);
    std::string part;
    while (std::getline(parts, part, ','))
      if (!part.empty()) out.push_back(part);
  }
  return out;
}

std::filesystem::path resolve_data_path(const core::Case& c, const std::string& name) {
  const std::filesystem::path p(name);
  if (p.is_absolute() || std::filesystem::exists(p)) return p;
  // Then beside the case file. Never the source tree the binary was built from: that may be
  // another checkout, whose data would be used without a word.
  const auto beside_case = std::filesystem::path(c.origin()).parent_path() / p;
  if (std::filesystem::exists(beside_case)) return beside_case;
  return p;  // reported as missing by read_dem_dataset
}

std::filesystem::path resolve_table_path(const core::Case& c, const std::string& name) {
  const std::filesystem::path p(name);
  if (p.is_absolute()) return p;
  const auto beside_case = std::filesystem::path(c.origin()).parent_path() / p;
  if (std::filesystem::exists(beside_case)) return beside_case;
  if (std::filesystem::exists(p)) return p;
  return beside_case;  // reported as missing
}

CalibratedModel read_case_model(const core::Case& c) {
  CalibratedModel m;
  m.settings = continuum::read_multi_regime_settings(c);
  m.reference_liquid_viscosity = m.settings.liquid_parameters.viscosity;
  if (c.schema().child("fit") && c.schema().child("fit")->child("fluctuation_dissipation_factor"))
    m.factors.fluctuation_dissipation = c.number("fit.fluctuation_dissipation_factor");
  if (c.schema().child("steady")) {
    m.factors.contact_production = c.number("steady.contact_production");
    m.factors.friction_rise = c.number("steady.friction_rise");
    m.factors.friction_rise_I0 = c.number("steady.friction_rise_I0");
    m.factors.viscous_dilatancy = c.number("steady.viscous_dilatancy");
    m.factors.skeleton_from_model = c.string("steady.skeleton_stress") == "force_chain_model";
  }
  m.factors.mixed_number_alpha = c.number("liquid.trulsson_alpha");
  return m;
}

CaseData read_case_data(const core::Case& c) {
  CaseData out;
  std::vector<DataPoint> all;
  const auto files = split_names(c.has("data.files") ? c.string("data.files") : "");
  const auto tables = split_names(c.has("data.table") ? c.string("data.table") : "");
  if (files.empty() && tables.empty())
    c.fail("data.files",
           "at least one DEM dataset: data.files (granflow result.h5) or data.table (a text "
           "table, docs/calibration.md)");
  const auto& col = continuum::read_multi_regime_settings(c).collisional_parameters;
  const bool filter = c.has("data.particle_friction");
  const auto keep = [&](const DataPoint& point) {
    if (!filter || std::abs(point.particle_friction - c.number("data.particle_friction")) < 1e-12)
      all.push_back(point);
  };
  int source = 0;
  for (const auto& name : files) {
    const auto path = resolve_data_path(c, name);
    DemDataset set;
    try {
      set = read_dem_dataset(path, source++);
    } catch (const std::exception& e) {
      c.fail("data.files", e.what());
    }
    for (const auto& why : set.skipped) out.notes.push_back("skipped " + why);
    out.files.push_back(fmt::format("{}: {} usable conditions ({})", path.string(),
                                    set.points.size(), protocol_name(set.protocol)));
    if (std::abs(set.diameter / col.diameter - 1) > 0.05 ||
        std::abs(set.particle_density / col.particle_density - 1) > 1e-6)
      out.notes.push_back(
          fmt::format("{}: DEM d = {:g} m, ρ_p = {:g} kg/m³ differ from the case's material; the "
                      "case's is used",
                      path.string(), set.diameter, set.particle_density));
    for (const auto& point : set.points) keep(point);
  }
  // ---- text tables (dem_table.hpp)
  TableSpec spec;
  if (c.has("data.protocol")) spec.protocol = c.string("data.protocol");
  if (c.has("data.units")) spec.units = c.string("data.units");
  for (const auto& q : table_quantities()) {
    if (c.has("data.columns." + q)) spec.columns[q] = c.string("data.columns." + q);
    if (c.has("data.errors." + q)) spec.errors[q] = c.string("data.errors." + q);
  }
  spec.particle_friction = filter ? c.number("data.particle_friction") : NAN;
  spec.diameter = col.diameter, spec.particle_density = col.particle_density;
  for (const auto& name : tables) {
    spec.file = resolve_table_path(c, name);
    spec.source_index = source++;
    if (!std::filesystem::exists(spec.file))
      c.fail("data.table", fmt::format("{}: no such table", spec.file.string()));
    DemTable table;
    try {
      table = read_dem_table(spec);
    } catch (const TableError& e) {
      const std::string at =
          e.line > 0 ? fmt::format("{}:{}", spec.file.string(), e.line) : spec.file.string();
      throw core::CaseError(fmt::format("{}: {}: {} (case {})", at, e.key, e.what(),
                                        c.location(c.has(e.key) ? e.key : "data.table")));
    } catch (const std::exception& e) {
      c.fail("data.table", e.what());
    }
    if (table.units == "dimensionless")
      for (const auto& [key, value] :
           {std::pair{"material.diameter", col.diameter},
            std::pair{"material.particle_density", col.particle_density}})
        if (std::abs(value - 1) > 1e-12)
          c.fail(key, fmt::format("1 with the dimensionless table {} (units d = ρ_p = γ̇ = 1: the "
                                  "continuum runs in the same units, force_chains."
                                  "atmospheric_pressure in ρ_p d² γ̇²), got {:g}; or give the "
                                  "table in si units",
                                  spec.file.string(), value));
    std::string derived, errors;
    for (const auto& s : table.derived) derived += (derived.empty() ? "" : "; ") + s;
    for (const auto& s : table.errors) errors += (errors.empty() ? "" : "; ") + s;
    out.files.push_back(fmt::format("{}: {} rows ({}, {} units)", spec.file.string(),
                                    table.set.points.size(), protocol_name(table.set.protocol),
                                    table.units));
    out.info.push_back(fmt::format("{}: derived: {}", spec.file.filename().string(),
                                   derived.empty() ? "nothing" : derived));
    out.info.push_back(
        fmt::format("{}: standard errors from columns: {}", spec.file.filename().string(), errors));
    if (!table.unused.empty()) {
      std::string unused;
      for (const auto& s : table.unused) unused += (unused.empty() ? "" : ", ") + s;
      out.info.push_back(
          fmt::format("{}: columns not read: {}", spec.file.filename().string(), unused));
    }
    for (const auto& point : table.set.points) keep(point);
  }
  if (all.empty())
    c.fail(files.empty() ? "data.table" : "data.files",
           "datasets with usable rows (and data.particle_friction matching one)");
  if (!c.has("data.points")) out.used = all;
  if (c.has("data.points"))
    for (double v : c.number_list("data.points")) {
      const auto i = static_cast<long>(v);
      if (i < 0 || i >= static_cast<long>(all.size()) || static_cast<double>(i) != v)
        c.fail("data.points", fmt::format("integer indices in [0, {})", all.size()));
      out.used.push_back(all[static_cast<std::size_t>(i)]);
    }
  // ---- error model: the data's own errors with a relative floor added in quadrature
  std::vector<Observable> observables;
  for (const auto& o : split_names(c.string("data.observables")))
    observables.push_back(parse_observable(o));
  for (auto& point : out.used)
    for (int k = 0; k < observable_count; ++k)
      point.floor[k] = c.number("data.error_floor." + observable_names()[k]);
  const auto source_name = [&](int s) {
    return s < static_cast<int>(files.size()) ? files[static_cast<std::size_t>(s)]
                                              : tables[static_cast<std::size_t>(s) - files.size()];
  };
  for (const auto o : observables) {
    const std::string& on = observable_names()[static_cast<int>(o)];
    int tested = 0;
    for (const auto& point : out.used) {
      const int k = static_cast<int>(o);
      if (o == imposed_observable(point.protocol) || !std::isfinite(point.value[k])) continue;
      if (!(fit_error(point, o) > 0))
        c.fail("data.error_floor." + on,
               fmt::format("a standard error for {} on row {} of {}, which gives none: name its "
                           "column in data.errors.{} or set data.error_floor.{} > 0",
                           on, point.row, source_name(point.source), on, on));
      ++tested;
    }
    if (tested == 0)
      c.fail("data.observables",
             fmt::format("observables the data test; no used row measures {} under a protocol "
                         "that predicts it (constant pressure imposes σ_yy, constant volume φ)",
                         on));
  }
  // ---- repeated conditions: kept as independent rows, their spread reported
  const auto same = [](double a, double b) {
    return (std::isnan(a) && std::isnan(b)) ||
           std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b));
  };
  const auto control = [](const DataPoint& p) {
    return p.protocol == Protocol::constant_volume ? p.value[1] : p.normal_stress;
  };
  std::vector<int> group(out.used.size(), -1);
  std::vector<std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < out.used.size(); ++i) {
    if (group[i] >= 0) continue;
    std::vector<std::size_t> members = {i};
    for (std::size_t j = i + 1; j < out.used.size(); ++j) {
      const auto &a = out.used[i], &b = out.used[j];
      if (group[j] < 0 && a.protocol == b.protocol && same(a.shear_rate, b.shear_rate) &&
          same(control(a), control(b)) && same(a.particle_friction, b.particle_friction) &&
          same(a.liquid_viscosity, b.liquid_viscosity))
        members.push_back(j), group[j] = static_cast<int>(groups.size());
    }
    group[i] = static_cast<int>(groups.size());
    if (members.size() > 1) groups.push_back(members);
  }
  out.repeat_groups = static_cast<int>(groups.size());
  double ss[observable_count] = {}, sigma2[observable_count] = {};
  int df[observable_count] = {}, n_sigma[observable_count] = {};
  for (const auto& members : groups) {
    const DataPoint& first = out.used[members.front()];
    std::string rows, spread;
    for (const auto m : members)
      rows += fmt::format("{}{}", rows.empty() ? "" : ", ",
                          out.used[m].line > 0 ? fmt::format("line {}", out.used[m].line)
                                               : fmt::format("row {}", out.used[m].row));
    for (int k = 0; k < observable_count; ++k) {
      if (Observable(k) == imposed_observable(first.protocol)) continue;
      double mean = 0, s2 = 0, e2 = 0;
      int n = 0;
      for (const auto m : members)
        if (std::isfinite(out.used[m].value[k])) mean += out.used[m].value[k], ++n;
      if (n < 2) continue;
      mean /= n;
      for (const auto m : members)
        if (std::isfinite(out.used[m].value[k])) {
          s2 += std::pow(out.used[m].value[k] - mean, 2);
          e2 += std::pow(out.used[m].error[k], 2);
        }
      ss[k] += s2, df[k] += n - 1, sigma2[k] += e2, n_sigma[k] += n;
      spread += fmt::format("; {} SD {:.3g} (stated σ {:.3g})", observable_names()[k],
                            std::sqrt(s2 / (n - 1)), std::sqrt(e2 / n));
    }
    out.repeat_notes.push_back(
        fmt::format("repeated condition ({}, γ̇ = {:g}, {} = {:g}) in {} rows of {} ({}){}",
                    protocol_name(first.protocol), first.shear_rate,
                    first.protocol == Protocol::constant_volume ? "φ" : "σ_yy", control(first),
                    members.size(), source_name(first.source), rows, spread));
  }
  for (int k = 0; k < observable_count; ++k)
    if (df[k] > 0 && sigma2[k] > 0)
      out.repeat_spread[k] = std::sqrt(ss[k] / df[k]) / std::sqrt(sigma2[k] / n_sigma[k]);
  // every_other holds out the 2nd, 4th, ... used point, as kind: calibrate
  out.held.assign(out.used.size(), 0);
  const std::string mode = c.string("holdout.mode");
  if (mode == "every_other")
    for (std::size_t i = 1; i < out.used.size(); i += 2) out.held[i] = 1;
  if (mode == "list")
    for (double v : c.number_list("holdout.points")) {
      const auto i = static_cast<long>(v);
      if (i < 0 || i >= static_cast<long>(out.used.size()))
        c.fail("holdout.points", fmt::format("indices in [0, {})", out.used.size()));
      out.held[static_cast<std::size_t>(i)] = 1;
    }
  for (std::size_t i = 0; i < out.used.size(); ++i)
    (out.held[i] ? out.holdout : out.training).push_back(out.used[i]);
  return out;
}

}  // namespace granflow::calibration
