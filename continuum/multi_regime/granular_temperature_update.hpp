// Local update of the granular temperature T over one step, for the energy balance of
// docs/model/multi_regime.md §3 (seed Eq. 21) at a homogeneous material point (no flux divergence):
//
//   (3/2) ρ_p ν dT/dt = σ_COL : D - Γ - Λ
//
// With s = T^½, p_COL = ρ_p f1 s², collisional shear viscosity ρ_p d f2 s, Γ = ρ_p f3 s³ / L and
// Λ = 54 ν η0 R_diss s² / d², the balance becomes a Riccati equation in s,
//
//   ds/dt = a - c s - b s²,   a = 2 d f2 (D':D') / (3ν),  b = f3 / (3 ν L),
//                              c = [f1 tr D + 54 ν η0 R_diss / (ρ_p d²)] / (3ν),
//
// (tension-positive D = -ε̇: tr D > 0 is expansion, which cools; compaction heats;
// docs/model/conventions.md). With a, b, c frozen
// over the step it has the exact solution used below: it stays non-negative and converges to the
// root s* = (-c + sqrt(c² + 4ab)) / (2b) for any step size, which is what "stable for any time step
// the mechanics allows" requires (docs/model/multi_regime.md §3). Coefficients are re-evaluated
// each step.
#pragma once

#include <algorithm>
#include <cmath>

namespace granflow::continuum {

struct RiccatiCoefficients {
  double a = 0;  // production (shear work), m/s²
  double b = 0;  // collisional dissipation, 1/m
  double c = 0;  // liquid dissipation Λ and volumetric work, 1/s
};

// Steady root s* >= 0 of a - c s - b s² = 0.
inline double steady_sqrt_temperature(const RiccatiCoefficients& k) {
  if (k.b > 0) {
    const double disc = std::sqrt(k.c * k.c + 4 * k.a * k.b);
    // numerically stable form of (-c + disc)/(2b) = 2a/(c + disc)
    if (k.c >= 0) return (k.c + disc) > 0 ? 2 * k.a / (k.c + disc) : 0.0;
    return (-k.c + disc) / (2 * k.b);
  }
  if (k.c > 0) return k.a / k.c;
  return INFINITY;  // no sink: grows without bound
}

// Explicit (forward Euler) stability limit of the same equation at s: 2 / |d(ds/dt)/ds|.
inline double explicit_step_limit(const RiccatiCoefficients& k, double s) {
  const double slope = std::abs(k.c + 2 * k.b * s);
  return slope > 0 ? 2.0 / slope : INFINITY;
}

// Exact solution of ds/dt = a - c s - b s² from s0 >= 0 over dt, with a >= 0, b >= 0.
inline double advance_sqrt_temperature(double s0, const RiccatiCoefficients& k, double dt) {
  s0 = std::max(s0, 0.0);
  if (k.b > 0) {
    // roots s+ >= 0 >= s- (their product is -a/b <= 0)
    // s± as in steady_sqrt_temperature, from one square root: with w = c + disc (c >= 0),
    // s+ = 2a/w and s- = -w/(2b); with w = disc - c (c < 0), s+ = w/(2b) and s- = -2a/w
    const double disc = std::sqrt(k.c * k.c + 4 * k.a * k.b);
    double s_plus, s_minus;
    if (k.c >= 0) {
      const double w = k.c + disc;
      s_plus = w > 0 ? 2 * k.a / w : 0.0;
      s_minus = -w / (2 * k.b);
    } else {
      const double w = disc - k.c;
      s_plus = w / (2 * k.b);
      s_minus = -2 * k.a / w;
    }
    // the decay rate b (s+ - s-) = disc (sqrt(c² + 4ab)) itself: exp(-rate dt) does not wait
    // for the divisions of s±
    const double rate = disc;
    if (rate <= 0) {
      // double root s+ = s- = 0 (a = 0, c = 0): ds/dt = -b s²
      return s0 / (1 + k.b * s0 * dt);
    }
    // (s - s+)/(s - s-) = ratio = u/v, u = (s0 - s+) exp(-rate dt), v = s0 - s- (> 0 unless
    // s0 = s- = 0: then s = s+), so s = (s+ - ratio s-)/(1 - ratio) = (s+ v - u s-)/(v - u)
    // with v - u > 0 (s0 - s+ < v, exp <= 1): one division
    const double v = s0 - s_minus;
    if (!(v > 0) || !std::isfinite(v)) return s_plus;
    const double u = (s0 - s_plus) * std::exp(-rate * dt);
    const double s = (s_plus * v - u * s_minus) / (v - u);
    return std::max(s, 0.0);
  }
  if (k.c != 0) {
    // linear: ds/dt = a - c s
    const double s_star = k.a / k.c;
    const double s = s_star + (s0 - s_star) * std::exp(-k.c * dt);
    return std::max(s, 0.0);
  }
  return s0 + k.a * dt;
}

}  // namespace granflow::continuum
