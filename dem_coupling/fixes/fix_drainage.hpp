// fix drainage: a periodic box under an imposed total normal stress that compacts only as fast
// as its pore liquid can drain (docs/transient_dem.md, "Drained reconsolidation"):
//
//   fix ID group drainage NORMAL_STRESS PRESSURE_ID darcy LENGTH FLUID_ID
//   fix ID group drainage NORMAL_STRESS PRESSURE_ID resistance R
//
//   NORMAL_STRESS  σ_n, the total normal stress on the box's y faces, Pa
//   PRESSURE_ID    a `compute pressure ... virial` of the group (the particles' virial stress)
//   LENGTH         H, the drainage length, m
//   FLUID_ID       the run's fix fluid/le: the liquid (η0, permeability closure, sphericity)
//   R              a dry box's damped height: k = 1/R, Pa s (the same law with a constant k; the
//                  continuum's mixed control takes the same R, rev/simple_shear.hpp)
//
// The box is one material point of a layer drained over H (Terzaghi's consolidation lumped to one
// point, as the continuum's consolidating element test, docs/model/multi_regime.md): the liquid
// is incompressible and leaves by Darcy's law, κ/η0 times the pressure gradient u/H over H, so
// the box compacts at
//   ε̇_yy = k (σ_n − σ_yy),   k = κ(ν) / (η0 H²),
// σ_yy = P_yy of PRESSURE_ID + Σ m v_y² / V (the particles' stress, compression positive) and
// u = σ_n − σ_yy the excess pore pressure that drives the outflow. κ(ν) is the permeability of
// the drag fix fluid/le applies (continuum/model/closures.hpp, model::permeability at the
// group's number-mean diameter and the box's solid fraction ν): the DEM's liquid and its
// drainage are one closure. Every step (end_of_step) the height is rescaled about the box's
// lower y face, L_y ← L_y (1 − ε̇_yy Δt), atoms remapped affinely (positions only: the liquid
// moves with the point; it drains outside it); the tilt xy is kept. Explicit in u: stable while
// k M Δt < 2 (M the skeleton's constrained modulus), i.e. when H is well resolved by the DEM
// time step; the fix refuses k σ_n Δt > 0.01 at setup (a 1 % height change per step).
//
// Global vector (f_ID[1..4]): 1 ln(L_y,0 / L_y) since the fix was defined (compaction strain),
// 2 σ_yy of the last step (Pa), 3 u = σ_n − σ_yy (Pa), 4 k (1/(Pa s)).
#pragma once

namespace LAMMPS_NS {
class LAMMPS;
class Fix;
}  // namespace LAMMPS_NS

namespace granflow::dem {

LAMMPS_NS::Fix* create_fix_drainage(LAMMPS_NS::LAMMPS* lmp, int narg, char** arg);

}  // namespace granflow::dem
