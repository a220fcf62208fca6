// Dimensionless resistance R_diss(ν) of the viscous dissipation of the grains' fluctuation
// energy by the interstitial fluid, Koch & Sangani (1999), J. Fluid Mech. 400, 229, as used by
// Garzó, Tenneti, Subramaniam & Hrenya (2012), J. Fluid Mech. 712, 129 (GTSH, Eq. 8.1) and in
// MFiX (model/kintheory_mod.f, function G_gtsh; calc_mu_s.f case GTSH_2012):
//   R_diss = 1 + 3 (ν/2)^{1/2} + (135/64) ν ln ν + 11.26 ν (1 - 5.1ν + 16.57ν² - 21.77ν³)
//            - ν g0 ln ε_m,   ε_m = 0.01 (lubrication cut-off, MFiX `EpM`).
// Λ = 54 ν η0 R_diss T / d² = 3 (18 η0 ν R_diss / d²) T: Stokes drag 3π η0 d per grain acting on
// the fluctuation velocity, so R_diss -> 1 as ν -> 0. MFiX adds Re_T K(ν) (inertial correction)
// with K set to 0 "for compatibility with GTSH (2012)"; it is not included here. One MFiX version
// switches to the dilute form 1 + 3(ν/2)^{1/2} for ν ≤ 0.1 (discontinuous); the full
// expression is used here for all ν.
#pragma once

#include <cmath>

namespace granflow::model {

inline constexpr double lubrication_cutoff = 0.01;  // ε_m of GTSH (2012) / MFiX EpM

inline double dissipation_resistance_koch_sangani(double solid_fraction, double g0) {
  const double nu = solid_fraction;
  if (nu <= 0.0) return 1.0;                              // limit ν ln ν -> 0
  constexpr double minus_log_cutoff = 4.605170185988091;  // -ln(0.01)
  return 1.0 + 3.0 * std::sqrt(0.5 * nu) + (135.0 / 64.0) * nu * std::log(nu) +
         11.26 * nu * (1.0 - nu * (5.1 - nu * (16.57 - 21.77 * nu))) + nu * g0 * minus_log_cutoff;
}

}  // namespace granflow::model
