// `kind: pair` (docs/calibration.md): the DEM simple shear (kind: dem) and the continuum steady
// simple shear at the same conditions, from one case file and so one material description,
// compared point by point (μ, φ, e, T, p, I, K; relative errors; regime of each point).
#pragma once

#include "core/kind_registry.hpp"

namespace granflow::pair {

core::Schema pair_schema();
void check_pair_case(const core::Case& c);
int run_pair_case(core::RunContext& ctx);

// Regime of a dry steady shear point by its inertial number (GDR MiDi 2004; Forterre &
// Pouliquen 2008): 0 quasi-static (I < 1e-3), 1 dense inertial (1e-3 ≤ I < 0.1), 2 collisional
// (I ≥ 0.1, where kinetic theory applies).
int dry_regime(double inertial_number);
// Immersed point: 3 viscous when the Stokes number St = I²/J < 1, else dry_regime(I).
int flow_regime(double inertial_number, double viscous_number);
const char* regime_name(int regime);

void register_pair_kinds(core::KindRegistry& registry);

}  // namespace granflow::pair
