// Case-file sections shared by every kind that runs the continuum model (rev, mpm, pair,
// calibrate): `material` (grain properties; the DEM reads the same keys), `collisional`,
// `liquid`, `force_chains`. One description of the material, so DEM and continuum cannot drift
// apart.
#pragma once

#include "continuum/multi_regime/multi_regime_point.hpp"
#include "core/case.hpp"
#include "core/schema.hpp"

namespace granflow::continuum {

core::Field material_section();
core::Field collisional_section();
core::Field liquid_section();
// `force_chains`: enabled + the ForceChainParameters (docs/model/force_chains.md); defaults are
// ForceChainParameters{} (the loose sand of the seed's section 4). `enabled_by_default`: the
// default of force_chains.enabled (true for the steady kinds pair and calibrate, whose forward
// model is the in-parallel steady state; false elsewhere).
core::Field force_chains_section(bool enabled_by_default = false);
// `steady`: options of the steady simple-shear forward model of pair and calibrate
// (docs/model/steady_state.md) that the time-stepped drivers do not have.
core::Field steady_section();

// Read the sections (force_chains only if the schema has it) of a validated case into the point
// settings. Throws CaseError (located at the key) for combinations the schema cannot express.
MultiRegimeSettings read_multi_regime_settings(const core::Case& c);

}  // namespace granflow::continuum
