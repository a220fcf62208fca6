// `kind: dem`: Lees-Edwards periodic simple shear with LIGGGHTS (granflow-dem), dry.
#pragma once

#include "core/kind_registry.hpp"
#include "dem_coupling/deck/shear_deck.hpp"

namespace granflow::dem {

void register_dem_kinds(core::KindRegistry& registry);
core::Schema shear_schema();
// The deck parameters of one (expanded) case.
ShearDeckParams read_shear_params(const core::Case& c);

}  // namespace granflow::dem
