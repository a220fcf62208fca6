// fix fluid/le: its arguments (syntax in fix_fluid_le.hpp).
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

bool FixFluidLE::parse_yes_no(const char* keyword, const char* value) const {
  if (std::strcmp(value, "yes") == 0) return true;
  if (std::strcmp(value, "no") == 0) return false;
  fail(std::string("fix fluid/le: keyword ") + keyword + " expects yes or no, got " + value);
  return false;
}

namespace {

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

}  // namespace

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

}  // namespace granflow::dem::fluid_le_detail
