// The shear rate over granflow-dem's shear stage: γ̇ (gf_shear_rate) for the first
// gf_rate_step_steps steps, then gf_rate_step_shear_rate (a step in the rate; docs/
// transient_dem.md, "A step in the shear rate"). Without the step, γ̇ throughout.
// At the step every owned sphere's v_x gains (γ̇2 − γ̇1)(y − y_lo), the change of the affine
// streaming profile about which T is measured (extraction/shear_sample.hpp), as the start adds
// the profile itself (the deck's velocity ramp); the spins are left to follow through contacts.
// fix gf_shear is then reissued at the new rate.
#pragma once

namespace LAMMPS_NS {
class LAMMPS;
}

namespace granflow::dem {

struct ShearSchedule {
  double rate = 0.0;       // γ̇ before the step, 1/s
  long step_steps = 0;     // shear steps before the step; 0: no step
  double step_rate = 0.0;  // γ̇ after the step, 1/s

  bool has_step() const { return step_steps > 0; }
  // γ̇ of the shear steps that follow `done` shear steps.
  double rate_after(long done) const { return has_step() && done >= step_steps ? step_rate : rate; }
  // Shear strain after `done` steps of Δt: γ̇1 min(done, n_s) Δt + γ̇2 max(done − n_s, 0) Δt.
  double strain_after(long done, double dt) const;
};

// `fix gf_shear all deform 1 xy erate RATE remap v` (collective): Lees-Edwards shear at the
// current box height (fix deform's tilt rate is erate × L_y at its definition, so a box whose
// height changes reissues it every sample).
void define_shear(void* handle, double rate);

// The rate step (collective, between runs): v_x += (new − old)(y − y_lo) on the owned spheres,
// then define_shear(new).
void step_shear_rate(void* handle, LAMMPS_NS::LAMMPS& lmp, double old_rate, double new_rate);

}  // namespace granflow::dem
