// LIGGGHTS deck of a DEM preparation (`kind: dem_prepare`): the random gas of the shear deck
// (same sizes, insertion, contact law and time step as make_shear_deck, which writes the particle
// file) with the contact friction set to the preparation friction μ_prep, then granflow-dem's
// preparation stage (driver/prepare_stage.hpp): isotropic compression by a servo on the mean
// stress to p0 and relaxation to rest, written to prepared.restart for the shear runs that start
// from it (shear_deck.hpp, ShearDeckParams::prepared_restart).
// μ_prep = 0 gives the densest random packing at p0, μ_prep = the shearing friction a loose one
// (Agnolin & Roux 2007, Phys. Rev. E 76, 061302: φ 0.637 frictionless, ~0.59 at μ 0.3 for
// slow compressions; faster compressions of frictional spheres give looser packings).
#pragma once

#include <string>

#include "dem_coupling/deck/shear_deck.hpp"

namespace granflow::dem {

struct PreparationParams {
  // material (particle_friction = μ_prep), particles, seed, dt_safety, impact_speed_factor;
  // the shear keys are not used.
  ShearDeckParams sample;
  double pressure = 100.0;                    // p0, Pa
  double tolerance = 0.02;                    // |p - p0| <= tolerance p0
  double energy_ratio = 1e-4;                 // kinetic <= ratio × elastic energy
  double compression_inertial_number = 1e-3;  // ε̇_max d / sqrt(p0/ρ_p)
  long update_every = 50;                     // steps between servo updates
  long settle = 5;                            // consecutive updates prepared
  long max_steps = 2000000;
  double loop_gain = 0.25;  // servo loop gain at p0
};

struct PreparationDeck {
  std::string deck, data;  // in.granflow, particles.data
  ShearDeck sample;        // sizes, dt, contact times of the gas (make_shear_deck)
  double max_rate = 0.0;   // ε̇_max, 1/s
};

// ε̇_max = compression_inertial_number sqrt(p0/ρ_p) / d (d = material.diameter).
double preparation_max_rate(const PreparationParams& p);

PreparationDeck make_preparation_deck(const PreparationParams& p,
                                      const std::string& data_file_name);

}  // namespace granflow::dem
