// granflow-dem: the touching pairs of the whole sample, gathered from the pair style's half
// neighbour list of every rank (each pair once), with the contact network they form
// (extraction/contact_network.hpp) and the normal elastic energy stored in them:
//   hertz: U = (8/15) E* sqrt(R*) δ^(5/2), E* = E / (2 (1 - ν²)), R* = r_i r_j / (r_i + r_j)
//          (the integral of LIGGGHTS' F_n = (4/3) E* sqrt(R* δ) δ; Johnson 1985, ch. 4);
//   hooke: U = k_n δ² / 2.
// The tangential springs' energy is left out (it vanishes for frictionless spheres and is a
// fraction of the normal one otherwise). Collective: every rank gets the same result.
#pragma once

#include "dem_coupling/extraction/contact_network.hpp"

namespace LAMMPS_NS {
class LAMMPS;
}

namespace granflow::dem {

struct ElasticLaw {
  bool hooke = false;
  double effective_modulus = 0.0;  // hertz: E*, Pa
  double normal_stiffness = 0.0;   // hooke: k_n, N/m
};

struct ContactProbe {
  NetworkState network;
  double elastic_energy = 0.0;  // J, normal springs of every touching pair
  double mean_overlap = 0.0;    // <δ> over the touching pairs, m
};

ContactProbe probe_contacts(void* handle, const LAMMPS_NS::LAMMPS& lmp, const ElasticLaw& law);

}  // namespace granflow::dem
