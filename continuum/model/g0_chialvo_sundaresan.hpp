// Radial distribution function at contact, Chialvo & Sundaresan (2013), Phys. Fluids 25, 070603,
// fitted to DEM simple shear of frictional spheres:
//   g0(ν) = (1 - ν/2) / (1 - ν)³ + 0.58 ν² / (ν_c - ν)^{3/2},
// Carnahan-Starling plus a term singular at the friction-dependent jamming fraction ν_c.
#pragma once

#include <cmath>

#include "continuum/model/g0_carnahan_starling.hpp"

namespace granflow::model {

inline constexpr double chialvo_sundaresan_g0_amplitude = 0.58;  // fitted constant of CS 2013

inline double g0_chialvo_sundaresan(double solid_fraction, double jamming_fraction) {
  const double distance = jamming_fraction - solid_fraction;  // ν_c - ν > 0 (guarded by caller)
  return g0_carnahan_starling(solid_fraction) + chialvo_sundaresan_g0_amplitude * solid_fraction *
                                                    solid_fraction /
                                                    (distance * std::sqrt(distance));
}

}  // namespace granflow::model
