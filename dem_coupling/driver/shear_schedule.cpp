#include "dem_coupling/driver/shear_schedule.hpp"

#include <algorithm>
#include <cstdio>

#include "domain.h"
#include "lammps.h"
#include "library.h"

namespace granflow::dem {

double ShearSchedule::strain_after(long done, double dt) const {
  if (!has_step()) return rate * double(done) * dt;
  const long before = std::min(done, step_steps), after = std::max(done - step_steps, 0L);
  return (rate * double(before) + step_rate * double(after)) * dt;
}

void define_shear(void* handle, double rate) {
  char command[128];
  std::snprintf(command, sizeof command, "fix gf_shear all deform 1 xy erate %.17g remap v", rate);
  lammps_command(handle, command);
}

void step_shear_rate(void* handle, LAMMPS_NS::LAMMPS& lmp, double old_rate, double new_rate) {
  const int nlocal = *static_cast<int*>(lammps_extract_global(handle, const_cast<char*>("nlocal")));
  auto** x = static_cast<double**>(lammps_extract_atom(handle, const_cast<char*>("x")));
  auto** v = static_cast<double**>(lammps_extract_atom(handle, const_cast<char*>("v")));
  const double ylo = lmp.domain->boxlo[1];
  for (int i = 0; i < nlocal; ++i) v[i][0] += (new_rate - old_rate) * (x[i][1] - ylo);
  define_shear(handle, new_rate);
}

}  // namespace granflow::dem
