// fix fluid/le (see fix_fluid_le.hpp for the syntax and the global vector; docs/dem_fluid.md for
// the equations and their sources): init, setup, the per-step drag and rotational drag, the
// global vector. The arguments, the reach of the pair list and the lubrication passes are in
// the other fix_fluid_le_*.cpp files (fix_fluid_le_class.hpp).
#include <fmt/format.h>
#include <mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "atom.h"
#include "comm.h"
#include "continuum/model/closures.hpp"
#include "dem_coupling/fixes/fix_fluid_le_class.hpp"
#include "dem_coupling/fixes/fluid_time_step.hpp"
#include "dem_coupling/fixes/lubrication.hpp"
#include "domain.h"
#include "error.h"
#include "fix.h"
#include "force.h"
#include "lammps.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "pair.h"
#include "update.h"

namespace granflow::dem::fluid_le_detail {

constexpr double pi = std::numbers::pi;

void FixFluidLE::init() {
  report_time_scales_ = true;
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
    fail("fix fluid/le needs atom_style granular (radius, rmass, omega, torque)");
  if (settings_.lubrication) {
    if (force->newton_pair) fail("fix fluid/le lubrication needs 'newton off'");
    if (!comm->ghost_velocity)
      fail("fix fluid/le lubrication needs 'communicate single vel yes' (ghost velocities)");
    if (force->pair == nullptr) fail("fix fluid/le lubrication needs a granular pair style");
  }
  // Size range and lightest material of the group (time-step limits, list reach).
  double lo[2] = {std::numeric_limits<double>::infinity(),
                  std::numeric_limits<double>::infinity()};  // r_min, ρ_min
  double r_max = 0.0;
  for (int i = 0; i < atom->nlocal; ++i) {
    if (!(atom->mask[i] & groupbit)) continue;
    const double r = atom->radius[i];
    lo[0] = std::min(lo[0], r);
    lo[1] = std::min(lo[1], atom->rmass[i] / (4.0 / 3.0 * pi * r * r * r));
    r_max = std::max(r_max, r);
  }
  double lo_all[2];
  MPI_Allreduce(lo, lo_all, 2, MPI_DOUBLE, MPI_MIN, world);
  MPI_Allreduce(&r_max, &largest_radius_, 1, MPI_DOUBLE, MPI_MAX, world);
  smallest_radius_ = lo_all[0];
  smallest_density_ = lo_all[1];
  if (!(smallest_radius_ > 0.0 && std::isfinite(smallest_radius_)))
    fail("fix fluid/le: the group has no particles of positive radius");
  if (settings_.lubrication) {
    if (!(settings_.maximum_gap < smallest_radius_))
      fail(
          "fix fluid/le: lubrication HMAX must be below the smallest radius (the near-field "
          "asymptotics and the log(1/h) term need h << r)");
    if (reach_by_skin_) {
      // The constructor raised the skin to the deck's + HMAX; post_integrate() keeps pairs with
      // h < HMAX listed by rebuilding at half the deck's skin.
      if (std::abs(neighbor->skin - raised_skin_) > 1e-12 * raised_skin_)
        fail(fmt::format(
            "fix fluid/le: reach skin: the neighbour skin is {:.6g} m, not the {:.6g} m (deck "
            "skin {:.6g} + HMAX) the fix set when it was defined: define the fix after the "
            "'neighbor' command",
            neighbor->skin, raised_skin_, deck_skin_));
      return;
    }
    // The granular list keeps pairs with r < (r_i + r_j) cdf + skin; every pair with
    // h < (r_i + r_j)(cdf - 1) stays listed between rebuilds, so cdf = 1 + HMAX / (2 r_min).
    // The pair style reads the factor in force->init(), before fixes are initialised, so the
    // constructor registered it; a radius that shrank since is caught here.
    const double needed = 1.0 + settings_.maximum_gap / (2.0 * smallest_radius_);
    if (neighbor->contactDistanceFactor < needed * (1.0 - 1e-12))
      fail(
          "fix fluid/le: the granular neighbour list does not reach HMAX: use 'neigh_modify "
          "contact_distance_factor " +
          std::to_string(needed) +
          "' (1 + HMAX / (2 r_min)) "
          "before the first run");
  }
}

FixFluidLE::Flow FixFluidLE::current_flow() const {
  Flow flow{};
  // H (upper triangular, Voigt order 0 xx, 1 yy, 2 zz, 3 yz, 4 xz, 5 xy) maps lamda to x - boxlo.
  const double* hr = domain->h_rate;
  const double* hi = domain->h_inv;
  const double rate[3][3] = {{hr[0], hr[5], hr[4]}, {0.0, hr[1], hr[3]}, {0.0, 0.0, hr[2]}};
  const double inv[3][3] = {{hi[0], hi[5], hi[4]}, {0.0, hi[1], hi[3]}, {0.0, 0.0, hi[2]}};
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      double s = 0.0;
      for (int k = 0; k < 3; ++k) s += rate[a][k] * inv[k][b];
      flow.L[a][b] = s;
    }
  for (int a = 0; a < 3; ++a) flow.rate_lo[a] = domain->h_ratelo[a];
  flow.spin[0] = 0.5 * (flow.L[2][1] - flow.L[1][2]);
  flow.spin[1] = 0.5 * (flow.L[0][2] - flow.L[2][0]);
  flow.spin[2] = 0.5 * (flow.L[1][0] - flow.L[0][1]);
  return flow;
}

void FixFluidLE::setup(int vflag) {
  double local_volume = 0.0;
  for (int i = 0; i < atom->nlocal; ++i)
    if (atom->mask[i] & groupbit) {
      const double r = atom->radius[i];
      local_volume += 4.0 / 3.0 * pi * r * r * r;
    }
  MPI_Allreduce(&local_volume, &solid_volume_, 1, MPI_DOUBLE, MPI_SUM, world);
  const double box_volume = domain->xprd * domain->yprd * domain->zprd;
  if (settings_.lubrication) {
    if (force->pair->list == nullptr) fail("fix fluid/le: the pair style has no neighbour list");
    const Flow flow = current_flow();
    const bool sheared = flow.L[0][1] != 0.0 || flow.L[0][2] != 0.0 || flow.L[1][2] != 0.0;
    if (sheared && !domain->deform_vremap)
      fail(
          "fix fluid/le: a sheared box needs fix deform ... remap v (Lees-Edwards ghost "
          "velocities)");
  }
  FluidTimeStepInput in;
  in.fluid = settings_;
  in.particle_density = smallest_density_;
  in.smallest_radius = smallest_radius_;
  in.largest_radius = largest_radius_;
  in.solid_fraction = solid_volume_ / box_volume;
  if (!(in.solid_fraction < 1.0)) fail("fix fluid/le: solid fraction >= 1");
  const FluidTimeScales scales = fluid_time_scales(in);
  const std::string refusal = check_fluid_time_step(update->dt, scales);
  if (!refusal.empty()) fail("fix fluid/le: " + refusal);
  if (report_time_scales_ && comm->me == 0) {  // once per init: the limits and the step in use
    const FluidTimeStep stable = stable_fluid_time_step(scales);
    const std::string text = fmt::format(
        "fix fluid/le: nu = {:.4g}, c_p/(3 pi eta d) = {:.4g}; time scales (s): drag {:.4g}, "
        "rotational drag {:.4g}, normal lubrication {:.4g}, tangential lubrication {:.4g}; "
        "dt = {:.4g} s (fluid-limited stable dt {:.4g} s, set by {})\n",
        in.solid_fraction,
        model::particle_drag_coefficient(settings_.liquid, 1.0, in.solid_fraction) /
            (3.0 * pi * settings_.liquid.viscosity),
        scales.drag, scales.rotational_drag, scales.normal_lubrication,
        scales.tangential_lubrication, update->dt, stable.dt, stable.limited_by);
    if (screen) std::fputs(text.c_str(), screen);
    if (logfile) std::fputs(text.c_str(), logfile);
  }
  report_time_scales_ = false;
  candidates_.build = -1;  // group or list may have changed between runs
  setup_pending_ = true;
  post_force(vflag);
}

void FixFluidLE::post_force(int vflag) {
  // The sums (virials, dissipation, pair count) cost ~15 % of the pair loop; with `sums sampled`
  // they are formed only when read: vflag (compute pressure tallies the virial this step), the
  // last step of a run (granflow-dem samples there), setup.
  const bool sums =
      sums_every_step_ || vflag != 0 || setup_pending_ || update->ntimestep == update->laststep;
  setup_pending_ = false;
  double** x = atom->x;
  double** v = atom->v;
  double** f = atom->f;
  double** omega = atom->omega;
  double** torque = atom->torque;
  const double* radius = atom->radius;
  const int* mask = atom->mask;
  const int nlocal = atom->nlocal;
  const double eta = settings_.liquid.viscosity;
  const Flow flow = current_flow();
  const double* lo = domain->boxlo;
  const double box_volume = domain->xprd * domain->yprd * domain->zprd;
  const double nu = solid_volume_ / box_volume;

  std::array<double, vec::size> acc{};
  double w_drag[6] = {0, 0, 0, 0, 0, 0};

  // (a) drag relative to the streaming velocity, and rotational drag relative to Ω.
  if (settings_.drag || settings_.rotational_drag) {
    // Every correlation has κ = d² × (a function of ν), so c_p(d, ν) = d c_p(1 m, ν): the
    // continuum's particle_drag_coefficient is evaluated once per step and scaled by d
    // (tests/dem_fluid/test_dem_fluid_time_step.cpp checks the proportionality for each option).
    const double drag_per_diameter =
        settings_.drag ? model::particle_drag_coefficient(settings_.liquid, 1.0, nu) : 0.0;
    // Flat, non-aliased views and local sums (the force writes cannot alias them).
    const double* __restrict xf = x[0];
    const double* __restrict vf = v[0];
    const double* __restrict wf = omega[0];
    double* __restrict ff = f[0];
    double* __restrict tf = torque[0];
    const double origin[3] = {lo[0], lo[1], lo[2]};
    const bool drag = settings_.drag, rotation = settings_.rotational_drag;
    const double rotational_per_diameter_cubed = pi * eta;
    double drag_dissipation = 0.0, rotational_dissipation = 0.0;
    for (int i = 0; i < nlocal; ++i) {
      if (!(mask[i] & groupbit)) continue;
      const double d = 2.0 * radius[i];
      if (drag) {
        const double dx[3] = {xf[3 * i] - origin[0], xf[3 * i + 1] - origin[1],
                              xf[3 * i + 2] - origin[2]};
        const double c = drag_per_diameter * d;
        double F[3];
        for (int a = 0; a < 3; ++a) {
          const double u =
              flow.L[a][0] * dx[0] + flow.L[a][1] * dx[1] + flow.L[a][2] * dx[2] + flow.rate_lo[a];
          const double w = vf[3 * i + a] - u;
          F[a] = -c * w;
          ff[3 * i + a] += F[a];
          drag_dissipation -= F[a] * w;  // c |v - u|²
        }
        w_drag[0] += dx[0] * F[0];
        w_drag[1] += dx[1] * F[1];
        w_drag[2] += dx[2] * F[2];
        w_drag[3] += dx[0] * F[1];
        w_drag[4] += dx[0] * F[2];
        w_drag[5] += dx[1] * F[2];
      }
      if (rotation) {
        const double cr = rotational_per_diameter_cubed * d * d * d;
        for (int a = 0; a < 3; ++a) {
          const double w = wf[3 * i + a] - flow.spin[a];
          tf[3 * i + a] -= cr * w;
          rotational_dissipation += cr * w * w;
        }
      }
    }
    acc[vec::drag_dissipation] = drag_dissipation;
    acc[vec::rotational_dissipation] = rotational_dissipation;
  }

  // (b) pairwise lubrication on the granular half list.
  if (settings_.lubrication && atom->nlocal + atom->nghost > 0) lubrication_forces(acc, sums);
  if (!sums) return;  // forces applied; the last sums stay, marked by sums_step_

  for (int k = 0; k < 6; ++k) {
    acc[vec::drag + k] = w_drag[k];
    virial[k] = acc[vec::lubrication_normal + k] + acc[vec::lubrication_tangential + k] + w_drag[k];
  }
  // Store virials as stresses (divide once here, the sums stay in acc).
  for (int k = 0; k < 18; ++k) acc[k] /= box_volume;
  acc[vec::solid_fraction] = nu;
  acc[vec::shear_rate] = flow.L[0][1];
  local_ = acc;
  last_reduce_ = -1;  // new forces: reduce again on the next request
  sums_step_ = update->ntimestep;
}

double FixFluidLE::compute_vector(int n) {
  if (sums_step_ != update->ntimestep)
    fail(fmt::format(
        "fix fluid/le: vector requested at step {} but its sums were last formed at step {} "
        "('sums sampled' forms them only when a compute tallies the virial and at the end of "
        "a run; use 'sums every' to read them at other steps)",
        long(update->ntimestep), long(sums_step_)));
  if (last_reduce_ != update->ntimestep) {
    // kinetic stress about the streaming velocity, from the current velocities
    const Flow flow = current_flow();
    const double* lo = domain->boxlo;
    double k[6] = {0, 0, 0, 0, 0, 0};
    for (int i = 0; i < atom->nlocal; ++i) {
      if (!(atom->mask[i] & groupbit)) continue;
      const double* xi = atom->x[i];
      const double dx[3] = {xi[0] - lo[0], xi[1] - lo[1], xi[2] - lo[2]};
      double w[3];
      for (int a = 0; a < 3; ++a)
        w[a] = atom->v[i][a] - (flow.L[a][0] * dx[0] + flow.L[a][1] * dx[1] + flow.L[a][2] * dx[2] +
                                flow.rate_lo[a]);
      const double m = atom->rmass[i];
      k[0] += m * w[0] * w[0];
      k[1] += m * w[1] * w[1];
      k[2] += m * w[2] * w[2];
      k[3] += m * w[0] * w[1];
      k[4] += m * w[0] * w[2];
      k[5] += m * w[1] * w[2];
    }
    const double box_volume = domain->xprd * domain->yprd * domain->zprd;
    std::array<double, vec::size> send = local_;
    for (int c = 0; c < 6; ++c) send[vec::kinetic + c] = k[c] / box_volume;
    MPI_Allreduce(send.data(), global_.data(), vec::size, MPI_DOUBLE, MPI_SUM, world);
    // per-box quantities, identical on every rank: not summed
    global_[vec::solid_fraction] = local_[vec::solid_fraction];
    global_[vec::shear_rate] = local_[vec::shear_rate];
    global_[vec::drag_correction] =
        model::particle_drag_coefficient(settings_.liquid, 1.0, local_[vec::solid_fraction]) /
        (3.0 * pi * settings_.liquid.viscosity);
    last_reduce_ = update->ntimestep;
  }
  if (n < 0 || n >= vec::size) return 0.0;
  return global_[n];
}

}  // namespace granflow::dem::fluid_le_detail

namespace granflow::dem {

LAMMPS_NS::Fix* create_fix_fluid_le(LAMMPS_NS::LAMMPS* lmp, int narg, char** arg) {
  return new fluid_le_detail::FixFluidLE(lmp, narg, arg);
}

const model::LiquidParameters* fluid_le_liquid(const LAMMPS_NS::Fix* fix) {
  const auto* fluid = dynamic_cast<const fluid_le_detail::FixFluidLE*>(fix);
  return fluid ? &fluid->settings().liquid : nullptr;
}

}  // namespace granflow::dem
