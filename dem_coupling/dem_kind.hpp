// `kind: dem`: Lees-Edwards periodic simple shear with LIGGGHTS (granflow-dem), dry.
#pragma once

#include "core/kind_registry.hpp"
#include "dem_coupling/deck/shear_deck.hpp"

namespace granflow::dem {

void register_dem_kinds(core::KindRegistry& registry);
core::Schema shear_schema();
// The deck parameters of one (expanded) case.
ShearDeckParams read_shear_params(const core::Case& c);
// The material section of a DEM case (kind: dem, dem_prepare), with the contact friction given
// (material.particle_friction for the shear, preparation.friction for a preparation).
DemMaterial read_dem_material(const core::Case& c, double particle_friction);

}  // namespace granflow::dem
