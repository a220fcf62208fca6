// The /pair table of `kind: pair`, defined once (docs/results.md): QUANTITY_SOURCE, the
// quantity named as in the shared vocabulary (core/result_columns.hpp) and the source a suffix:
//   _dem      the DEM steady value (batch means), _dem_err its standard error
//   _cont     the continuum's steady simple shear at the DEM's γ̇ and σ_yy (at its φ when the
//             DEM ran at constant volume)
//   _kt       kinetic theory alone at the same conditions
//   _cal      the model calibrated on the points with held_out = 0
//   _rev      the time-stepped REV, kinetic theory alone (the second path of _kt)
//   _model    the case's continuum model (smooth curves)
//   _rel_err  continuum / DEM − 1
// pair_column(name) gives the unit and a description of each.
#pragma once

#include <string>
#include <string_view>
#include <utility>

#include "core/result_columns.hpp"

namespace granflow::pair {

struct PairColumn {
  std::string name, unit, description;
};

inline constexpr std::pair<const char*, const char*> pair_sources[] = {
      {"_dem_err", "standard error of the DEM steady value (batch means)"},
      {"_dem", "DEM steady value"},
      {"_cont",
       "continuum steady simple shear at the DEM's γ̇ and σ_yy (at its φ for a constant-volume "
       "DEM)"},
      {"_kt", "kinetic theory alone at the DEM's conditions"},
      {"_cal", "the model calibrated on the points with held_out = 0"},
      {"_rev", "time-stepped REV, kinetic theory alone (second path of _kt)"},
      {"_model", "the case's continuum model"},
      {"_rel_err", "relative error of the continuum: continuum / DEM − 1"}};

// What a suffix means ("" for an unknown one).
inline std::string pair_source(std::string_view suffix) {
  for (const auto& [tag, source] : pair_sources)
    if (suffix == tag) return source;
  return "";
}

inline PairColumn pair_column(const std::string& name) {
  namespace c = core::columns;
  constexpr core::Column quantities[] = {
      c::friction,        c::solid_fraction, c::void_ratio,     c::granular_temperature,
      c::inertial_number, c::mixed_number,   c::viscous_number, c::normal_stress};
  for (const core::Column& q : quantities) {
    const std::string_view n = name, base = q.name;
    if (!n.starts_with(base) || n.size() == base.size()) continue;
    const std::string_view suffix = n.substr(base.size());
    if (const std::string source = pair_source(suffix); !source.empty())
      return {name, suffix == "_rel_err" ? "1" : q.unit, std::string(q.description) + ": " + source};
  }
  return {name, "1", name};  // not a QUANTITY_SOURCE name: the writer gives its own
}

}  // namespace granflow::pair
