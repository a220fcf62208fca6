// fix drainage (syntax, equations and the global vector in fix_drainage.hpp).
#include "dem_coupling/fixes/fix_drainage.hpp"

#include <fmt/format.h>
#include <mpi.h>

#include <cmath>
#include <cstdlib>
#include <numbers>
#include <string>

#include "atom.h"
#include "compute.h"
#include "continuum/model/closures.hpp"
#include "dem_coupling/fixes/fix_fluid_le.hpp"
#include "domain.h"
#include "error.h"
#include "fix.h"
#include "lammps.h"
#include "modify.h"
#include "update.h"

namespace granflow::dem {
namespace {

class FixDrainage : public LAMMPS_NS::Fix {
 public:
  FixDrainage(LAMMPS_NS::LAMMPS* lmp, int narg, char** arg) : Fix(lmp, narg, arg) {
    const std::string law = narg > 5 ? arg[5] : "";
    if (!((law == "darcy" && narg == 8) || (law == "resistance" && narg == 7)))
      fail(
          "fix drainage: expected 'fix ID group drainage NORMAL_STRESS PRESSURE_ID darcy LENGTH "
          "FLUID_ID' or '... NORMAL_STRESS PRESSURE_ID resistance R'");
    normal_stress_ = number(arg[3], "NORMAL_STRESS");
    pressure_id_ = arg[4];
    if (law == "darcy") {
      length_ = number(arg[6], "LENGTH");
      fluid_id_ = arg[7];
    } else {
      resistance_ = number(arg[6], "R");
    }
    if (!(normal_stress_ > 0.0) || !(length_ > 0.0 || resistance_ > 0.0))
      fail("fix drainage: NORMAL_STRESS and LENGTH (or R) must be positive");
    box_change_size = 1;  // the box height changes every step (neighbour lists, remaps)
    no_change_box = 1;
    time_depend = 1;
    nevery = 1;
    vector_flag = 1;
    size_vector = 4;
    global_freq = 1;
    extvector = 0;
  }

  int setmask() override { return LAMMPS_NS::FixConst::END_OF_STEP; }

  void init() override {
    const int c = modify->find_compute(pressure_id_.c_str());
    if (c < 0 || !modify->compute[c]->pressflag)
      fail(fmt::format("fix drainage: {} is not a compute pressure", pressure_id_));
    pressure_ = modify->compute[c];
    if (resistance_ > 0.0) return;  // a damped height: no liquid, k = 1/R
    const int f = modify->find_fix(fluid_id_.c_str());
    liquid_ = f < 0 ? nullptr : fluid_le_liquid(modify->fix[f]);
    if (liquid_ == nullptr)
      fail(fmt::format("fix drainage: {} is not a fix fluid/le (the liquid that drains)",
                       fluid_id_));
    // Number-mean diameter and solid volume of the group (the permeability's d and ν).
    double local[3] = {0.0, 0.0, 0.0};  // Σ d, Σ π d³/6, count
    for (int i = 0; i < atom->nlocal; ++i)
      if (atom->mask[i] & groupbit) {
        const double d = 2.0 * atom->radius[i];
        local[0] += d, local[1] += std::numbers::pi / 6.0 * d * d * d, local[2] += 1.0;
      }
    double global[3];
    MPI_Allreduce(local, global, 3, MPI_DOUBLE, MPI_SUM, world);
    if (!(global[2] > 0.0)) fail("fix drainage: the group has no particles");
    diameter_ = global[0] / global[2];
    solid_volume_ = global[1];
  }

  void setup(int /*vflag*/) override {
    if (initial_height_ <= 0.0) initial_height_ = domain->yprd;
    update_coefficient();
    if (coefficient_ * normal_stress_ * update->dt > 0.01)
      fail(fmt::format(
          "fix drainage: k σ_n Δt = {:.3g} > 0.01: the height moves faster than the DEM time "
          "step resolves (k = {:.3g} 1/(Pa s)); use a longer drainage length or a larger "
          "resistance",
          coefficient_ * normal_stress_ * update->dt, coefficient_));
    pressure_->addstep(update->ntimestep + 1);
  }

  void end_of_step() override {
    modify->clearstep_compute();
    pressure_->compute_vector();
    double kinetic = 0.0;  // Σ m v_y², this rank
    for (int i = 0; i < atom->nlocal; ++i)
      if (atom->mask[i] & groupbit) kinetic += atom->rmass[i] * atom->v[i][1] * atom->v[i][1];
    double kinetic_all = 0.0;
    MPI_Allreduce(&kinetic, &kinetic_all, 1, MPI_DOUBLE, MPI_SUM, world);
    const double volume = domain->xprd * domain->yprd * domain->zprd;
    normal_stress_now_ = pressure_->vector[1] + kinetic_all / volume;
    pore_pressure_ = normal_stress_ - normal_stress_now_;
    update_coefficient();
    const double height = domain->yprd * (1.0 - coefficient_ * pore_pressure_ * update->dt);
    // Affine remap of the owned atoms about the lower face (fix deform's `remap x`).
    domain->x2lamda(atom->nlocal);
    domain->boxhi[1] = domain->boxlo[1] + height;
    domain->set_global_box();
    domain->set_local_box();
    domain->lamda2x(atom->nlocal);
    pressure_->addstep(update->ntimestep + 1);  // the virial is tallied on the next step
  }

  double compute_vector(int n) override {
    switch (n) {
      case 0:
        return initial_height_ > 0.0 ? std::log(initial_height_ / domain->yprd) : 0.0;
      case 1:
        return normal_stress_now_;
      case 2:
        return pore_pressure_;
      default:
        return coefficient_;
    }
  }

 private:
  // k = κ(ν) / (η0 H²) at the box's current solid fraction, or 1/R.
  void update_coefficient() {
    if (resistance_ > 0.0) {
      coefficient_ = 1.0 / resistance_;
      return;
    }
    const double nu = solid_volume_ / (domain->xprd * domain->yprd * domain->zprd);
    coefficient_ =
        model::permeability(*liquid_, diameter_, nu) / (liquid_->viscosity * length_ * length_);
  }
  double number(const char* text, const char* name) const {
    char* end = nullptr;
    const double v = std::strtod(text, &end);
    if (end == text || *end != '\0' || !std::isfinite(v))
      fail(fmt::format("fix drainage: {} must be a number, not '{}'", name, text));
    return v;
  }
  [[noreturn]] void fail(const std::string& message) const {
    error->all(FLERR, message.c_str());
    std::abort();  // error->all does not return
  }

  double normal_stress_ = 0, length_ = 0, resistance_ = 0;
  std::string pressure_id_, fluid_id_;
  LAMMPS_NS::Compute* pressure_ = nullptr;
  const model::LiquidParameters* liquid_ = nullptr;
  double diameter_ = 0, solid_volume_ = 0, initial_height_ = 0;
  double coefficient_ = 0, normal_stress_now_ = 0, pore_pressure_ = 0;
};

}  // namespace

LAMMPS_NS::Fix* create_fix_drainage(LAMMPS_NS::LAMMPS* lmp, int narg, char** arg) {
  return new FixDrainage(lmp, narg, arg);
}

}  // namespace granflow::dem
