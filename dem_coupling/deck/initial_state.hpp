// The state the shear stage starts from (docs/dem_dataset.md, "Starting state"):
//  * the packing: spheres placed at random without overlap (random sequential addition, the
//    largest first) in a cubic periodic box at φ_insert = min(φ, insertion_solid_fraction);
//    a denser target is then reached by compressing the box (fix deform), never by expanding a
//    denser packing (an expansion leaves the spheres apart and at rest: a dilute gas started so
//    never collides and never heats);
//  * the velocities: the streaming profile u_x = γ̇ (y - y_lo) plus Gaussian fluctuations of
//    granular temperature T0 = Σ|c|²/(3N), zero total peculiar momentum, no spin (added by
//    granflow-dem after the deck; LIGGGHTS 3.8.0 has no `velocity ... create`).
// T0 defaults to kinetic theory's steady homogeneous-shear temperature (below), so a point
// starts near its steady state in any regime.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace granflow::dem {

// Largest φ random sequential addition is asked to reach: RSA of equal spheres jams at
// φ ≈ 0.384 (Torquato, Uche & Stillinger 2006, Phys. Rev. E 74, 061308); at 0.30 each sphere
// needs a few tens of trials at most.
constexpr double insertion_solid_fraction = 0.30;

// Kinetic theory's steady temperature of homogeneous simple shear, scaled: T/(d γ̇)² = f2/f3
// with L = d (docs/model/closures.md; Berzi & Jenkins 2014; f2, f3 of
// continuum/model/kinetic_theory_coefficients.hpp), g0 of Carnahan & Starling (1969), ε the
// effective restitution of Chialvo & Sundaresan (2013), ε = e - (3/2) μ_p exp(-3 μ_p). The
// dense limit is finite, T/(dγ̇)² -> 2 J/(15 (1 - ε²)) with J -> (1+e)/2, so φ is capped at 0.6
// (beyond, the flow is no longer collisional and this is only a start value). ε >= 1 (elastic,
// no steady state): 1.
double kinetic_shear_temperature(double solid_fraction, double restitution,
                                 double particle_friction);

// Constant normal stress: the φ at which kinetic theory's homogeneous shear has the inertial
// number I = γ̇ d / sqrt(σ_yy/ρ_p), I(φ) = (f1 f2 / f3)^(-1/2) (the same closed form), found by
// bisection on φ in [0.01, 0.6]; the ends when I is out of that range.
double kinetic_solid_fraction_at(double inertial_number, double restitution,
                                 double particle_friction);

struct RandomPacking {
  double box_length = 0;          // m, edge of the cubic box at φ_insert
  std::vector<double> positions;  // x y z per sphere, in [0, box_length)
  long trials = 0;                // insertion attempts in all
};

// Random sequential addition of `diameters` (placed largest first, kept in their order in
// `positions`) in a periodic cube of solid fraction `solid_fraction`, seeded (mt19937_64).
// Throws std::runtime_error when a sphere finds no place in 1e5 trials (φ near RSA jamming).
RandomPacking random_packing(const std::vector<double>& diameters, double solid_fraction,
                             std::uint64_t seed);

}  // namespace granflow::dem
