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

// The drained stop: the point, at rest (γ̇ = 0, ε̇_xx = ε̇_zz = 0), under a total normal stress σ_n
// shared by the grains and the excess pore pressure u that drives its liquid out over the
// drainage length H (Terzaghi's consolidation lumped to one point, as the consolidating element
// test and the DEM's fix drainage):
//   σ_yy(state) + u = σ_n,   ε̇_yy = k u,   k = κ(ν) / (η0 H²)
// (κ the liquid's permeability closure at the point's diameter, k at the start of each step, u
// implicit: constant_normal_stress_step with the drainage resistance 1/k). The point compacts
// as fast as the liquid leaves; compaction regrows r_c (docs/model/force_chains.md) and heats it
// (p_COL ε̇_v in the T balance). Steps: Δt <= time_step_factor / rate with rate the larger of the
// cooling rate of s and k M (M = dσ_yy/dε_yy of the last step, the consolidation rate), and
// <= largest_step_fraction × duration, >= smallest_step_fraction × duration. Appends rows as
// run_shear_stop, with vertical_strain_rate ε̇_yy. Throws core::NumericalFailure (step, variable)
// when no compaction carries σ_n.
struct DrainedStopControl {
  ShearStopControl stop;
  double normal_stress = 100.0;          // σ_n, Pa
  double drainage_length = 0.01;         // H, m
  double smallest_step_fraction = 1e-4;  // Δt >= this × duration (at most ~1e4 steps)
  // |σ_yy + u − σ_n| <= this × σ_n per step; a step that misses it is halved up to max_splits
  // times (advance_at_normal_stress: the force chains' sub-stepping makes σ_yy(Δε) jump by
  // ~STOL |Δσ_FC|, 1e-5 × 60 Pa here, where no root meets a tighter tolerance)
  double relative_tolerance = 1e-5;
  int max_splits = 3;
};

void run_drained_stop(const continuum::MultiRegimePoint& point, continuum::PointState state,
                      double stop_strain, const DrainedStopControl& control,
                      SimpleShearSeries& series);

}  // namespace granflow::rev
