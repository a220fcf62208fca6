// Workarounds for Debian's LIGGGHTS 3.8.0 (libliggghts3 3.8.0+repack1), kept in this one file.
//
// 1. Upstream bug, LIGGGHTS-PUBLIC 3.8.0 src/domain.cpp:144-145: the Domain constructor sets
//    prd_lamda[] = 0.0 and prd_half_lamda[] = 0.0 (LAMMPS: 1.0 and 0.5) and nothing resets them.
//    For triclinic (prism) boxes Comm::setup divides by prd_lamda, so maxneed overflows: no
//    periodic ghost atoms in serial, a hang under MPI, and Domain::pbc does not wrap atoms
//    ("Lost atoms"). See docs of liggghts-study.md section 3.1. Setting the lamda-box period
//    to (1,1,1) right after construction repairs it (the members are public).
// 2. Modify::fix_map (the style name -> creator table) is private and Debian ships no
//    style_fix.h, so a fix compiled into the driver can only be registered by opening the access
//    specifiers of modify.h. GCC/Clang do not change class layout for access specifiers, so this
//    is ABI-safe; it is confined to register_fix_style below.
#include "dem_coupling/liggghts_access.hpp"

// System and MPI headers first, so the access trick below only touches LIGGGHTS' own classes.
#include <mpi.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>

#include "domain.h"
#include "lammps.h"
#define private public
#include "modify.h"
#undef private

namespace granflow::dem {

void apply_triclinic_workaround(LAMMPS_NS::LAMMPS& lmp) {
  for (int k = 0; k < 3; ++k) {
    lmp.domain->prd_lamda[k] = 1.0;       // lamda box = (1,1,1), as in LAMMPS' Domain()
    lmp.domain->prd_half_lamda[k] = 0.5;  // half of it
  }
}

void register_fix_style(LAMMPS_NS::LAMMPS& lmp, const char* name, FixCreator create) {
  (*lmp.modify->fix_map)[name] = create;
}

}  // namespace granflow::dem
