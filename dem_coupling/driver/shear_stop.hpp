// The stop stage of granflow-dem: after the shear, the shear is stopped at constant volume and
// the agitation left to decay (docs/transient_dem.md, "The shear stopped").
//   0. the particle snapshots (output.snapshot_strain) end: they are the shear's;
//   1. `unfix gf_shear`: the box is held (its tilt and height kept), and the deformation rate of
//      the domain (h_rate, h_ratelo) is zeroed, so periodic images carry no velocity offset and
//      fix fluid/le's liquid is at rest;
//   2. the streaming flow is taken out of every sphere: v_x -= γ̇ (y - y_lo), the profile about
//      which the shear's T was measured (extraction/shear_sample.hpp), and ω_z -= <ω_z>, the
//      mean spin (-γ̇/2 in steady shear: the flow's rotation); then the total momentum is
//      zeroed. What is left is the agitation: T is continuous across the stop.
#pragma once

namespace LAMMPS_NS {
class LAMMPS;
}

namespace granflow::dem {

struct StoppedFlow {
  double mean_spin = 0;         // <ω_z> removed, 1/s
  double drift[3] = {0, 0, 0};  // mean velocity removed after the profile, m/s
};

// Collective: every rank calls it between runs.
StoppedFlow stop_shear(void* handle, LAMMPS_NS::LAMMPS& lmp, double shear_rate);

}  // namespace granflow::dem
