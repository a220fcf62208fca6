// fix fluid/le: the forces of a viscous liquid on the grains of a Lees-Edwards (fix deform ...
// remap v) simple-shear DEM run, applied every step in post_force (docs/dem_fluid.md).
//
//   fix ID group fluid/le viscosity ETA permeability NAME [sphericity A]
//       [drag yes|no] [rotation yes|no] [lubrication HMAX HMIN] [tangential yes|no]
//       [reach factor|skin] [sums every|sampled]
//
//   viscosity     η0 of the liquid, Pa s
//   permeability  drag correlation by the continuum's name (seed_eq26, kozeny_carman, ergun):
//                 c_p = granflow::model::particle_drag_coefficient(liquid, d, ν), the same
//                 function the continuum's drag uses; seed_eq26 gives 3π η0 d (1-ν) F(ν)/A²
//   sphericity    A of the permeability (default 1)
//   drag          translational drag F = -c_p (v - u(x)), ν = the current box solid fraction
//                 (default yes)
//   rotation      rotational drag T = -π η0 d³ (ω - Ω), Ω = vorticity/2 (default yes)
//   lubrication   pairwise lubrication for gaps h < HMAX, resistances held at h = HMIN below it
//                 (default off); needs newton off and `communicate single vel yes`
//   tangential    the log(1/h) shear-mode lubrication with its torques (default yes when
//                 lubrication is on)
//   reach         how pairs with h < HMAX are kept in the granular list: factor (default)
//                 registers contact_distance_factor >= 1 + HMAX/(2 r_min); skin raises the
//                 neighbour skin by HMAX and forces a rebuild once an atom has moved half the
//                 deck's skin (LAMMPS' check, box motion included), so pair gran treats pairs
//                 outside contact as in a dry run (cheaper; see docs/dem_fluid.md)
//   sums          every (default): the global vector's sums (virials, dissipation, pair count)
//                 are formed every step; sampled: only on steps where a compute tallies the
//                 virial (vflag), the last step of a run and setup, i.e. where granflow-dem
//                 samples; reading the vector at another step is refused (not stale values)
// The fluid velocity is the box's affine (streaming) velocity, as LAMMPS' compute temp/deform:
// u = L (x - boxlo) + h_ratelo with L = H_rate H⁻¹; for `fix deform 1 xy erate γ̇ remap v` this is
// u_x = γ̇ (y - ylo) and Ω_z = -γ̇/2. Without fix deform the liquid is at rest.
// With reach factor the fix registers neigh_modify contact_distance_factor >= 1 + HMAX/(2 r_min)
// itself, so the granular pair list holds every pair with h < HMAX; it refuses a time step above
// the limits of dem_coupling/fixes/fluid_time_step.hpp (naming the limit).
//
// Global vector (f_ID[1..31]; intensive, summed over ranks), stresses in the sign convention of
// `compute pressure` (P_ab = W_ab / V, compression positive as docs/model/conventions.md states
// for the DEM; components xx yy zz xy xz yz, with
// W_xy = Σ Δx F_y as LIGGGHTS' pair virial):
//   1-6    P_lub,n   normal lubrication virial / V, Pa
//   7-12   P_lub,t   tangential lubrication virial / V, Pa
//   13-18  P_drag    drag virial Σ (x - boxlo) ⊗ F_drag / V, Pa (zero mean in homogeneous shear)
//   19-24  P_kin     kinetic stress Σ m (v - u) ⊗ (v - u) / V, Pa (current velocities)
//   25     ν         solid fraction used by the drag
//   26     c_p / (3π η0 d), the drag correlation's correction to Stokes drag (same for every d)
//   27     number of lubricated pairs (h < HMAX)
//   28     translational drag dissipation Σ c_p |v - u|², W
//   29     rotational drag dissipation Σ π η0 d³ |ω - Ω|², W
//   30     lubrication dissipation Σ c_n v_n² + c_t |v_t|², W
//   31     shear rate γ̇ = L_xy, 1/s
// virial_flag is set and the fix's virial (lubrication + drag) is in `compute pressure ...
// virial`, so P_contact = c_pressure - (P_lub,n + P_lub,t + P_drag) and the total stress is
// c_pressure + P_kin.
#pragma once

namespace granflow::model {
struct LiquidParameters;
}

namespace LAMMPS_NS {
class LAMMPS;
class Fix;
}  // namespace LAMMPS_NS

namespace granflow::dem {

LAMMPS_NS::Fix* create_fix_fluid_le(LAMMPS_NS::LAMMPS* lmp, int narg, char** arg);

// The liquid of `fix` when it is a fix fluid/le (viscosity, permeability closure, sphericity), else
// nullptr: other fixes (fix drainage) use the liquid the drag uses.
const model::LiquidParameters* fluid_le_liquid(const LAMMPS_NS::Fix* fix);

// Number of entries of the global vector and the 0-based offsets of its blocks.
namespace fluid_le_vector {
constexpr int lubrication_normal = 0;
constexpr int lubrication_tangential = 6;
constexpr int drag = 12;
constexpr int kinetic = 18;
constexpr int solid_fraction = 24;
constexpr int drag_correction = 25;
constexpr int lubricated_pairs = 26;
constexpr int drag_dissipation = 27;
constexpr int rotational_dissipation = 28;
constexpr int lubrication_dissipation = 29;
constexpr int shear_rate = 30;
constexpr int size = 31;
// Offset of a component within a stress block (xx yy zz xy xz yz).
constexpr int xy = 3;
}  // namespace fluid_le_vector

}  // namespace granflow::dem
