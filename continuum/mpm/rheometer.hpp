// The seed paper's undrained constant-volume annular rheometer (section 6, Fig. 2) with the
// double-point MPM and the multi-regime material: annulus R_in < r < R_out on the polar O-grid,
// plane strain, saturated; (i) the drained isotropic consolidation is represented by its end
// state (σ_FC = p' I, pore pressure u_w0, e0) set at t = 0; (ii) undrained, constant volume:
// v_r = 0 on both rings (both phases), inner ring fixed, outer ring v_θ = a t; (iii) v_θ held at
// v_max (reached at t = v_max / a). docs/rheometer.md.
#pragma once

#include <memory>
#include <vector>

#include "continuum/mpm/multi_regime_material.hpp"
#include "continuum/mpm/solver.hpp"

namespace granflow::mpm {

struct RheometerSpec {
  double inner_radius = 0.08, outer_radius = 0.11;  // m
  int cells_r = 8, cells_theta = 96;
  int points_per_cell = 2;             // per direction, each phase
  double void_ratio = 0.818;           // e0
  double effective_pressure = 50.0e3;  // p'0 after consolidation, Pa
  double pore_pressure = 50.0e3;       // u_w0, Pa
  double ocr = 1.0;                    // r_c / (√3 p'0)
  double initial_temperature = 0.0;    // T0, m²/s²
  double acceleration = 333.0;         // a of v_θ = a t, m/s²
  double max_velocity = 1.0;           // v_max, m/s
  continuum::MultiRegimeSettings model;
  LiquidOptions liquid;
  SolverOptions options;
};

struct Rheometer {
  std::unique_ptr<Solver> solver;
  MultiRegimeMaterial* material = nullptr;  // owned by the solver
};

// Builds the solver, fills both phases, applies the ring conditions and initializes.
Rheometer make_rheometer(const RheometerSpec& spec);

// Averages over the solid points (volume weighted; "averaged along θ and r" of the seed), with
// stresses of the solid phase σ' = σ_FC + σ_COL + σ_L, compression positive for σ_G:
struct RheometerAverages {
  double shear_stress = 0;        // τ̄ = <σ_rθ> (positive in the sense of the outer ring), Pa
  double normal_stress = 0;       // σ̄_G = <-(σ'_xx + σ'_yy + σ'_zz)/3>, Pa
  double shear_strain = 0;        // γ̄ = <γ> (accumulated engineering shear strain γ_rθ)
  double shear_rate = 0;          // <γ̇_rθ> of the last step, 1/s
  double mixture_volume = 0;      // Σ V of the solid points, m² (per m)
  double pore_pressure = 0;       // <p> over the liquid points (volume weighted), Pa
  double porosity_std = 0;        // standard deviation of n over the solid points
  double fluidized_fraction = 0;  // volume fraction of solid points with r_c below fluidization
};

// Accumulates γ_rθ per solid point from the last step's velocity gradient (call after every
// step): γ += 2 D_rθ dt.
void accumulate_shear_strain(const Solver& solver, std::vector<double>& shear_strain);
RheometerAverages rheometer_averages(const Solver& solver, const MultiRegimeMaterial& material,
                                     const std::vector<double>& shear_strain);

// Radial profiles over `bins` equal rings: θ-averaged γ and v_θ of the solid points.
void rheometer_profiles(const Solver& solver, const RheometerSpec& spec,
                        const std::vector<double>& shear_strain, int bins,
                        std::vector<double>& radius, std::vector<double>& gamma,
                        std::vector<double>& velocity);

}  // namespace granflow::mpm
