// fix fluid/le: which pairs are within reach of the lubrication. `reach skin` keeps every pair
// with h < h_max in the granular list by forcing rebuilds (post_integrate); the candidates are
// the list's pairs this rank lubricates, rebuilt with the list, with the periodic images of
// owned atoms found once per build.
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

}  // namespace granflow::dem::fluid_le_detail
