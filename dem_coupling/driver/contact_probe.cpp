#include "dem_coupling/driver/contact_probe.hpp"

#include <mpi.h>

#include <cmath>
#include <vector>

#include "force.h"
#include "lammps.h"
#include "library.h"
#include "lmptype.h"
#include "neigh_list.h"
#include "pair.h"

namespace granflow::dem {

ContactProbe probe_contacts(void* handle, const LAMMPS_NS::LAMMPS& lmp, const ElasticLaw& law) {
  // Packed per pair: tag_i - 1, tag_j - 1, n (3), δ, R*. Newton off: a pair of two owned atoms
  // is listed once, a pair with a ghost by both owners (on one rank, a periodic image), so a
  // ghost pair is kept where the owned atom has the smaller tag.
  constexpr int width = 7;
  std::vector<double> local;
  double energy_local = 0.0;
  if (const LAMMPS_NS::NeighList* list = lmp.force->pair->list) {
    const int nlocal = *static_cast<int*>(lammps_extract_global(handle, "nlocal"));
    auto** x = static_cast<double**>(lammps_extract_atom(handle, "x"));
    const auto* radius = static_cast<double*>(lammps_extract_atom(handle, "radius"));
    const auto* tag = static_cast<int*>(lammps_extract_atom(handle, "id"));
    for (int ii = 0; ii < list->inum; ++ii) {
      const int i = list->ilist[ii];
      if (i >= nlocal) continue;
      for (int jj = 0; jj < list->numneigh[i]; ++jj) {
        const int j = list->firstneigh[i][jj] & NEIGHMASK;
        if (j >= nlocal && tag[j] < tag[i]) continue;
        const double dx = x[j][0] - x[i][0], dy = x[j][1] - x[i][1], dz = x[j][2] - x[i][2];
        const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
        const double overlap = radius[i] + radius[j] - r;
        if (overlap <= 0.0 || r <= 0.0) continue;
        const double reduced = radius[i] * radius[j] / (radius[i] + radius[j]);
        local.insert(local.end(), {double(tag[i] - 1), double(tag[j] - 1), dx / r, dy / r, dz / r,
                                   overlap, reduced});
        energy_local += law.hooke ? 0.5 * law.normal_stiffness * overlap * overlap
                                  : 8.0 / 15.0 * law.effective_modulus * std::sqrt(reduced) *
                                        overlap * overlap * std::sqrt(overlap);
      }
    }
  }
  int ranks = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  const int count = static_cast<int>(local.size());
  std::vector<int> counts(static_cast<std::size_t>(ranks), 0), offsets(counts);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  int total = 0;
  for (int r = 0; r < ranks; ++r) {
    offsets[r] = total;
    total += counts[r];
  }
  std::vector<double> all(static_cast<std::size_t>(total));
  MPI_Allgatherv(local.data(), count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(),
                 MPI_DOUBLE, MPI_COMM_WORLD);
  ContactProbe out;
  MPI_Allreduce(&energy_local, &out.elastic_energy, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  std::vector<ContactPair> pairs;
  double overlap_sum = 0.0;
  for (int k = 0; k + width <= total; k += width) {
    pairs.push_back(
        {std::lround(all[k]), std::lround(all[k + 1]), {all[k + 2], all[k + 3], all[k + 4]}});
    overlap_sum += all[k + 5];
  }
  out.mean_overlap = pairs.empty() ? 0.0 : overlap_sum / double(pairs.size());
  out.network = network_state(static_cast<long>(lammps_get_natoms(handle)), pairs);
  return out;
}

}  // namespace granflow::dem
