// Homogeneous steady simple shear of a material point (REV) at imposed shear rate γ̇, at constant
// volume (imposed void ratio) or constant normal stress (imposed p on the granular phase; e
// evolves). T is integrated in time from the energy balance (docs/model/multi_regime.md §3) until a
// steady state is detected. The closed forms of docs/model/closures.md are its first check. At
// constant normal stress with the force chains on, each step is a mixed control (ε̇_xy imposed, ε̇_xx
// = ε̇_zz = 0, ε̇_yy solved so that σ_yy = p; rev/simple_shear_mixed_control.hpp,
// docs/model/multi_regime.md §4.1).
#pragma once

#include <cmath>
#include <functional>
#include <vector>

#include "continuum/multi_regime/multi_regime_point.hpp"

namespace granflow::rev {

enum class ShearControl { constant_volume, constant_pressure };

struct SimpleShearControl {
  ShearControl control = ShearControl::constant_volume;
  double shear_rate = 10.0;           // γ̇, 1/s
  double void_ratio = 0.8;            // imposed (constant volume) or initial e
  double normal_stress = 0.0;         // imposed p on the grains (constant pressure), Pa
  double initial_temperature = 1e-6;  // T(0), m²/s²
  double time_step_factor = 0.5;      // Δt = factor × min(1/γ̇, T relaxation time)
  double steady_tolerance = 1e-10;    // relative change per unit strain of T and ν
  double max_strain = 1e4;            // stop (not steady) beyond this strain
  long max_steps = 1000000;
  // With force chains: the skeleton starts isotropic at p'0 with r_c = √3 p'0 ocr, and each
  // step's shear strain increment is at most `strain_increment`. At constant pressure p'0 is not
  // read: the skeleton starts at p'0 = p - p_COL(ν0, T0), so that σ_yy = p from the start (or
  // fluidized if p_COL(ν0, T0) >= p).
  double effective_pressure = 50e3;  // p'0, Pa (constant volume)
  double overconsolidation = 1.0;
  double strain_increment = 1e-3;  // largest Δγ per step with force chains
  // Constant pressure with force chains: |σ_yy - p| <= this × p after every step.
  double normal_stress_tolerance = 1e-12;
  // Drained (constant pressure with force chains and the liquid on, drainage_length H > 0): p is
  // the total normal stress, shared by σ_yy and the excess pore pressure u = r ε̇_yy that drives
  // the liquid in or out over H, r = η0 H² / κ(ν) (lumped Darcy flow, κ the liquid's
  // permeability closure at the start of each step; rev/simple_shear_mixed_control.hpp). 0: the
  // grains carry p alone (fully drained, or dry).
  double drainage_length = 0.0;
  // Damped height (constant pressure with force chains, drainage_length 0): the same law with a
  // constant r = height_resistance (Pa s), a viscous piston on the point's height (dry or
  // immersed; the DEM's fix drainage ... resistance R). 0: the grains carry p at every step.
  double height_resistance = 0.0;
  // A step in the shear rate: γ̇ = shear_rate up to the strain rate_step_strain, then
  // rate_step_shear_rate (the time step ends on the step's strain). Infinity: no step.
  double rate_step_strain = INFINITY;
  double rate_step_shear_rate = 0.0;
};

struct SimpleShearSeries {
  std::vector<double> time, strain, time_step, granular_temperature, void_ratio, solid_fraction,
      pressure, shear_stress, collisional_shear_stress, liquid_shear_stress, friction,
      inertial_number, force_chain_shear_stress, effective_pressure, locus_size;
  // σ_yy of the grains (σ_FC + σ_IC + σ_COL + σ_L), its σ_FC part, p_COL, ε̇_yy (compression
  // positive; 0 except at constant pressure with force chains) and the contacts' dense inertial
  // pressure p_IC (0 unless collisional.inertial_contact > 0; its shear part μ_IC p_IC is in τ).
  std::vector<double> normal_stress, force_chain_normal_stress, collisional_pressure,
      vertical_strain_rate, inertial_contact_pressure;
};

struct SimpleShearSteady {
  bool reached = false;
  double strain = 0;  // strain at which steady state was detected
  double void_ratio = 0, solid_fraction = 0, granular_temperature = 0;
  // Granular normal stress, Pa: constant volume p_COL + p'; constant pressure σ_yy (= the
  // imposed p; without force chains σ_yy = p_COL).
  double pressure = 0;
  double effective_pressure = 0, force_chain_shear_stress = 0, locus_size = 0;     // σ_FC part
  double shear_stress = 0, collisional_shear_stress = 0, liquid_shear_stress = 0;  // Pa
  double friction = 0;                                                             // μ = τ/p
  double inertial_number = 0;  // I = γ̇ d / sqrt(p/ρ_p)
  double viscous_number = 0;   // J = η0 γ̇ / p (liquid on)
  // σ_yy = σ_yy,FC + σ_yy,COL + σ_yy,L (σ_yy,COL = p_COL + 2 η_COL ε̇'_yy), Pa, and the shares of
  // τ and σ_yy carried by each term (each triple sums to 1; 0 when τ or σ_yy is 0).
  double normal_stress = 0, force_chain_normal_stress = 0, collisional_normal_stress = 0,
         liquid_normal_stress = 0;
  double share_tau_force_chains = 0, share_tau_collisional = 0, share_tau_liquid = 0;
  double share_normal_force_chains = 0, share_normal_collisional = 0, share_normal_liquid = 0;
  Eigen::Matrix3d force_chain_stress = Eigen::Matrix3d::Zero();  // σ_FC at the end, Pa
  bool fluidized = false;  // the skeleton is fluidized at the end (σ_FC = 0)
};

struct SimpleShearResult {
  SimpleShearSeries series;
  SimpleShearSteady steady;
  long steps = 0;
  double min_time_step = 0, max_time_step = 0;
  double max_explicit_ratio = 0;  // largest Δt / explicit Euler limit used
  // Mixed control (constant pressure with force chains): largest |σ_yy - p| / p after a step,
  // and the trial advances it took in all.
  double max_normal_stress_residual = 0;
  long solver_evaluations = 0;
  continuum::PointState final_state;  // the point's state after the last step
};

// Runs to steady state, filling `result` as it goes. `progress(strain)` is called now and then
// (may be empty). Throws core::NumericalFailure naming step and variable on NaN/Inf/negative T
// or when no state satisfies the imposed pressure; `result` then holds the series so far.
void run_simple_shear(const continuum::MultiRegimePoint& point, const SimpleShearControl& control,
                      SimpleShearResult& result, const std::function<void(double)>& progress = {});
SimpleShearResult run_simple_shear(const continuum::MultiRegimePoint& point,
                                   const SimpleShearControl& control);

// Largest inertial number a dry steady homogeneous shear admits with L = d,
// I(ν) = (f1 f2 / f3)^(-1/2) maximised over ν (kinetic theory has no dense steady state beyond).
struct InertialNumberBound {
  double inertial_number, solid_fraction;
};
InertialNumberBound maximum_steady_inertial_number(const model::CollisionalParameters& p);

// Solid fraction at which p_COL(ν, T) + p_IC(ν, γ̇) = p (bisection; both increase with ν; p_IC is
// the contacts' dense inertial pressure, 0 unless collisional.inertial_contact > 0).
double solid_fraction_at_pressure(const continuum::MultiRegimePoint& point, double pressure,
                                  double granular_temperature, double shear_rate);

}  // namespace granflow::rev
