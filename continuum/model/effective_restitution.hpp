// Effective coefficient of restitution ε of frictional spheres, Chialvo & Sundaresan (2013),
// Phys. Fluids 25, 070603 (their fit to DEM simple shear; the idea of folding friction into an
// effective restitution goes back to Jenkins & Zhang 2002, Phys. Fluids 14, 1228):
//   ε = e_r - (3/2) μ_p exp(-3 μ_p).
// The correction is largest at μ_p = 1/3, where it equals 1/(2e) = 0.184. ε enters only the
// collisional dissipation f3 and the correlation length; J, F and M use e_r
// (docs/model/closures.md).
#pragma once

#include <cmath>

namespace granflow::model {

inline double effective_restitution_chialvo_sundaresan(double restitution,
                                                       double particle_friction) {
  return restitution - 1.5 * particle_friction * std::exp(-3.0 * particle_friction);
}

}  // namespace granflow::model
