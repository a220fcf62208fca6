// fix fluid/le (see fix_fluid_le.hpp for the syntax and the global vector; docs/dem_fluid.md for
// the equations and their sources).
#include "dem_coupling/fixes/fix_fluid_le.hpp"

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

namespace granflow::dem {

namespace {

namespace vec = fluid_le_vector;
constexpr double pi = std::numbers::pi;

class FixFluidLE : public LAMMPS_NS::Fix {
 public:
  FixFluidLE(LAMMPS_NS::LAMMPS* lmp, int narg, char** arg);
  ~FixFluidLE() override {  // `unfix` gives the deck its own skin back (reach skin)
    if (reach_by_skin_ && neighbor->skin == raised_skin_) neighbor->skin = deck_skin_;
  }
  int setmask() override {
    return LAMMPS_NS::FixConst::POST_FORCE |
           (reach_by_skin_ ? LAMMPS_NS::FixConst::POST_INTEGRATE : 0);
  }
  void post_integrate() override;
  void init() override;
  void setup(int vflag) override;
  void post_force(int vflag) override;
  double compute_vector(int n) override;

 private:
  // Streaming (fluid) velocity gradient L = H_rate H⁻¹ of the deforming box and the vorticity/2.
  struct Flow {
    double L[3][3];
    double rate_lo[3];
    double spin[3];  // Ω = (1/2) curl u
  };
  Flow current_flow() const;
  void fail(const std::string& message) const { error->all(FLERR, message.c_str()); }
  bool parse_yes_no(const char* keyword, const char* value) const;

  FluidForceSettings settings_;
  double solid_volume_ = 0.0;  // Σ π d³/6 of the group, m³ (set in setup)
  double smallest_radius_ = 0.0, largest_radius_ = 0.0, smallest_density_ = 0.0;
  std::array<double, vec::size> local_{};   // this rank's sums (kinetic part filled on demand)
  std::array<double, vec::size> global_{};  // reduced over ranks
  LAMMPS_NS::bigint last_reduce_ = -1;
  bool report_time_scales_ = true;
  // This step's pairs within h_max (grow-only buffers, structure of arrays, sized by the list):
  // pairs with an owned j at [0, owned), pairs with a ghost j at [capacity - ghost, capacity).
  // Layout after selection: [0, owned) owned j; [owned, owned + images) ghost j that is a
  // periodic image of an atom owned here (target = that atom); [top - ghost, top - ghost + half)
  // ghost j owned by another rank. Capacity 2 × entries keeps the regions apart.
  struct LubricatedPairs {
    std::vector<int> i, j, target;
    std::vector<double> inverse_distance, normal, tangential, log_argument;
    void grow(std::size_t entries) {
      if (2 * entries <= i.size()) return;
      const std::size_t n = 3 * entries;  // grows with the list, not in steady state
      for (auto* a : {&i, &j, &target}) a->resize(n);
      for (auto* a : {&inverse_distance, &normal, &tangential, &log_argument}) a->resize(n);
    }
  };
  LubricatedPairs pairs_;
  // Candidate pairs of this rank (update_candidates), rebuilt with the neighbour list.
  struct Candidate {
    int i, j, target;  // target: where j's force goes (j, its owned image, or -1: other rank)
  };
  struct Candidates {
    std::vector<Candidate> owned, images, remote, all;  // all = owned, images, remote in order
    std::size_t end[3] = {0, 0, 0};                     // ends of the three kinds in all
    LAMMPS_NS::bigint build = -1;
  };
  Candidates candidates_;
  void update_candidates();
  // `sums sampled`: virials, dissipation and pair count only on the steps that read them (a
  // compute tallies the virial, the last step of a run, setup); `sums every`: every step.
  bool sums_every_step_ = true;
  bool setup_pending_ = false;
  LAMMPS_NS::bigint sums_step_ = -1;
  // For each ghost (index - nlocal): the local index of the owned atom it is a periodic image
  // of, or -1 if the atom is owned by another rank; rebuilt when the ghosts are (with every
  // neighbour build: neighbor->ncalls counts them).
  std::vector<int> ghost_owner_;
  LAMMPS_NS::bigint ghost_owner_build_ = -1;
  void update_ghost_owners();

  // `reach skin`: the list reach for h_max comes from the skin (raised by h_max when the fix is
  // created) instead of contact_distance_factor, and the fix forces a rebuild once an atom has
  // moved half the deck's own skin (less the box corners' motion, as LAMMPS' check), so every
  // pair with h < h_max stays listed. Positions and box corners at the last build:
  bool reach_by_skin_ = false;
  double deck_skin_ = 0.0, raised_skin_ = 0.0;
  std::vector<double> x_at_build_;
  double corners_at_build_[8][3] = {};
  LAMMPS_NS::bigint hold_build_ = -1;
  void hold_build_positions();
  void lubrication_forces(std::array<double, fluid_le_vector::size>& acc, bool sums);
};

bool FixFluidLE::parse_yes_no(const char* keyword, const char* value) const {
  if (std::strcmp(value, "yes") == 0) return true;
  if (std::strcmp(value, "no") == 0) return false;
  fail(std::string("fix fluid/le: keyword ") + keyword + " expects yes or no, got " + value);
  return false;
}

double parse_number(LAMMPS_NS::Error* error, const char* keyword, const char* text) {
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  if (end == text || *end != '\0' || !std::isfinite(value)) {
    const std::string message =
        std::string("fix fluid/le: keyword ") + keyword + " expects a number, got " + text;
    error->all(FLERR, message.c_str());
  }
  return value;
}

FixFluidLE::FixFluidLE(LAMMPS_NS::LAMMPS* lmp, int narg, char** arg) : Fix(lmp, narg, arg) {
  settings_.lubrication = false;
  bool have_viscosity = false, have_permeability = false;
  for (int i = 3; i < narg;) {
    const std::string key = arg[i];
    auto need = [&](int n) {
      if (i + n >= narg)
        fail("fix fluid/le: keyword " + key + " needs " + std::to_string(n) + " value(s)");
    };
    if (key == "viscosity") {
      need(1);
      settings_.liquid.viscosity = parse_number(error, "viscosity", arg[i + 1]);
      if (!(settings_.liquid.viscosity > 0.0)) fail("fix fluid/le: viscosity must be > 0 (Pa s)");
      have_viscosity = true;
      i += 2;
    } else if (key == "permeability") {
      need(1);
      try {
        settings_.liquid.permeability = model::parse_permeability(arg[i + 1]);
      } catch (const std::invalid_argument& e) {
        fail(std::string("fix fluid/le: permeability: ") + e.what());
      }
      have_permeability = true;
      i += 2;
    } else if (key == "sphericity") {
      need(1);
      settings_.liquid.sphericity = parse_number(error, "sphericity", arg[i + 1]);
      if (!(settings_.liquid.sphericity > 0.0 && settings_.liquid.sphericity <= 1.0))
        fail("fix fluid/le: sphericity must be in (0, 1]");
      i += 2;
    } else if (key == "drag") {
      need(1);
      settings_.drag = parse_yes_no("drag", arg[i + 1]);
      i += 2;
    } else if (key == "rotation") {
      need(1);
      settings_.rotational_drag = parse_yes_no("rotation", arg[i + 1]);
      i += 2;
    } else if (key == "tangential") {
      need(1);
      settings_.tangential_lubrication = parse_yes_no("tangential", arg[i + 1]);
      i += 2;
    } else if (key == "lubrication") {
      need(2);
      settings_.maximum_gap = parse_number(error, "lubrication HMAX", arg[i + 1]);
      settings_.minimum_gap = parse_number(error, "lubrication HMIN", arg[i + 2]);
      if (!(settings_.minimum_gap > 0.0 && settings_.maximum_gap > settings_.minimum_gap))
        fail("fix fluid/le: lubrication HMAX HMIN needs 0 < HMIN < HMAX (m)");
      settings_.lubrication = true;
      i += 3;
    } else if (key == "reach") {
      need(1);
      const std::string value = arg[i + 1];
      if (value != "factor" && value != "skin")
        fail("fix fluid/le: keyword reach expects factor or skin, got " + value);
      reach_by_skin_ = value == "skin";
      i += 2;
    } else if (key == "sums") {
      need(1);
      const std::string value = arg[i + 1];
      if (value != "every" && value != "sampled")
        fail("fix fluid/le: keyword sums expects every or sampled, got " + value);
      sums_every_step_ = value == "every";
      i += 2;
    } else {
      fail("fix fluid/le: unknown keyword " + key +
           " (expected viscosity, permeability, sphericity, drag, rotation, lubrication, "
           "tangential, reach, sums)");
    }
  }
  if (!have_viscosity || !have_permeability)
    fail(
        "fix fluid/le: needs 'viscosity ETA' and 'permeability NAME' (seed_eq26, kozeny_carman, "
        "ergun)");
  if (settings_.lubrication) {
    // Reach of the granular list (see init()): register the contact distance factor now, from
    // the particles that exist when the fix is defined, since the pair style's cutoff is set in
    // force->init() before any fix's init().
    double r_min = std::numeric_limits<double>::infinity();
    for (int i = 0; i < atom->nlocal; ++i)
      if (atom->mask[i] & groupbit) r_min = std::min(r_min, atom->radius[i]);
    double r_min_all = r_min;
    MPI_Allreduce(&r_min, &r_min_all, 1, MPI_DOUBLE, MPI_MIN, world);
    if (reach_by_skin_) {
      deck_skin_ = neighbor->skin;
      raised_skin_ = deck_skin_ + settings_.maximum_gap;
      neighbor->skin = raised_skin_;
      force_reneighbor = 1;
      next_reneighbor = -1;
    } else if (std::isfinite(r_min_all) && r_min_all > 0.0) {
      neighbor->register_contact_dist_factor(1.0 + settings_.maximum_gap / (2.0 * r_min_all));
    }
  }
  vector_flag = 1;
  size_vector = vec::size;
  global_freq = 1;
  extvector = 0;    // stresses, rates and counts: never normalised by the number of atoms
  virial_flag = 1;  // compute pressure adds virial[] (lubrication + drag)
  for (double& w : virial) w = 0.0;
}

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

// Positions of the owned atoms and the box corners at the last neighbour build (`reach skin`).
void FixFluidLE::hold_build_positions() {
  const std::size_t n = 3 * std::size_t(atom->nlocal);
  if (x_at_build_.size() < n) x_at_build_.resize(n + n / 2);  // grows with nlocal only
  if (n > 0) std::copy(atom->x[0], atom->x[0] + n, x_at_build_.begin());
  domain->box_corners();
  for (int c = 0; c < 8; ++c)
    for (int a = 0; a < 3; ++a) corners_at_build_[c][a] = domain->corners[c][a];
  hold_build_ = neighbor->ncalls;
}

// `reach skin`: LAMMPS' Neighbor::check_distance with half the deck's skin instead of half the
// raised one. Between builds a pair's distance changes by at most twice the largest atom
// displacement plus the two largest box-corner displacements (ghost images move with the box), so
// rebuilding before that reaches the deck's skin keeps every pair with h < HMAX in the list built
// with reach r_i + r_j + deck skin + HMAX. Runs after the position update, before
// neighbor->decide() reads next_reneighbor.
void FixFluidLE::post_integrate() {
  if (!settings_.lubrication || hold_build_ < 0) return;
  domain->box_corners();
  double largest = 0.0, second = 0.0;
  for (int c = 0; c < 8; ++c) {
    double sq = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double d = domain->corners[c][a] - corners_at_build_[c][a];
      sq += d * d;
    }
    const double moved = std::sqrt(sq);
    if (moved > largest) {
      second = largest;
      largest = moved;
    } else if (moved > second) {
      second = moved;
    }
  }
  const double trigger = 0.5 * (deck_skin_ - (largest + second));
  int rebuild = trigger <= 0.0 ? 1 : 0;
  const double trigger_sq = trigger * trigger;
  const double* x = atom->x[0];
  const double* held = x_at_build_.data();
  const int n = 3 * atom->nlocal;
  for (int k = 0; k < n && !rebuild; k += 3) {
    const double dx = x[k] - held[k], dy = x[k + 1] - held[k + 1], dz = x[k + 2] - held[k + 2];
    rebuild = dx * dx + dy * dy + dz * dz > trigger_sq;
  }
  int rebuild_any = rebuild;
  MPI_Allreduce(&rebuild, &rebuild_any, 1, MPI_INT, MPI_MAX, world);
  if (rebuild_any) next_reneighbor = update->ntimestep;
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

// Which ghosts are periodic images of atoms owned by this rank (atom->map gives the owned copy
// of a tag when this rank has one, LAMMPS' convention); without a map, none is.
void FixFluidLE::update_ghost_owners() {
  const int nlocal = atom->nlocal, nghost = atom->nghost;
  if (ghost_owner_.size() < std::size_t(nghost)) ghost_owner_.resize(nghost + nghost / 2);
  for (int g = 0; g < nghost; ++g) {
    int owner = -1;
    if (atom->map_style != 0) {
      const int k = atom->map(atom->tag[nlocal + g]);
      if (k >= 0 && k < nlocal) owner = k;
    }
    ghost_owner_[g] = owner;
  }
  ghost_owner_build_ = neighbor->ncalls;
}

// The lubrication candidates: every pair of the granular half list (newton off) whose
// lubrication this rank computes, rebuilt with the list (neighbor->ncalls counts the builds) and
// at setup, ordered [owned j | periodic image | other rank]. A pair with an owned j is listed
// once and updates both. A pair with a ghost j is listed by both owners: if j's atom is owned by
// this rank too (a periodic image: on one rank every ghost is), the pair is kept once, by the
// owner with the smaller tag (a sphere and its own image, only in boxes narrower than the list
// reach, stays in the half-weight group), and updates i and j's atom (target); if j's atom is on
// another rank, each owner applies its own half and counts the virial and dissipation with
// weight 1/2. Group membership is applied here too. Per step only the distance test remains.
void FixFluidLE::update_candidates() {
  if (ghost_owner_build_ != neighbor->ncalls) update_ghost_owners();
  const LAMMPS_NS::NeighList* list = force->pair->list;
  const int* mask = atom->mask;
  const int* tag = atom->tag;
  const int nlocal = atom->nlocal;
  const bool whole_system = groupbit == 1;  // group all: every atom (and ghost) is in it
  Candidates& c = candidates_;
  for (auto* kind : {&c.owned, &c.images, &c.remote}) kind->clear();  // capacity is kept
  for (int ii = 0; ii < list->inum; ++ii) {
    const int i = list->ilist[ii];
    if (!(mask[i] & groupbit)) continue;
    const int* jlist = list->firstneigh[i];
    for (int jj = 0; jj < list->numneigh[i]; ++jj) {
      const int j = jlist[jj] & NEIGHMASK;
      if (!whole_system && !(mask[j] & groupbit)) continue;
      if (j < nlocal) {
        c.owned.push_back({i, j, j});
        continue;
      }
      const int owner = ghost_owner_[j - nlocal];
      if (owner >= 0 && tag[i] != tag[j]) {
        if (tag[i] < tag[j]) c.images.push_back({i, j, owner});
      } else {
        c.remote.push_back({i, j, -1});
      }
    }
  }
  c.all.clear();
  for (auto* kind : {&c.owned, &c.images, &c.remote})
    c.all.insert(c.all.end(), kind->begin(), kind->end());
  c.end[0] = c.owned.size();
  c.end[1] = c.end[0] + c.images.size();
  c.end[2] = c.end[1] + c.remote.size();
  pairs_.grow(c.all.size());
  c.build = neighbor->ncalls;
}

namespace {

// Pass 4 of the pair loop for one kind of pair: forces, torques and, when the step's sums are
// wanted, virials and dissipation. Kind 0: owned j (j updated); 1: periodic image (j's atom,
// target, updated); 2: j on another rank (j left to its owner; the caller weights the sums 1/2).
struct PairForceArrays {
  const int *i, *j, *target;
  const double *inverse_distance, *normal, *tangential;
  const double *radius, *x, *v, *omega;
  double *f, *torque;
};
struct PairForceSums {
  double normal[6] = {0, 0, 0, 0, 0, 0}, tangential[6] = {0, 0, 0, 0, 0, 0}, dissipation = 0.0;
};

template <int kind, bool tangential, bool sums>
PairForceSums pair_forces(const PairForceArrays& a, std::size_t begin, std::size_t end) {
  const int* __restrict pair_i = a.i;
  const int* __restrict pair_j = a.j;
  const int* __restrict pair_target = a.target;
  const double* __restrict radius = a.radius;
  const double* __restrict xf = a.x;
  const double* __restrict vf = a.v;
  const double* __restrict wf = a.omega;
  double* __restrict ff = a.f;
  double* __restrict tf = a.torque;
  constexpr bool j_updated = kind < 2;
  double sn[6] = {0, 0, 0, 0, 0, 0}, st[6] = {0, 0, 0, 0, 0, 0}, dissipation = 0.0;
  for (std::size_t p = begin; p < end; ++p) {
    const int i = pair_i[p], j = pair_j[p];
    const int jt = pair_target[p];  // where j's force and torque go (kinds 0 and 1)
    const double del[3] = {xf[3 * i] - xf[3 * j], xf[3 * i + 1] - xf[3 * j + 1],
                           xf[3 * i + 2] - xf[3 * j + 2]};
    const double inverse_r = a.inverse_distance[p];
    const double n[3] = {del[0] * inverse_r, del[1] * inverse_r,
                         del[2] * inverse_r};  // from j to i
    // Ghost velocities carry the Lees-Edwards shift (fix deform remap v).
    const double dv[3] = {vf[3 * i] - vf[3 * j], vf[3 * i + 1] - vf[3 * j + 1],
                          vf[3 * i + 2] - vf[3 * j + 2]};
    const double vn = dv[0] * n[0] + dv[1] * n[1] + dv[2] * n[2];
    const double fn = -a.normal[p] * vn;  // F_n = -c_n v_n n
    double F[3] = {fn * n[0], fn * n[1], fn * n[2]};
    if constexpr (sums) {
      dissipation -= fn * vn;  // c_n v_n²
      sn[0] += del[0] * F[0];
      sn[1] += del[1] * F[1];
      sn[2] += del[2] * F[2];
      sn[3] += del[0] * F[1];
      sn[4] += del[0] * F[2];
      sn[5] += del[1] * F[2];
    }
    if constexpr (tangential) {
      const double ri = radius[i], rj = radius[j];
      // tangential part of the relative surface velocity at the gap,
      // v_t = v_ij - (r_i ω_i + r_j ω_j) × n - v_n n (the cross product is normal to n)
      const double s[3] = {ri * wf[3 * i] + rj * wf[3 * j], ri * wf[3 * i + 1] + rj * wf[3 * j + 1],
                           ri * wf[3 * i + 2] + rj * wf[3 * j + 2]};
      const double vt[3] = {dv[0] - vn * n[0] - (s[1] * n[2] - s[2] * n[1]),
                            dv[1] - vn * n[1] - (s[2] * n[0] - s[0] * n[2]),
                            dv[2] - vn * n[2] - (s[0] * n[1] - s[1] * n[0])};
      const double ct = a.tangential[p];
      const double Ft[3] = {-ct * vt[0], -ct * vt[1], -ct * vt[2]};
      if constexpr (sums) {
        dissipation -= Ft[0] * vt[0] + Ft[1] * vt[1] + Ft[2] * vt[2];  // c_t |v_t|²
        st[0] += del[0] * Ft[0];
        st[1] += del[1] * Ft[1];
        st[2] += del[2] * Ft[2];
        st[3] += del[0] * Ft[1];
        st[4] += del[0] * Ft[2];
        st[5] += del[1] * Ft[2];
      }
      for (int c = 0; c < 3; ++c) F[c] += Ft[c];
      // torque of F_t at the surface point -r_i n of i (and +r_j n with -F_t on j)
      const double nxF[3] = {n[1] * Ft[2] - n[2] * Ft[1], n[2] * Ft[0] - n[0] * Ft[2],
                             n[0] * Ft[1] - n[1] * Ft[0]};
      for (int c = 0; c < 3; ++c) tf[3 * i + c] -= ri * nxF[c];
      if constexpr (j_updated)
        for (int c = 0; c < 3; ++c) tf[3 * jt + c] -= rj * nxF[c];
    }
    for (int c = 0; c < 3; ++c) ff[3 * i + c] += F[c];
    if constexpr (j_updated)
      for (int c = 0; c < 3; ++c) ff[3 * jt + c] -= F[c];
  }
  PairForceSums out;
  for (int k = 0; k < 6; ++k) {
    out.normal[k] = sn[k];
    out.tangential[k] = st[k];
  }
  out.dissipation = dissipation;
  return out;
}

template <bool tangential, bool sums>
std::array<PairForceSums, 3> pair_forces_all(const PairForceArrays& a,
                                             const std::size_t (&bounds)[4]) {
  return {pair_forces<0, tangential, sums>(a, bounds[0], bounds[1]),
          pair_forces<1, tangential, sums>(a, bounds[1], bounds[2]),
          pair_forces<2, tangential, sums>(a, bounds[2], bounds[3])};
}

}  // namespace

// Normal and tangential lubrication of the candidate pairs within h_max, in four passes over
// flat arrays, so that each is a short loop of independent iterations (no long sqrt -> division
// -> log -> force dependency chain per pair):
//   1. select the candidates within h_max, compacted without a data-dependent branch, kinds in
//      order [owned j | periodic image | other rank];
//   2. geometry and resistances (pair_lubrication_terms: one sqrt and one division per pair);
//   3. the log(1/ξ) of the tangential mode, all pairs back to back;
//   4. forces, torques and (on the steps that want them) virials and dissipation.
void FixFluidLE::lubrication_forces(std::array<double, vec::size>& acc, bool sums) {
  if (reach_by_skin_ && hold_build_ != neighbor->ncalls) hold_build_positions();
  if (candidates_.build != neighbor->ncalls) update_candidates();
  const double eta = settings_.liquid.viscosity;
  const double h_max = settings_.maximum_gap, h_min = settings_.minimum_gap;
  const bool tangential = settings_.tangential_lubrication;
  // Flat views of the per-atom arrays (LAMMPS allocates each as one contiguous block), so a
  // neighbour costs one load per quantity instead of a pointer chase.
  const double* __restrict radius = atom->radius;
  const double* __restrict xf = atom->x[0];
  int* __restrict pair_i = pairs_.i.data();
  int* __restrict pair_j = pairs_.j.data();
  int* __restrict pair_target = pairs_.target.data();
  double* __restrict inverse_distance = pairs_.inverse_distance.data();
  double* __restrict normal = pairs_.normal.data();
  double* __restrict tangential_resistance = pairs_.tangential.data();
  double* __restrict log_argument = pairs_.log_argument.data();

  // Pass 1. Every slot is written and the counter advances for a pair within h_max.
  const Candidate* __restrict candidate = candidates_.all.data();
  std::size_t bounds[4] = {0, 0, 0, 0}, n = 0;
  for (int kind = 0; kind < 3; ++kind) {
    for (std::size_t c = kind == 0 ? 0 : candidates_.end[kind - 1]; c < candidates_.end[kind];
         ++c) {
      const int i = candidate[c].i, j = candidate[c].j;
      const double del[3] = {xf[3 * i] - xf[3 * j], xf[3 * i + 1] - xf[3 * j + 1],
                             xf[3 * i + 2] - xf[3 * j + 2]};
      const double rsq = del[0] * del[0] + del[1] * del[1] + del[2] * del[2];
      const double reach = radius[i] + radius[j] + h_max;
      pair_i[n] = i;
      pair_j[n] = j;
      pair_target[n] = candidate[c].target;
      n += rsq < reach * reach;
    }
    bounds[kind + 1] = n;
  }

  // Pass 2.
  for (std::size_t p = 0; p < n; ++p) {
    const int i = pair_i[p], j = pair_j[p];
    const double del[3] = {xf[3 * i] - xf[3 * j], xf[3 * i + 1] - xf[3 * j + 1],
                           xf[3 * i + 2] - xf[3 * j + 2]};
    const double r = std::sqrt(del[0] * del[0] + del[1] * del[1] + del[2] * del[2]);
    const PairLubricationTerms t = pair_lubrication_terms(eta, radius[i], radius[j], r, h_min);
    inverse_distance[p] = t.inverse_distance;
    normal[p] = t.normal;
    tangential_resistance[p] = t.tangential_prefactor;
    log_argument[p] = t.log_argument;
  }

  // Pass 3: c_t = prefactor × ln(1/ξ).
  if (tangential)
    for (std::size_t p = 0; p < n; ++p) tangential_resistance[p] *= std::log(log_argument[p]);

  // Pass 4 (sums in registers, weighted at the end).
  const PairForceArrays arrays{
      pair_i, pair_j, pair_target, inverse_distance, normal,     tangential_resistance,
      radius, xf,     atom->v[0],  atom->omega[0],   atom->f[0], atom->torque[0]};
  if (!sums) {
    if (tangential)
      pair_forces_all<true, false>(arrays, bounds);
    else
      pair_forces_all<false, false>(arrays, bounds);
    return;
  }
  const std::array<PairForceSums, 3> k = tangential ? pair_forces_all<true, true>(arrays, bounds)
                                                    : pair_forces_all<false, true>(arrays, bounds);
  for (int c = 0; c < 6; ++c) {
    acc[vec::lubrication_normal + c] = k[0].normal[c] + k[1].normal[c] + 0.5 * k[2].normal[c];
    acc[vec::lubrication_tangential + c] =
        k[0].tangential[c] + k[1].tangential[c] + 0.5 * k[2].tangential[c];
  }
  acc[vec::lubricated_pairs] = double(bounds[2]) + 0.5 * double(bounds[3] - bounds[2]);
  acc[vec::lubrication_dissipation] = k[0].dissipation + k[1].dissipation + 0.5 * k[2].dissipation;
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

}  // namespace

LAMMPS_NS::Fix* create_fix_fluid_le(LAMMPS_NS::LAMMPS* lmp, int narg, char** arg) {
  return new FixFluidLE(lmp, narg, arg);
}

}  // namespace granflow::dem
