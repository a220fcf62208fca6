// Conduction of the granular temperature among the solid points through the nodes (seed section
// 5): q = -κ_T ∇T with a constant κ_T or the one each material reports per point.
#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <type_traits>
#include <vector>

#include "continuum/mpm/solver_internal.hpp"

namespace granflow::mpm {

using namespace solver_internal;

template <class G, ShapeKind S>
void Solver::conduct_temperature(const G& grid) {
  cache_[0].valid = true;
  long negative = -1;
  // One parallel region (as the grid part of the step, solver_maps.cpp): each piece on the
  // thread's fixed chunk of points or share of nodes, the pieces separated by barriers; the
  // per-thread scatters are reduced in thread order (reproducible for a thread count). Inside the
  // step's own region the step calls conduct_part itself.
  if (threads_ == 1) {
    negative = conduct_part<G, S>(grid, 0);
  } else {
#pragma omp parallel num_threads(threads_) reduction(max : negative)
    negative = std::max(negative, conduct_part<G, S>(grid, omp_get_thread_num()));
  }
  throw_if_negative_temperature(negative);
}

void Solver::throw_if_negative_temperature(long negative) const {
  if (negative >= 0) {
    throw core::NumericalFailure(step_ + 1, fmt::format("solid point {}", negative), "temperature",
                                 solid_.temperature[negative],
                                 "negative or non-finite granular temperature");
  }
}

// Thread t's part of the conduction; every thread of the team calls it (or the one thread). Returns
// the last point of its chunk whose T went negative or non-finite, -1 if none.
template <class G, ShapeKind S>
long Solver::conduct_part(const G& grid, int t) {
  const int nn = nn_, T = threads_;
  const double kappa = options_.temperature_conductivity, dt = dt_;
  SolidPoints& sp = solid_;
  double* nodal_T = nodal_temperature_.data();
  double* capacity = heat_capacity_.data();
  int nb, ne;
  node_share(nn, t, T, nb, ne);
  std::size_t b, e;
  chunk(sp.size(), t, T, b, e);
  Stencil st{};
  // the nodes the thread's points touch: the same in pieces 1 and 2 (same points, same cached
  // stencils), so taken once (a min/max over each stencil's nodes per point)
  NodeSpan span;
  // 1. nodal heat capacity C_a = Σ N_a (3/2) m and C_a T_a = Σ N_a (3/2) m T
  {
    double* acc = scatter_buffer(t, 2);
    for (std::size_t p = b; p < e; ++p) {
      if (!locate<G, S>(grid, 0, p, st)) continue;  // caught in the next map
      if (T > 1) {
        if constexpr (std::is_same_v<G, PolarGrid>)  // the cached stencil's two rows
          span.add_rows(cache_[0].quad[p].node[0], cache_[0].quad[p].node[1]);
        else
          span.add<G>(st);
      }
      const double c = 1.5 * sp.mass[p], cT = c * sp.temperature[p];
      for (int k = 0; k < st.count; ++k) {
        acc[st.node[k]] += st.N[k] * c;
        acc[nn + st.node[k]] += st.N[k] * cT;
      }
    }
    mark_dirty(t, 2, span.begin, span.end, span.wrap_end);
  }
  if (T > 1) {
#pragma omp barrier
  }
  reduce_part(2, t);
  for (int a = nb; a < ne; ++a) {
    capacity[a] = acc_[a];
    nodal_T[a] = acc_[a] > 0 ? acc_[nn + a] / acc_[a] : 0.0;
  }
  if (T > 1) {
#pragma omp barrier
  }
  // 2. ∇T at the points and the nodal heat flow -Σ ∇N_a · q V, q = κ ∇T
  {
    double* acc = scatter_buffer(t, 1);
    for (std::size_t p = b; p < e; ++p) {
      if (!locate<G, S>(grid, 0, p, st)) continue;
      double gx = 0, gy = 0;
      for (int k = 0; k < st.count; ++k) {
        gx += st.dNdx[k] * nodal_T[st.node[k]];
        gy += st.dNdy[k] * nodal_T[st.node[k]];
      }
      temperature_gradient_x_[p] = gx;
      temperature_gradient_y_[p] = gy;
      const double kappa_p = options_.material_conductivity ? point_conductivity_[p] : kappa;
      const double qx = kappa_p * gx * sp.volume[p];
      const double qy = kappa_p * gy * sp.volume[p];
      for (int k = 0; k < st.count; ++k) acc[st.node[k]] -= st.dNdx[k] * qx + st.dNdy[k] * qy;
    }
    mark_dirty(t, 1, span.begin, span.end, span.wrap_end);
  }
  if (T > 1) {
#pragma omp barrier
  }
  reduce_part(1, t);
  for (int a = nb; a < ne; ++a)
    acc_[a] = capacity[a] > 0 ? dt * acc_[a] / capacity[a] : 0.0;  // ΔT_a
  if (T > 1) {
#pragma omp barrier
  }
  // 3. remap of the nodal change ΔT_a to the points. Heating: N_a ΔT_a (additive). Cooling:
  // each point gives up its share in proportion to its own T, N_a ΔT_a T_p / T_a, with T_a the
  // capacity-weighted nodal T. Both conserve the energy of node a exactly
  // (Σ_p c_p N_a ΔT_a T_p / T_a = ΔT_a C_a), and a cooling point keeps T_p ≥ 0 whenever the
  // nodal update keeps T_a + ΔT_a ≥ 0 (the explicit conduction limit), which the additive form
  // does not guarantee for a cold point next to hot ones.
  const double* A = acc_.data();
  long bad = -1;
  for (std::size_t p = b; p < e; ++p) {
    if (!locate<G, S>(grid, 0, p, st)) continue;
    const double Tp = sp.temperature[p];
    double dT = 0;
    for (int k = 0; k < st.count; ++k) {
      const int a = st.node[k];
      const double dTa = A[a];
      if (dTa >= 0.0)
        dT += st.N[k] * dTa;
      else if (nodal_T[a] > 0.0)
        dT += st.N[k] * dTa * (Tp / nodal_T[a]);
    }
    sp.temperature[p] = Tp + dT;
    if (!(sp.temperature[p] >= 0.0)) bad = static_cast<long>(p);
  }
  return bad;
}

// For the grids and shapes step() runs (solver_maps.cpp).
template void Solver::conduct_temperature<CartesianGrid, ShapeKind::linear>(const CartesianGrid&);
template void Solver::conduct_temperature<CartesianGrid, ShapeKind::gimp>(const CartesianGrid&);
template void Solver::conduct_temperature<PolarGrid, ShapeKind::linear>(const PolarGrid&);
template long Solver::conduct_part<CartesianGrid, ShapeKind::linear>(const CartesianGrid&, int);
template long Solver::conduct_part<CartesianGrid, ShapeKind::gimp>(const CartesianGrid&, int);
template long Solver::conduct_part<PolarGrid, ShapeKind::linear>(const PolarGrid&, int);

}  // namespace granflow::mpm
