// The owned spheres of this rank as the extraction harness reads them (extraction/
// shear_sample.hpp): positions, velocities, masses and radii straight from LIGGGHTS' atom arrays
// (lammps_extract_atom; valid until the next run or re-neighbouring).
#pragma once

#include "dem_coupling/extraction/shear_sample.hpp"
#include "library.h"

namespace granflow::dem {

inline ParticleView owned_particles(void* handle) {
  const int nlocal = *static_cast<int*>(lammps_extract_global(handle, const_cast<char*>("nlocal")));
  auto** x = static_cast<double**>(lammps_extract_atom(handle, const_cast<char*>("x")));
  auto** v = static_cast<double**>(lammps_extract_atom(handle, const_cast<char*>("v")));
  return {nlocal, nlocal ? x[0] : nullptr, nlocal ? v[0] : nullptr,
          static_cast<double*>(lammps_extract_atom(handle, const_cast<char*>("rmass"))),
          static_cast<double*>(lammps_extract_atom(handle, const_cast<char*>("radius")))};
}

}  // namespace granflow::dem
