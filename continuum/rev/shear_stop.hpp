// The shear stopped: a material point held at its volume with ε̇ = 0 after a simple shear, whose
// agitation decays by the energy balance alone (docs/model/multi_regime.md §3). With s = T^½,
//   ds/dt = -c s - b s²   (a = 0: no shear work; c: the liquid's dissipation Λ, 0 dry;
//                          b: the collisional dissipation Γ),
// so a dry point cools as Haff's law, T(t) = T0 / (1 + b s0 t)² (Haff 1983), and an immersed one
// as s(t) = c s0 e^{-ct} / (c + b s0 (1 - e^{-ct})). At constant volume the skeleton does not
// strain, so σ_FC and r_c keep the values of the stop (a liquefied point stays liquefied: no
// compaction drives the regrowth of r_c), and the contacts' inertial pressure p_IC, ∝ γ̇, is 0.
#pragma once

#include "continuum/multi_regime/multi_regime_point.hpp"
#include "continuum/rev/simple_shear.hpp"

namespace granflow::rev {

struct ShearStopControl {
  double duration = 0.1;                 // s after the stop
  double time_step_factor = 0.1;         // Δt = factor / |c + 2 b s| (the cooling rate of s)
  double largest_step_fraction = 0.005;  // and Δt <= this × duration (resolution of the series)
};

// Advances `state` (constant volume, ε̇ = 0) for control.duration from the stop and appends one
// row per step to `series`: time (since the stop), strain (stop_strain, unchanged), time_step,
// granular_temperature, solid_fraction, void_ratio, pressure (p_COL + p_IC + tr(σ_FC)/3, the
// DEM's tr(P)/3), shear_stress, effective_pressure, normal_stress and collisional_pressure (the
// other columns stay empty). The T update is the point's exact Riccati step, so the series is
// exact at every step up to round-off. Throws core::NumericalFailure (step, variable) on a
// non-finite or negative T.
void run_shear_stop(const continuum::MultiRegimePoint& point, continuum::PointState state,
                    double stop_strain, const ShearStopControl& control, SimpleShearSeries& series);

}  // namespace granflow::rev
