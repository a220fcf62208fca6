#include "dem_coupling/driver/shear_stop.hpp"

#include <mpi.h>

#include <array>
#include <string>

#include "domain.h"
#include "dump.h"
#include "lammps.h"
#include "library.h"
#include "output.h"

namespace granflow::dem {

StoppedFlow stop_shear(void* handle, LAMMPS_NS::LAMMPS& lmp, double shear_rate) {
  lammps_command(handle, const_cast<char*>("unfix gf_shear"));
  // The particle snapshots are the shear's (indexed by strain, their velocities about the
  // streaming profile): none of the stopped sample.
  for (const std::string dump : {"gf_snapshots", "gf_snapshots_text"})
    for (int k = 0; k < lmp.output->ndump; ++k)
      if (dump == lmp.output->dump[k]->id) {
        lammps_command(handle, const_cast<char*>(("undump " + dump).c_str()));
        break;
      }
  LAMMPS_NS::Domain& domain = *lmp.domain;
  for (int k = 0; k < 6; ++k) domain.h_rate[k] = 0.0;
  for (int k = 0; k < 3; ++k) domain.h_ratelo[k] = 0.0;

  const int nlocal = *static_cast<int*>(lammps_extract_global(handle, const_cast<char*>("nlocal")));
  auto** x = static_cast<double**>(lammps_extract_atom(handle, const_cast<char*>("x")));
  auto** v = static_cast<double**>(lammps_extract_atom(handle, const_cast<char*>("v")));
  auto** omega = static_cast<double**>(lammps_extract_atom(handle, const_cast<char*>("omega")));
  const auto* mass = static_cast<double*>(lammps_extract_atom(handle, const_cast<char*>("rmass")));
  std::array<double, 6> local{}, global{};  // Σ m v (3), Σ m, Σ ω_z, N
  for (int i = 0; i < nlocal; ++i) {
    v[i][0] -= shear_rate * (x[i][1] - domain.boxlo[1]);
    for (int k = 0; k < 3; ++k) local[k] += mass[i] * v[i][k];
    local[3] += mass[i];
    local[4] += omega[i][2];
    local[5] += 1.0;
  }
  MPI_Allreduce(local.data(), global.data(), 6, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  StoppedFlow out;
  if (global[5] > 0.0) out.mean_spin = global[4] / global[5];
  for (int k = 0; k < 3; ++k) out.drift[k] = global[3] > 0.0 ? global[k] / global[3] : 0.0;
  for (int i = 0; i < nlocal; ++i) {
    omega[i][2] -= out.mean_spin;
    for (int k = 0; k < 3; ++k) v[i][k] -= out.drift[k];
  }
  return out;
}

}  // namespace granflow::dem
