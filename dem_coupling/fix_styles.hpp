// Fix styles compiled into granflow-dem and registered by name before the deck is read, so decks
// can use them like built-in LIGGGHTS styles (`fix ID group <name> args...`).
//
// To add one (e.g. immersed drag / lubrication): write a LAMMPS_NS::Fix subclass in
// dem_coupling/fixes/<name>.{hpp,cpp} with a creator `Fix* create_<name>(LAMMPS*, int, char**)`
// and add {"<style name>", &create_<name>} to the table in fix_styles.cpp. The driver calls
// register_custom_fix_styles() right after the triclinic workaround.
#pragma once

#include <span>

#include "dem_coupling/liggghts_access.hpp"

namespace granflow::dem {

struct FixStyle {
  const char* name;
  FixCreator create;
};

// The table of granflow's own fix styles (dry shear needs none).
std::span<const FixStyle> custom_fix_styles();

void register_custom_fix_styles(LAMMPS_NS::LAMMPS& lmp);

}  // namespace granflow::dem
