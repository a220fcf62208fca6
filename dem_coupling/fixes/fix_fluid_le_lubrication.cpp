// fix fluid/le: the normal and tangential lubrication of the candidate pairs (docs/dem_fluid.md).
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

}  // namespace granflow::dem::fluid_le_detail
