// Correlation length that grows toward jamming, independent of T:
//   L / d = 1 + c_L (ν − ν_L) / (ν_c − ν)^n   for ν_L < ν < ν_c,   L / d = 1 for ν ≤ ν_L,
// so the collisional dissipation Γ = ρ_p f3 T^{3/2} / L falls toward jamming and the steady
// temperature T / (d γ̇)² = (L/d) f2/f3 (no liquid, no contact work) rises with ν, as it does in
// constant-volume DEM of rigid spheres (about 5x over ν 0.50 … 0.585), where kinetic theory with
// L = d keeps f2/f3 nearly constant (G cancels in the ratio).
//
// Extended kinetic theory (Jenkins 2006, 2007; Berzi & Vescovi 2015) attributes the slower
// dissipation of dense flows to velocity correlations over a length L that grows toward the
// singularity of the flow's functions; Berzi & Vescovi argue that L diverges at the jamming
// fraction while the kinetic-theory coefficients stay finite there. The form above (an onset ν_L,
// by default the freezing fraction 0.49 of hard spheres, and a power n of the distance to ν_c,
// by default 3/2) is granflow's own parametrisation of that idea, made so that the steady state
// at constant volume has a closed form; it is not a transcription of a published formula. c_L is
// `collisional.correlation_length_constant`, ν_L `collisional.correlation_length_onset`, n
// `collisional.correlation_length_exponent` and ν_c the jamming fraction of g0
// (`collisional.jamming_fraction`).
#pragma once

#include <cmath>

namespace granflow::model {

// L / d ≥ 1 at 0 < ν < ν_c (the caller checks the range; at ν ≥ ν_c there is no steady state).
inline double correlation_length_ratio_toward_jamming(double constant, double onset,
                                                      double exponent, double jamming_fraction,
                                                      double nu) {
  if (!(nu > onset)) return 1.0;
  return 1.0 + constant * (nu - onset) / std::pow(jamming_fraction - nu, exponent);
}

}  // namespace granflow::model
