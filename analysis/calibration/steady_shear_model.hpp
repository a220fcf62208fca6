// Forward model of the calibration and of the pairs: the steady state of the continuum REV simple
// shear (rev/simple_shear.hpp) at an imposed shear rate γ̇ and an imposed normal stress p on the
// grains (constant_pressure), solved algebraically instead of by time stepping. Two models:
//  - kinetic theory alone (force chains off): p = p_COL, described first below;
//  - the in-parallel steady state (force chains on, docs/model/steady_state.md): the force chains
//    sit on their critical state and share p with the collisions, p = p_FC(ν) + p_COL(ν, T).
//
// Kinetic theory alone.
// At steady homogeneous simple shear the energy balance of docs/model/multi_regime.md §3 (seed Eq.
// 21) reduces to production = dissipation, with s = T^½ (granular_temperature_update.hpp, divided
// by ρ_p s):
//
//     d f2(ν) γ̇² = f3(ν) s³ / (d max(s, a)) + λ s,   λ = f_Λ Λ(ν, T = 1) / ρ_p,
//
// where a = c_L [2J/(15(1-ε²))]^½ d γ̇ is Jenkins' correlation speed (a = 0 for L = d) and f_Λ a
// calibration factor on Λ (1: the model as written). The right-hand side increases with s, so s(ν)
// is unique: the root of a quadratic for s ≥ a, of a monotone cubic (Newton from s = a) below.
// The imposed stress then fixes ν through p_COL(ν) = ρ_p f1(ν) s(ν)² = p on the dense branch
// (ν above the minimum of p_COL(ν), the branch the REV time integration relaxes to), by bisection.
// μ = (ρ_p d f2 s γ̇ + η(ν) γ̇) / p with the liquid term only when the liquid is on.
// Dry with L = d this is the closed form of docs/model/closures.md: T = (f2/f3) d² γ̇², μ = sqrt(f2
// f3)/f1.
//
// In parallel (seed §3.1: at steady state the force chains are on their critical state). The
// skeleton carries p_FC(ν) (critical_state_pressure below), the collisions p_COL(ν, s(ν)), and
//     p_FC(ν) + ρ_p f1(ν) s(ν)² = p                                   (shared normal stress)
// is solved for ν by bisection on the dense branch as above. The energy balance keeps the seed's
// form (only σ_COL : D produces T; the force chains dissipate their own work, seed Eq. 21-22),
// optionally with a production by the contacts α_FC τ_FC γ̇ (granflow's own, off by default):
//     d f2 γ̇² + W/s = f3 s³ / (d max(s, a)) + λ s,   W = α_FC μ_FC p_FC γ̇ / ρ_p,
// whose left side falls and right side rises with s: one root, by safeguarded Newton.
// μ = (μ_FC p_FC + ρ_p d f2 s γ̇ + η(ν) γ̇) / p, μ_FC rate independent unless friction_rise > 0
// (ModelFactors). As γ̇ -> 0, T -> 0 and the state tends to the
// critical state of the skeleton: e = e_cs(p), μ = μ_FC.
//
// Why not rev::run_simple_shear inside the fit: it time-steps to a relative change of 1e-10 per
// unit strain, thousands of steps per point and per Jacobian column; its steady state satisfies
// the same two equations, and tests/calibration checks the two agree to 1e-6.
#pragma once

#include <string>

#include "continuum/model/force_chains/force_chain_parameters.hpp"
#include "continuum/multi_regime/multi_regime_point.hpp"

namespace granflow::calibration {

// Factors the calibration may fit that have no key in the model sections (applied here, at the
// call site; 1 = the model as written).
struct ModelFactors {
  double fluctuation_dissipation = 1.0;  // f_Λ, multiplies Λ (liquid.fluctuation_dissipation on)
  // α_FC: fraction of the force chains' shear work τ_FC γ̇ fed to the granular temperature
  // (steady.contact_production; granflow's own, 0 = the seed's model, where only σ_COL : D
  // produces T).
  double contact_production = 0.0;
  // Rise of the force chains' friction with the inertial number (steady.friction_rise,
  // steady.friction_rise_I0; granflow's own extension, 0 = the seed's rate-independent skeleton):
  //   μ_FC(X) = M(θ=0)/√3 + Δμ_FC / (1 + I_0/X),  X = I = γ̇ d / sqrt(p/ρ_p) of the imposed p,
  // the form of the μ(I) law of GDR MiDi (2004) and Jop, Forterre & Pouliquen (2006) applied to
  // the contact network alone.
  double friction_rise = 0.0;
  double friction_rise_I0 = 0.3;
  // Immersed: the rise is driven by the mixed number X = sqrt(I² + J/α) = sqrt(K/α) with
  // K = J + α I² (Trulsson, Andreotti & Claudin 2012; α = liquid.trulsson_alpha), X = I dry.
  double mixed_number_alpha = 0.6;
  // a_J: viscous dilatancy of the skeleton's critical state (steady.viscous_dilatancy;
  // granflow's own extension after Boyer, Guazzelli & Pouliquen 2011, φ(J) = φ_m/(1 + √J), i.e.
  // e(J) = e_m + √J/φ_m): e_Γ -> e_Γ + a_J √J with J = η0 γ̇/p of the imposed condition. 0 = the
  // seed's critical state, which does not see the liquid.
  double viscous_dilatancy = 0.0;
  // Stress state of the skeleton on its critical state in simple shear (steady.skeleton_stress):
  // false (`lode_zero`): σ_xx = σ_yy = σ_zz = p_FC, τ_FC/σ_yy = M(θ=0)/√3 (closed form, fast);
  // true (`force_chain_model`): the state the force-chain model itself reaches in simple shear
  // (skeleton_simple_shear_state), which the time-stepped REV reaches too.
  bool skeleton_from_model = false;
};

// The force-chain model's own critical state in simple shear: integrated at constant volume on
// the critical state line until its stress is stationary (to 1e-10 per unit strain). The ratios
// depend on the shape parameters only (the model is rate independent and its steady stress scales
// with p), so the result is cached per parameter set.
struct SkeletonShearState {
  double friction = 0;        // τ_FC / σ_yy,FC
  double pressure_ratio = 1;  // p_FC / σ_yy,FC (p_FC = tr σ_FC / 3)
  double cos3theta = 0;       // Lode angle of σ_FC (diagnostics)
  double strain = 0;          // shear strain integrated
};
SkeletonShearState skeleton_simple_shear_state(const model::force_chains::ForceChainParameters& p);

struct SteadyShearState {
  bool ok = false;                  // false: no steady state carries p (message in `why`)
  const char* why = "";             // static text
  double solid_fraction = 0;        // ν
  double granular_temperature = 0;  // T, m²/s²
  double scaled_temperature = 0;    // T / (d γ̇)²
  double shear_stress = 0;          // τ = τ_FC + τ_COL + τ_L, Pa
  double normal_stress = 0;    // σ_yy = σ_yy,FC + σ_yy,IC + p_COL, Pa (the imposed p at constant
                               // pressure, the predicted one at constant volume)
  double scaled_pressure = 0;  // σ_yy / (ρ_p d² γ̇²)
  double force_chain_normal_stress = 0;       // σ_yy,FC (= p_FC on the line with lode_zero), Pa
  double collisional_pressure = 0;            // p_COL = ρ_p f1 T, Pa
  double inertial_contact_normal_stress = 0;  // σ_yy,IC = ρ_p (a_c d γ̇)² (ν_c - ν)^-m, Pa
  double force_chain_shear_stress = 0;        // τ_FC + τ_IC = μ_FC (p_FC + σ_yy,IC), Pa
  double collisional_shear_stress = 0;        // τ_COL = ρ_p d f2 T^½ γ̇, Pa
  double liquid_shear_stress = 0;             // τ_L = η(ν) γ̇, Pa
  double friction = 0;                        // μ = τ / p
  double inertial_number = 0;                 // I = γ̇ d / sqrt(p/ρ_p)
  double viscous_number = 0;                  // J = η0 γ̇ / p (0 when dry)
};

// Steady state at (γ̇, p). Requires settings.collisional (throws std::invalid_argument
// otherwise); with settings.force_chains the in-parallel state (needs λ_c > 0).
SteadyShearState steady_simple_shear(const continuum::MultiRegimeSettings& settings,
                                     const ModelFactors& factors, double shear_rate,
                                     double normal_stress);

// Steady state at (γ̇, ν), constant volume: the same two equations with ν given and the normal
// stress unknown. The shared normal stress is explicit in ν,
//     p = σ_yy,FC(ν) + ρ_p f1(ν) s(ν)²,
// except through the terms that depend on the flow's own p: the friction rise (X = I or
// sqrt(I² + J/α)), the contact work (through μ_FC) and the viscous dilatancy (J). Without them p
// is evaluated directly; with them p is the root of G(x) = ln P(ν; e^x) - x, x = ln p, where P is
// the right side above with those terms at p. P does not rise with p, so G falls strictly and
// the root is unique: bracketed by doubling steps in x, then regula falsi (Illinois) to
// |Δx| ≤ 1e-13 (relative 1e-13 in p). On the dense branch this is the constant-pressure state at
// that p (tests/calibration/test_table_protocols.cpp: σ_yy, μ, T back to 1e-11); a given ν on
// the dilute branch (below the minimum of p(ν)) has a state too, as a constant-volume DEM has.
// ok = false for ν outside (0, ν_max) or, immersed, at or above the maximum packing of η(ν).
SteadyShearState steady_simple_shear_at_solid_fraction(
    const continuum::MultiRegimeSettings& settings, const ModelFactors& factors, double shear_rate,
    double solid_fraction);

// s = T^½ solving the energy balance above at ν (exposed for tests), with an extra production
// by the contacts W = α_FC τ_FC γ̇ / ρ_p (m³/s³ per unit density; 0 without it).
double steady_sqrt_temperature_at(const continuum::MultiRegimeSettings& settings,
                                  const ModelFactors& factors, double solid_fraction,
                                  double shear_rate, double contact_work = 0.0);

// The force chains on their critical state in steady simple shear (docs/model/steady_state.md):
// the skeleton's normal stress p_FC(ν) = p_ref ((e_Γ - e)/λ_c)^(1/ξ_c) for e = 1/ν - 1 < e_Γ, 0
// otherwise (the inverse of the critical state line e_cs = e_Γ - λ_c (p/p_ref)^ξ_c), and its
// friction μ_FC = τ_FC/σ_yy,FC = M(θ = 0)/√3 (the Lade-Duncan ratio at the plane-strain,
// isochoric stress state of steady simple shear, J3 = 0).
double critical_state_pressure(const model::force_chains::ForceChainParameters& p,
                               double solid_fraction);
double critical_state_friction(const model::force_chains::ForceChainParameters& p);

// Empty, or why the force chains of `settings` can never carry load in the steady state (the
// critical state line lies beyond the jamming fraction of g0, so p_COL diverges first and the
// state is kinetic theory's at every I): for a log warning.
std::string in_parallel_caveat(const continuum::MultiRegimeSettings& settings);

}  // namespace granflow::calibration
