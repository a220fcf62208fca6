// The contact network of a sample: coordination with and without rattlers, the non-rattler
// fraction and the fabric, from the list of touching pairs (pure, testable without LIGGGHTS;
// the driver gathers the pairs from the pair style's neighbour list, driver/contact_probe.cpp).
//
//   Z = 2 N_c / N over all particles (as shear_sample.hpp);
//   rattlers: particles with fewer than 2 contacts, removed repeatedly with their contacts until
//     every particle left has >= 2 (a particle with one contact carries no force at rest;
//     [Agnolin2007]: x0, z* = 2 N_c* / N*);
//   Z* = 2 N_c* / N* over the N* non-rattlers and their N_c* contacts, x_nr = N*/N;
//   fabric F_ab = <n_a n_b> over the non-rattler contacts (n the unit branch vector), reported
//     trace-free, F'_ab = F_ab - δ_ab/3 ([Satake1982]; [Radjai1998]), with its scalar
//     anisotropy a = sqrt(3/2 F':F') (0 isotropic; uniaxial F' = diag(2,-1,-1) a/3 has norm a).
#pragma once

#include <array>
#include <vector>

namespace granflow::dem {

struct ContactPair {
  long i = 0, j = 0;          // particle indices in [0, particles)
  std::array<double, 3> n{};  // unit branch vector from i to j
};

struct NetworkState {
  double coordination = 0.0;             // Z
  double coordination_nonrattler = 0.0;  // Z* (0 when no particle is left)
  double nonrattler_fraction = 0.0;      // N*/N
  std::array<double, 6> fabric{};        // F' (xx yy zz xy xz yz), trace-free
  double anisotropy = 0.0;               // sqrt(3/2 F':F')
  double contacts = 0.0;                 // N_c
};

NetworkState network_state(long particles, const std::vector<ContactPair>& contacts);

}  // namespace granflow::dem
