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
  // Diagnostics of a non-axisymmetric (numerical) disturbance: the flow of the annulus is
  // axisymmetric, so v_r and the spread of p around its ring means stay small.
  double pore_pressure_std = 0;    // rms of p about its mean over each ring of cells, Pa
  double radial_velocity_rms = 0;  // rms of the solid v_r, m/s
};

// Accumulates γ_rθ per solid point from the last step's velocity gradient (call after every
// step): γ += 2 D_rθ dt.
void accumulate_shear_strain(const Solver& solver, std::vector<double>& shear_strain);
RheometerAverages rheometer_averages(const Solver& solver, const MultiRegimeMaterial& material,
                                     const std::vector<double>& shear_strain);

// θ-averaged radial profiles of the solid points over `bins` equal rings (volume weighted);
// with bins = 3 the rings are the inner, middle and outer crowns of docs/rheometer.md.
struct RheometerProfiles {
  std::vector<double> radius;              // bin centre, m
  std::vector<double> shear_strain;        // accumulated γ_rθ
  std::vector<double> velocity;            // v_θ of the solid, m/s
  std::vector<double> shear_stress;        // σ'_rθ of the solid phase, Pa
  std::vector<double> porosity;            // n
  std::vector<double> locus_size;          // r_c, Pa
  std::vector<double> fluidized_fraction;  // volume fraction with r_c below fluidization
};
RheometerProfiles rheometer_profiles(const Solver& solver, const MultiRegimeMaterial& material,
                                     const RheometerSpec& spec,
                                     const std::vector<double>& shear_strain, int bins);

// Inertia of the imposed ring acceleration against the strength of the skeleton (docs/
// rheometer.md, "Where strain starts"). Torque balance of the annulus, d(τ r²)/dr = ρ r² a_θ(r),
// with the mixture moving together (drag relaxation ≪ 1 ms) and the acceleration profile of
// uniform shear a_θ = a (r − R_in)/(R_out − R_in):
//   τ_out R_out² − τ_in R_in² = ρ a [(R_out⁴ − R_in⁴)/4 − R_in (R_out³ − R_in³)/3] / (R_out − R_in)
// so the inner ring carries the larger shear stress (the quasi-static τ ∝ 1/r² picture of the
// seed) only while τ_in exceeds
//   τ* = ρ a [(R_out⁴ − R_in⁴)/4 − R_in (R_out³ − R_in³)/3] / ((R_out − R_in)(R_out² − R_in²)).
// Returns τ* in Pa for the mixture density ρ = ν ρ_p + (1 − ν) ρ_L at e0.
double inertial_shear_stress(const RheometerSpec& spec);

}  // namespace granflow::mpm
