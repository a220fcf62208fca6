// The result tables of `kind: rev, test: simple_shear`, defined once (docs/results.md): the
// series of each condition (/series or /conditions/N/series) and the steady table (/steady, one
// row per condition), with the names of the shared vocabulary (core/result_columns.hpp). The
// writer (rev_kind.cpp) and `granflow results --markdown` use these tables.
//
// p, the grain pressure: the pressure that μ = τ/p and I use in the model: the imposed σ_yy under
// constant_pressure, p_COL + p' under constant_volume (docs/model/multi_regime.md). σ_yy itself is
// `normal_stress` (it differs from p at constant volume when σ_FC is anisotropic).
#pragma once

#include <vector>

#include "continuum/rev/simple_shear.hpp"
#include "core/result_columns.hpp"

namespace granflow::rev {

// One steady row of the simple-shear table.
struct SimpleShearRow {
  double shear_rate = 0, void_ratio = 0, solid_fraction = 0, granular_temperature = 0,
         scaled_temperature = 0, grain_pressure = 0, normal_stress = 0, shear_stress = 0,
         collisional_shear_stress = 0, liquid_shear_stress = 0, friction = 0, inertial_number = 0,
         viscous_number = 0, mixed_number = 0, steady_start_strain = 0;
  long steady_reached = 0;
};

struct RevSeriesColumn {
  core::Column column;
  std::vector<double> SimpleShearSeries::*values;
};

struct RevSteadyColumn {
  core::Column column;
  double SimpleShearRow::*value = nullptr;  // a number, or
  long SimpleShearRow::*flag = nullptr;     // a flag (integer)
};

namespace rev_columns {
using core::columns::described;
namespace c = core::columns;

inline constexpr core::Column grain_pressure{
    "grain_pressure", "Pa",
    "pressure p on the grains that μ and I use: σ_yy (constant_pressure), p_COL + p_IC + "
    "p' (constant_volume)"};
inline constexpr core::Column collisional_shear_stress{"collisional_shear_stress", "Pa",
                                                       "collisional shear stress τ_COL"};
inline constexpr core::Column liquid_shear_stress{"liquid_shear_stress", "Pa",
                                                  "liquid shear stress τ_L = η(ν) γ̇"};

inline constexpr RevSeriesColumn simple_shear_series[] = {
    {c::time, &SimpleShearSeries::time},
    {c::strain, &SimpleShearSeries::strain},
    {{"time_step", "s", "time step Δt"}, &SimpleShearSeries::time_step},
    {c::granular_temperature, &SimpleShearSeries::granular_temperature},
    {c::void_ratio, &SimpleShearSeries::void_ratio},
    {described(c::solid_fraction, "solid fraction ν"), &SimpleShearSeries::solid_fraction},
    {grain_pressure, &SimpleShearSeries::pressure},
    {described(c::shear_stress, "shear stress τ = τ_FC + τ_IC + τ_COL + τ_L"),
     &SimpleShearSeries::shear_stress},
    {collisional_shear_stress, &SimpleShearSeries::collisional_shear_stress},
    {liquid_shear_stress, &SimpleShearSeries::liquid_shear_stress},
    {described(c::friction, "stress ratio μ = τ/p"), &SimpleShearSeries::friction},
    {described(c::inertial_number, "I = γ̇ d / √(p/ρ_p)"), &SimpleShearSeries::inertial_number},
    {{"force_chain_shear_stress", "Pa", "force-chain shear stress τ_FC"},
     &SimpleShearSeries::force_chain_shear_stress},
    {{"effective_pressure", "Pa", "effective pressure p' = p_FC of the force chains"},
     &SimpleShearSeries::effective_pressure},
    {c::locus_size, &SimpleShearSeries::locus_size},
    {described(c::normal_stress, "σ_yy = σ_yy,FC + σ_yy,IC + σ_yy,COL + σ_yy,L"),
     &SimpleShearSeries::normal_stress},
    {{"force_chain_normal_stress", "Pa", "σ_yy,FC"}, &SimpleShearSeries::force_chain_normal_stress},
    {{"collisional_pressure", "Pa", "collisional pressure p_COL"},
     &SimpleShearSeries::collisional_pressure},
    {{"vertical_strain_rate", "1/s", "ε̇_yy (compression positive; mixed control only, else 0)"},
     &SimpleShearSeries::vertical_strain_rate},
    {{"inertial_contact_pressure", "Pa",
      "the contacts' dense inertial pressure p_IC (collisional.inertial_contact; 0 when off)"},
     &SimpleShearSeries::inertial_contact_pressure},
};

inline constexpr RevSteadyColumn simple_shear_steady[] = {
    {c::shear_rate, &SimpleShearRow::shear_rate},
    {c::void_ratio, &SimpleShearRow::void_ratio},
    {described(c::solid_fraction, "solid fraction ν"), &SimpleShearRow::solid_fraction},
    {c::granular_temperature, &SimpleShearRow::granular_temperature},
    {described(c::scaled_temperature, "T / (d γ̇)², d the grain diameter"),
     &SimpleShearRow::scaled_temperature},
    {grain_pressure, &SimpleShearRow::grain_pressure},
    {described(c::normal_stress, "σ_yy = σ_yy,FC + σ_yy,IC + σ_yy,COL + σ_yy,L"),
     &SimpleShearRow::normal_stress},
    {c::shear_stress, &SimpleShearRow::shear_stress},
    {collisional_shear_stress, &SimpleShearRow::collisional_shear_stress},
    {liquid_shear_stress, &SimpleShearRow::liquid_shear_stress},
    {described(c::friction, "stress ratio μ = τ/p"), &SimpleShearRow::friction},
    {described(c::inertial_number, "I = γ̇ d / √(p/ρ_p)"), &SimpleShearRow::inertial_number},
    {described(c::viscous_number, "J = η0 γ̇ / p (0 when dry)"), &SimpleShearRow::viscous_number},
    {described(c::mixed_number, "K = J + α I² (α = liquid.trulsson_alpha) [Trulsson2012]"),
     &SimpleShearRow::mixed_number},
    {described(c::steady_start_strain, "strain at which the steady state was detected"),
     &SimpleShearRow::steady_start_strain},
    {c::steady_reached, nullptr, &SimpleShearRow::steady_reached},
};

}  // namespace rev_columns

}  // namespace granflow::rev
