// granflow-dem: the preparation stage (decks that define gf_prepare_pressure, written by
// deck/preparation_deck.cpp) instead of the shear stage. Isotropic compression of the granular
// gas the deck read, by a servo on the mean stress p = tr(P)/3 (P = P^vir + P^kin): every
// gf_prepare_every steps the three box lengths are rescaled by the same factor over the next
// interval (fix gf_prepare deform ... remap x),
//   Δ ln L = -clamp(g (p0 - p)/p0, ±ε̇_max Δt_int),   g = loop × (2/3) δ_t/d,
// ε̇_max = gf_prepare_max_rate; δ_t = <δ> (p0/p)^(2/3) is the mean overlap the Hertz contacts
// will have at p0 (p ∝ δ^(3/2)), so that with d ln p/d ln L ≈ -(3/2) d/δ (affine compression
// of the contacts) the loop gain is `loop` (gf_prepare_loop_gain) at the target; far from it
// (the gas, p ≈ 0) the box shrinks at the largest rate. Linear springs (p ∝ δ) see 2/3 of it.
// The sample is prepared when, at gf_prepare_settle consecutive updates, |p - p0| <=
// gf_prepare_tolerance p0 and the kinetic energy (translation + rotation) is at most
// gf_prepare_energy_ratio times the elastic energy of the contacts (contact_probe.hpp). Then
// the state is written: prepared.restart (LIGGGHTS restart: atoms, box, contact history),
// prepared.tsv (one row, the columns of prepare.tsv, the series of every update).
// Returns the exit code: 0 prepared, 3 not at rest within gf_prepare_max_steps (no restart is
// written, so the run cannot be used as a start).
#pragma once

namespace LAMMPS_NS {
class LAMMPS;
}

namespace granflow::dem {

int run_preparation(void* handle, LAMMPS_NS::LAMMPS& lmp, int rank);

}  // namespace granflow::dem
