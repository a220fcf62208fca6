// Radial distribution function at contact, Torquato (1995), Phys. Rev. E 51, 3170:
//   g0(ν) = (1 - ν/2) / (1 - ν)³                                  for ν ≤ ν_f = 0.49,
//   g0(ν) = (1 - ν_f/2) / (1 - ν_f)³ · (ν_c - ν_f) / (ν_c - ν)     for ν_f < ν < ν_c,
// i.e. Carnahan-Starling on the fluid branch (up to freezing ν_f) and a simple pole at the
// random-close-packing (jamming) fraction ν_c on the metastable branch; continuous at ν_f.
// Precondition: ν_c > ν_f (checked by maximum_solid_fraction()).
#pragma once

#include "continuum/model/g0_carnahan_starling.hpp"

namespace granflow::model {

inline constexpr double torquato_freezing_fraction = 0.49;  // ν_f of Torquato (1995)

inline double g0_torquato(double solid_fraction, double jamming_fraction) {
  constexpr double nu_f = torquato_freezing_fraction;
  if (solid_fraction <= nu_f) return g0_carnahan_starling(solid_fraction);
  // g0_CS(ν_f) = (1 - 0.245) / 0.51³ = 5.6910..., folded at compile time.
  constexpr double g0_at_freezing =
      (1.0 - 0.5 * nu_f) / ((1.0 - nu_f) * (1.0 - nu_f) * (1.0 - nu_f));
  return g0_at_freezing * (jamming_fraction - nu_f) / (jamming_fraction - solid_fraction);
}

}  // namespace granflow::model
