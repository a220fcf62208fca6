// Case keys of the shear start and of the tangential dashpot (kept out of dem_kind.cpp, which
// is long already): material.tangential_damping, control.initial_temperature
// (docs/dem_dataset.md, "Starting state" and "Tangential dashpot").
#pragma once

#include "core/case.hpp"
#include "core/schema.hpp"
#include "dem_coupling/deck/shear_deck.hpp"

namespace granflow::dem {

inline void add_tangential_damping_key(core::Field& material) {
  material
      .choice("tangential_damping", {"liggghts", "lammps_hooke_history", "none"},
              "tangential dashpot γ_t of the contact: liggghts = LIGGGHTS' own (hooke: γ_t = "
              "γ_n; hertz: γ_t/γ_n = √(2(1-ν)/(2-ν)), 0.91 at ν 0.3), lammps_hooke_history = "
              "γ_n/2 (LAMMPS gran/hooke/history; hooke only), none = 0")
      .default_value("liggghts");
}

inline void add_initial_temperature_key(core::Field& control) {
  control
      .number("initial_temperature", "",
              "granular temperature T0/(d γ̇)² of the Gaussian velocity fluctuations (zero total "
              "momentum) added to the streaming profile at the shear start; default: kinetic "
              "theory's steady homogeneous-shear value f2/f3 at φ (constant_volume) or at the φ "
              "of its I (constant_pressure); 0: the affine profile alone")
      .at_least(0);
}

inline void read_shear_start_keys(const core::Case& c, ShearDeckParams& p) {
  // (material.tangential_damping is read with the material: read_dem_material)
  if (c.has("control.initial_temperature"))
    p.initial_temperature = c.number("control.initial_temperature");
}

}  // namespace granflow::dem
