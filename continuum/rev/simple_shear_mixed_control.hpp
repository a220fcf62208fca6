// Mixed control of one REV simple-shear step at constant normal stress with the force chains on
// (docs/model/multi_regime.md §4.1). Compression positive. Imposed per step: the shear rate γ̇
// (ε̇_xy = ε̇_yx = -γ̇/2, u_x = γ̇ y), ε̇_xx = ε̇_zz = 0, and the normal stress p on the grains:
//     R(Δε_yy) = σ_yy(state after the step) - p = 0,
//     σ_yy = [σ_FC + σ_COL + σ_L]_yy = σ_yy,FC + p_COL + 2 η_COL ε̇'_yy + 2 η(ν) ε̇'_yy,
// with ε̇'_yy = (2/3) ε̇_yy (the viscous normal stresses vanish at steady state, ε̇_yy = 0).
// The unknown Δε_yy = ε̇_yy Δt is found by trial steps, MultiRegimePoint::advance on copies of
// the start state: compaction (Δε_yy > 0) raises σ_yy,FC (elastic stiffness), ν and hence
// p_COL, and heats (the volumetric work in the T balance), so R increases with Δε_yy; the root
// is bracketed by secant steps, then refined by Illinois (modified regula falsi) with a
// bisection safeguard.
#pragma once

#include "continuum/multi_regime/multi_regime_point.hpp"

namespace granflow::rev {

struct NormalStressStep {
  continuum::PointState state;   // after the step
  continuum::StressParts parts;  // at the state after the step
  Eigen::Matrix3d strain_rate;   // the rate used (ε̇_yy = vertical_strain / Δt)
  double vertical_strain = 0;    // Δε_yy over the step (compression positive)
  double residual = 0;           // σ_yy - p after the step, Pa
  int evaluations = 0;           // trial advances
};

// Compression-positive rate of simple shear u_x = γ̇ y with vertical strain rate ε̇_yy.
Eigen::Matrix3d simple_shear_strain_rate(double shear_rate, double vertical_strain_rate = 0.0);

// One step of Δt from `start` at γ̇ with σ_yy = p to |R| <= relative_tolerance · p (or until the
// bracket cannot shrink: the residual is then the best reached; the caller checks it).
// `guess` is the first trial Δε_yy (the previous step's). Throws core::NumericalFailure (naming
// `step`) when no admissible Δε_yy (ν in [0.05, ν_c)) brackets the root.
// Drained (drainage_resistance r = η0 H² / κ > 0, Pa s): p is the total normal stress, shared by
// the grains and the excess pore pressure u = r ε̇_yy that drives the liquid out over the
// drainage length H (lumped Darcy outflow, ε̇_yy = u κ / (η0 H²)), so R = σ_yy + r Δε_yy/Δt - p:
// backward Euler in u, stable at any Δt.
NormalStressStep constant_normal_stress_step(const continuum::MultiRegimePoint& point,
                                             const continuum::PointState& start, double shear_rate,
                                             double dt, double normal_stress, double guess,
                                             double relative_tolerance, long step,
                                             double drainage_resistance = 0.0);

// The step of Δt as above, split into two half steps (each again up to `max_splits` levels) when
// no Δε_yy meets the tolerance: R(Δε_yy) jumps by ~STOL |Δσ_FC| where the force-chain
// integrator's error control changes its number of sub-steps (Sloan et al. 2001), and a root
// sitting in such a jump cannot be reached; halving the strain increment moves the jump. The
// result is the state after the full Δt, with vertical_strain the sum of the parts.
NormalStressStep advance_at_normal_stress(const continuum::MultiRegimePoint& point,
                                          const continuum::PointState& start, double shear_rate,
                                          double dt, double normal_stress, double guess,
                                          double relative_tolerance, long step, int max_splits = 8,
                                          double drainage_resistance = 0.0);

}  // namespace granflow::rev
