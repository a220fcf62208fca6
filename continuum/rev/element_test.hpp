// Laboratory element tests of one multi-regime material point (REV), all terms in parallel
// (σ = σ_FC + σ_COL + σ_L, docs/model/multi_regime.md): axisymmetric triaxial compression at
// imposed deviatoric strain rate ε̇_d with the total radial (cell) stress held, drained, undrained
// or consolidating; and isotropic compression at imposed volumetric strain rate.
// docs/model/multi_regime.md.
//
// Sign convention: compression positive (docs/model/multi_regime.md §1). Axis 0 is the axial
// direction. ε_d = (2/3)(ε_a - ε_r), ε_v = ε_a + 2 ε_r, q = σ_a - σ_r, p = tr σ / 3, p' = p_FC.
//
// Pore pressure (the liquid carries u_w I in σ_L, seed Eq. 27). Grains incompressible, liquid of
// bulk modulus K_w, porosity n: the liquid's volume change equals the mixture's, so
//   undrained:     Δu_w = (K_w / n) Δε_v                  (ε_v of the mixture = of the skeleton)
//   consolidating: Δu_w = (K_w / n) [Δε_v - Δt k (u_w,new - u_b)],  k = κ / (η0 H²)
//                  (lumped Darcy outflow through a drainage length H towards the back pressure u_b)
//   drained:       u_w = u_b.
// The radial stress condition σ_r(Δε_v) = σ_cell is solved for the one unknown Δε_v per step by a
// bracketed Illinois iteration on the full point update, so u_w is implicit and the real
// K_w = 2.2 GPa (K_w/n ≈ 5 GPa against a skeleton of MPa) is stable for any step.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "continuum/multi_regime/multi_regime_point.hpp"

namespace granflow::rev {

enum class Drainage { drained, undrained, consolidating };

struct TriaxialStage {
  Drainage drainage = Drainage::undrained;
  double deviatoric_strain_rate = 1.0;  // ε̇_d, 1/s (>= 0)
  double duration = 0.1;                // s
  int steps = 1000;                     // time steps
  double first_time_step = 0;           // > 0: steps grow geometrically from it (sum = duration)
  double drainage_length = 0.05;        // H, m (consolidating only)
  // Run on until steady (equal steps only): after `steps`, the stage goes on with the same Δt
  // until the drifts of T and q over the last `steady_window` steps, |d ln T/dε_d| and
  // |d ln |q|/dε_d|, are both ≤ steady_tolerance, or until `max_steps`. 0: stop at `steps`.
  double steady_tolerance = 0;  // per unit ε_d
  int steady_window = 0;        // steps of the drift window (0: max(1, steps/10))
  int max_steps = 0;            // steps at most when running on (>= steps)
};

struct TriaxialControl {
  double void_ratio = 0.70;           // e0
  double effective_pressure = 50e3;   // p'0 (isotropic σ_FC), Pa
  double overconsolidation = 1.0;     // r_c0 / (√3 p'0) >= 1
  double pore_pressure = 50e3;        // u_w0 = back pressure u_b, Pa
  double initial_temperature = 0.0;   // T0, m²/s²
  std::vector<TriaxialStage> stages;  // run one after the other
  double stress_tolerance = 1e-9;     // |σ_r - σ_cell| ≤ tol · σ_cell
};

struct ElementSeries {
  std::vector<double> time, deviatoric_strain, volumetric_strain, axial_strain, q, q_force_chain,
      q_collisional, q_liquid, mean_stress, effective_pressure, collisional_pressure, pore_pressure,
      granular_temperature, locus_size, void_ratio, fluidized, yield_value, stage,
      collisional_dissipation, liquid_dissipation;  // Γ, Λ (W/m³)
};

// The end of one stage and, when it ran on until steady, its drifts there.
struct StageEnd {
  std::size_t last = 0;          // series index of the stage's last step
  bool steady_checked = false;   // the stage had a steady_tolerance
  bool steady = false;           // both drifts ≤ steady_tolerance at `last`
  double drift_temperature = 0;  // d ln T / dε_d over the window ending at `last`
  double drift_q = 0;            // d ln |q| / dε_d over the same window
  int extra_steps = 0;           // steps run beyond the stage's `steps`
};

struct ElementResult {
  ElementSeries series;
  long steps = 0;
  long solver_evaluations = 0;        // point updates spent on the radial-stress condition
  double max_radial_residual = 0;     // largest |σ_r - σ_cell| accepted, Pa
  double liquefaction_strain = -1;    // ε_d where σ_FC first vanished (-1: never)
  double resolidification_time = -1;  // time where a fluidized skeleton became solid again
  std::vector<StageEnd> stage_ends;   // one per stage run (fewer when interrupted)
};

// Runs the stages from the isotropic initial state (σ_FC = p'0 I, u_w = u_w0, cell pressure
// σ_cell = p'0 + u_w0 + p_COL(ν0, T0)). Throws core::NumericalFailure (step, "REV point",
// variable) on NaN/Inf, negative T or r_c, or when no Δε_v satisfies the radial condition;
// `result` then holds the series so far. `progress(fraction)` now and then.
void run_triaxial(const continuum::MultiRegimePoint& point, const TriaxialControl& control,
                  ElementResult& result, const std::function<void(double)>& progress = {});
ElementResult run_triaxial(const continuum::MultiRegimePoint& point,
                           const TriaxialControl& control);

struct IsotropicControl {
  double void_ratio = 0.8;
  double effective_pressure = 10e3;  // p'0, Pa
  double overconsolidation = 1.0;
  double pore_pressure = 0.0;             // u_w (drained), Pa
  double volumetric_strain_rate = 1e-3;   // ε̇_v, 1/s (> 0 compaction)
  double final_volumetric_strain = 0.02;  // stop at this ε_v
  int steps = 200;
};

// Drained isotropic compression at imposed ε̇_v (Δε = Δε_v/3 I, u_w constant).
ElementResult run_isotropic_compression(const continuum::MultiRegimePoint& point,
                                        const IsotropicControl& control);

}  // namespace granflow::rev
