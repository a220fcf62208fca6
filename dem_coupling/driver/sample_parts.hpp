// Parts of a granflow-dem sample read straight from the LIGGGHTS instance (collective: every
// rank calls them, they reduce over ranks).
#pragma once

#include "dem_coupling/driver/series_output.hpp"
#include "dem_coupling/extraction/shear_sample.hpp"

namespace LAMMPS_NS {
class LAMMPS;
}

namespace granflow::dem {

// The immersed stress split from fix gf_fluid's global vector (fixes/fix_fluid_le.hpp):
// τ_lub = -(P_lub,n,xy + P_lub,t,xy), τ_drag = -P_drag,xy, τ_kin = -P^kin_xy,
// τ_contact = -P^vir_xy - τ_lub - τ_drag (the fix's virial is part of compute gf_virial), so
// the four parts sum to τ = -(P^vir_xy + P^kin_xy) exactly; and the hydrodynamic pressure (the
// lubrication and drag part of tr(P)/3). The deck must define fix gf_fluid.
FluidStress fluid_stress(void* handle, const ShearSample& s);

// Mean overlap of the touching pairs, <δ> = Σ δ_ij / N_c with δ_ij = r_i + r_j - |x_i - x_j| > 0,
// over the pair's half neighbour list (a pair with a ghost is listed on both ranks: weight 1/2,
// as accumulate_contacts). How soft the sample is: δ/d of a few % above jamming (O'Hern et al.
// 2003). 0 without contacts.
double mean_overlap(void* handle, const LAMMPS_NS::LAMMPS& lmp);

}  // namespace granflow::dem
