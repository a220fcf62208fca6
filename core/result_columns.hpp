// The results vocabulary shared by the case kinds: one dataset name and unit per physical
// quantity, whichever kind writes it (rev, dem, pair, calibrate). A kind's tables
// (continuum/rev/rev_columns.hpp, dem_coupling/kind/dem_columns.hpp) are built from these, with a
// description of their own where the kind measures the quantity its own way (`described`), and
// the C++ readers (calibration, pair, `granflow report`) use the same constants. docs/results.md
// is generated from the tables (`granflow results --markdown`).
//
// Stresses are compression positive. σ_yy is the normal stress on the shear planes (the gradient
// direction), τ = σ_xy the shear stress, tr(σ)/3 the mean stress; they differ by a few per cent in
// a sheared granular sample (normal stress differences), so they have different names.
#pragma once

#include "core/result_file.hpp"

namespace granflow::core::columns {

constexpr Column described(Column column, const char* description) {
  column.description = description;
  return column;
}

// Imposed loading.
inline constexpr Column shear_rate{"shear_rate", "1/s", "imposed shear rate γ̇"};
inline constexpr Column normal_stress_target{
    "normal_stress_target", "Pa", "imposed normal stress σ_yy (constant_pressure protocol)"};
inline constexpr Column solid_fraction_target{
    "solid_fraction_target", "1", "imposed solid fraction φ (constant_volume protocol)"};
inline constexpr Column particle_friction{"particle_friction", "1",
                                          "interparticle (Coulomb) friction coefficient μ_p"};
inline constexpr Column liquid_viscosity{"liquid_viscosity", "Pa s", "liquid viscosity η0"};

// Stresses.
inline constexpr Column normal_stress{"normal_stress", "Pa",
                                      "normal stress σ_yy on the shear planes"};
inline constexpr Column mean_stress{"mean_stress", "Pa", "mean stress tr(σ)/3"};
inline constexpr Column shear_stress{"shear_stress", "Pa", "shear stress τ = σ_xy"};

// State and dimensionless numbers.
inline constexpr Column friction{"friction", "1", "stress ratio μ = τ/σ_yy"};
inline constexpr Column solid_fraction{"solid_fraction", "1", "solid fraction φ (ν)"};
inline constexpr Column void_ratio{"void_ratio", "1", "void ratio e = 1/φ − 1"};
inline constexpr Column granular_temperature{"granular_temperature", "m^2/s^2",
                                             "granular temperature T (fluctuation kinetic energy)"};
inline constexpr Column scaled_temperature{"scaled_temperature", "1", "T / (d γ̇)²"};
inline constexpr Column inertial_number{"inertial_number", "1", "inertial number I = γ̇ d / √(σ_yy/ρ_p)"};
inline constexpr Column viscous_number{"viscous_number", "1", "viscous number J = η0 γ̇ / σ_yy"};
inline constexpr Column mixed_number{"mixed_number", "1",
                                     "mixed (visco-inertial) number K = J + α I² [Trulsson2012]"};
inline constexpr Column stokes_number{"stokes_number", "1", "Stokes number St = ρ_p d² γ̇ / η0 = I²/J"};
inline constexpr Column coordination_number{"coordination_number", "1",
                                            "coordination number Z = 2 N_contacts / N"};
inline constexpr Column locus_size{"locus_size", "Pa",
                                   "size r_c of the force-chain yield locus (docs/model/force_chains.md)"};

// Steady-state bookkeeping.
inline constexpr Column steady_start_strain{"steady_start_strain", "1",
                                            "shear strain from which the state is steady"};
inline constexpr Column steady_reached{"steady_reached", "1",
                                       "1 when a steady state was detected, else 0"};
inline constexpr Column strain{"strain", "1", "shear strain γ = γ̇ t"};
inline constexpr Column time{"time", "s", "time"};

// The suffix of a standard-error column: `<name>_err`, same unit.
inline constexpr const char* error_suffix = "_err";

}  // namespace granflow::core::columns
