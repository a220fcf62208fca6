// The only place where granflow reaches into LIGGGHTS internals that its headers do not offer.
#pragma once

namespace LAMMPS_NS {
class LAMMPS;
class Fix;
}  // namespace LAMMPS_NS

namespace granflow::dem {

using FixCreator = LAMMPS_NS::Fix* (*)(LAMMPS_NS::LAMMPS*, int, char**);

// Must be called right after constructing the LAMMPS instance, before any input is read.
void apply_triclinic_workaround(LAMMPS_NS::LAMMPS& lmp);

// Makes `fix ID group <name> ...` create an instance through `create` (for fixes compiled into
// granflow-dem, since Debian ships no style_fix.h to add styles the LAMMPS way).
void register_fix_style(LAMMPS_NS::LAMMPS& lmp, const char* name, FixCreator create);

}  // namespace granflow::dem
