// Forward model of the calibration: the steady state of the continuum REV simple shear
// (rev/simple_shear.hpp) at an imposed shear rate γ̇ and an imposed normal stress p on the grains
// (constant_pressure, no force chains), solved algebraically instead of by time stepping.
//
// At steady homogeneous simple shear the energy balance of model.md §5 (seed Eq. 21) reduces to
// production = dissipation, with s = T^½ (granular_temperature_update.hpp, divided by ρ_p s):
//
//     d f2(ν) γ̇² = f3(ν) s³ / (d max(s, a)) + λ s,   λ = f_Λ Λ(ν, T = 1) / ρ_p,
//
// where a = c_L [2J/(15(1-ε²))]^½ d γ̇ is Jenkins' correlation speed (a = 0 for L = d) and f_Λ a
// calibration factor on Λ (1: the model as written). The right-hand side increases with s, so s(ν)
// is unique: the root of a quadratic for s ≥ a, of a monotone cubic (Newton from s = a) below.
// The imposed stress then fixes ν through p_COL(ν) = ρ_p f1(ν) s(ν)² = p on the dense branch
// (ν above the minimum of p_COL(ν), the branch the REV time integration relaxes to), by bisection.
// μ = (ρ_p d f2 s γ̇ + η(ν) γ̇) / p with the liquid term only when the liquid is on.
// Dry with L = d this is the closed form of model.md §3: T = (f2/f3) d² γ̇², μ = sqrt(f2 f3)/f1.
//
// Why not rev::run_simple_shear inside the fit: it time-steps to a relative change of 1e-10 per
// unit strain, thousands of steps per point and per Jacobian column; its steady state satisfies
// the same two equations, and tests/calibration checks the two agree to 1e-6.
#pragma once

#include "continuum/multi_regime/multi_regime_point.hpp"

namespace granflow::calibration {

// Factors the calibration may fit that have no key in the model sections (applied here, at the
// call site; 1 = the model as written).
struct ModelFactors {
  double fluctuation_dissipation = 1.0;  // f_Λ, multiplies Λ (liquid.fluctuation_dissipation on)
};

struct SteadyShearState {
  bool ok = false;                  // false: no steady state carries p (message in `why`)
  const char* why = "";             // static text
  double solid_fraction = 0;        // ν
  double granular_temperature = 0;  // T, m²/s²
  double scaled_temperature = 0;    // T / (d γ̇)²
  double shear_stress = 0;          // τ = τ_COL + τ_L, Pa
  double friction = 0;              // μ = τ / p
  double inertial_number = 0;       // I = γ̇ d / sqrt(p/ρ_p)
  double viscous_number = 0;        // J = η0 γ̇ / p (0 when dry)
};

// Steady state at (γ̇, p). Requires settings.collisional and no force chains (throws
// std::invalid_argument otherwise).
SteadyShearState steady_simple_shear(const continuum::MultiRegimeSettings& settings,
                                     const ModelFactors& factors, double shear_rate,
                                     double normal_stress);

// s = T^½ solving the energy balance above at ν (exposed for tests).
double steady_sqrt_temperature_at(const continuum::MultiRegimeSettings& settings,
                                  const ModelFactors& factors, double solid_fraction,
                                  double shear_rate);

}  // namespace granflow::calibration
