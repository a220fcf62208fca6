#include "dem_coupling/driver/sample_parts.hpp"

#include <mpi.h>

#include <array>
#include <cmath>
#include <cstdlib>

#include "dem_coupling/fixes/fix_fluid_le.hpp"
#include "force.h"
#include "lammps.h"
#include "library.h"
#include "lmptype.h"
#include "neigh_list.h"
#include "pair.h"

namespace granflow::dem {
namespace {

// Entry `offset` (0-based, dem::fluid_le_vector; f_gf_fluid[offset + 1] in a deck) of the fix's
// global vector; collective (the fix reduces its sums over ranks), so every rank calls it. The
// value is malloc'ed by library.cpp.
double fluid_entry(void* handle, int offset) {
  double* value = static_cast<double*>(lammps_extract_fix(handle, "gf_fluid", 0, 1, offset, 0));
  const double v = *value;
  std::free(value);
  return v;
}

}  // namespace

FluidStress fluid_stress(void* handle, const ShearSample& s) {
  FluidStress f;
  namespace v = fluid_le_vector;
  f.lubrication = -(fluid_entry(handle, v::lubrication_normal + v::xy) +
                    fluid_entry(handle, v::lubrication_tangential + v::xy));
  f.drag = -fluid_entry(handle, v::drag + v::xy);
  f.kinetic = -s.kinetic_stress[3];
  f.contact = -s.virial_stress[3] - f.lubrication - f.drag;
  f.lubricated_pairs = fluid_entry(handle, v::lubricated_pairs);
  for (int k = 0; k < 3; ++k)  // xx yy zz: the effective (solid) p' = p - pressure
    f.pressure +=
        (fluid_entry(handle, v::lubrication_normal + k) +
         fluid_entry(handle, v::lubrication_tangential + k) + fluid_entry(handle, v::drag + k)) /
        3.0;
  return f;
}

double mean_overlap(void* handle, const LAMMPS_NS::LAMMPS& lmp) {
  std::array<double, 2> local{}, global{};  // Σ w δ, Σ w
  if (const LAMMPS_NS::NeighList* list = lmp.force->pair->list) {
    const int nlocal = *static_cast<int*>(lammps_extract_global(handle, "nlocal"));
    auto** x = static_cast<double**>(lammps_extract_atom(handle, "x"));
    const auto* radius = static_cast<double*>(lammps_extract_atom(handle, "radius"));
    for (int ii = 0; ii < list->inum; ++ii) {
      const int i = list->ilist[ii];
      for (int jj = 0; jj < list->numneigh[i]; ++jj) {
        const int j = list->firstneigh[i][jj] & NEIGHMASK;
        const double dx = x[i][0] - x[j][0], dy = x[i][1] - x[j][1], dz = x[i][2] - x[j][2];
        const double overlap = radius[i] + radius[j] - std::sqrt(dx * dx + dy * dy + dz * dz);
        if (overlap <= 0.0) continue;
        const double w = j < nlocal ? 1.0 : 0.5;
        local[0] += w * overlap;
        local[1] += w;
      }
    }
  }
  MPI_Allreduce(local.data(), global.data(), 2, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  return global[1] > 0.0 ? global[0] / global[1] : 0.0;
}

}  // namespace granflow::dem
