// Internals shared by the solver_*.cpp files (continuum/mpm/solver.hpp has the class): the layout
// of the nodal accumulators, the fixed split of points and nodes among the threads, and the
// member templates that more than one of those files instantiates (the per-thread scatter with its
// reproducible reduction, the point stencils, the liquid volume sums). Not part of the interface.
#pragma once

#include <omp.h>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <optional>
#include <type_traits>
#include <utility>

#include "continuum/model/exp_near_zero.hpp"
#include "continuum/mpm/solver.hpp"

namespace granflow::mpm::solver_internal {

// Nodal accumulators of the first map, field-major (field k of node a at k * nodes + a). Solid
// fields first, so a dry run reduces only those.
enum Field : int { MS, PXS, PYS, FXS, FYS, NMS, ML, PXL, PYL, FXL, FYL, GLX, GLY, CD, NF };
inline constexpr int solid_fields = 6;
// Accumulators of the MUSL momentum remap (reuse the first fields of the same buffer).
enum RemapField : int { R_MS, R_PXS, R_PYS, R_ML, R_PXL, R_PYL };

inline constexpr double inf = std::numeric_limits<double>::infinity();

inline double sign(double v) { return v > 0.0 ? 1.0 : (v < 0.0 ? -1.0 : 0.0); }

// Thread t's fixed contiguous chunk [b, e) of n points (or nodes) among T threads.
inline void chunk(std::size_t n, int t, int T, std::size_t& b, std::size_t& e) {
  b = n * t / T;
  e = n * (t + 1) / T;
}
inline void node_share(int nn, int t, int T, int& b, int& e) {
  b = static_cast<int>(static_cast<long>(nn) * t / T);
  e = static_cast<int>(static_cast<long>(nn) * (t + 1) / T);
}

// V = m / (n ρ_w), ρ_w = ρ_w0 exp(p / K_w): the mixture volume a liquid point of mass m stands
// for, as m (1/n)(1/ρ_w0) exp(−p/K_w), so that its only division, 1/n, is shared with the
// storage equation (one function wherever a liquid point's volume is computed).
inline double liquid_point_volume(double m, double inv_n, double inv_rho0, double p, double inv_K) {
  return m * inv_n * inv_rho0 * model::exp_near_zero(-p * inv_K);
}

// Linear shapes have stencils of a fixed width (the 4 nodes of the cell) on both grids, which
// solver_quad.cpp maps with packed operations; GIMP uses Stencil.
template <class G, ShapeKind S>
inline constexpr bool fixed_quad = S == ShapeKind::linear;

// The span [begin, end) of nodes a thread's scatter touched.
struct NodeSpan {
  int begin = std::numeric_limits<int>::max(), end = 0;
  int wrap_end = 0;  // [0, wrap_end): the polar grid's first rays, reached across θ = 0
  // The rows (n0, n0 + 1) and (n1, n1 + 1) of a polar quad stencil (rays j and j + 1); n1 < n0
  // when ray j + 1 is ray 0 (the seam).
  void add_rows(int n0, int n1) {
    begin = std::min(begin, n0);
    if (n1 > n0) {
      end = std::max(end, n1 + 2);
    } else {
      end = std::max(end, n0 + 2);
      wrap_end = std::max(wrap_end, n1 + 2);
    }
  }
  template <class G>
  void add(const Stencil& st) {
    if constexpr (std::is_same_v<G, CartesianGrid>) {
      // Cartesian stencils list their nodes in increasing order (j outer, i inner).
      if (st.count == 0) return;
      begin = std::min(begin, st.node[0]);
      end = std::max(end, st.node[st.count - 1] + 1);
    } else {  // polar: the θ direction wraps around
      for (int k = 0; k < st.count; ++k) {
        begin = std::min(begin, st.node[k]);
        end = std::max(end, st.node[k] + 1);
      }
    }
  }
};

// P2G of one point: its loads, and their scatter to a node (or to a row of two adjacent nodes,
// Value = Eigen::Array2d, solver_quad.cpp) with the node's shape value N and gradient (dx, dy).
// One body for the general and the fixed-stencil maps, so both add the same terms in the same
// order. `at(field)` gives the node's (or row's) entry of a nodal field, a reference or a map.
struct SolidLoad {
  double mi, mvx, mvy, mn, fx, fy, sxx, syy, sxy;
};
// m_i = m s (mass scaling s), m v, m n, f_ext = m g + point load, σ' V.
inline SolidLoad solid_load(const SolidPoints& sp, std::size_t p, double s, double gx, double gy) {
  const double m = sp.mass[p], mi = m * s, V = sp.volume[p];
  return {mi,
          mi * sp.vx[p],
          mi * sp.vy[p],
          m * sp.porosity[p],
          m * gx + sp.fx_ext[p],
          m * gy + sp.fy_ext[p],
          sp.sxx[p] * V,
          sp.syy[p] * V,
          sp.sxy[p] * V};
}
// The solid loads into the accumulator acc (field-major, nn nodes per field: MS, PXS, ...).
template <class Value, class At>
inline void scatter_solid(const SolidLoad& L, const Value& N, const Value& dx, const Value& dy,
                          double* acc, int nn, At at) {
  at(acc + MS * nn) += N * L.mi;
  at(acc + PXS * nn) += N * L.mvx;
  at(acc + PYS * nn) += N * L.mvy;
  // f_int = -∫ ∇N · σ' dV ; f_ext = N (m g + point load)
  at(acc + FXS * nn) += N * L.fx - (dx * L.sxx + dy * L.sxy);
  at(acc + FYS * nn) += N * L.fy - (dx * L.sxy + dy * L.syy);
  at(acc + NMS * nn) += N * L.mn;
}
struct LiquidLoad {
  double mi, mvx, mvy, fx, fy, sxx, syy, sxy, beta_V;
};
// As solid_load, with the liquid stress σ_L = -p I + τ acting on the mixture volume V of the
// point, and the drag coefficient times V.
inline LiquidLoad liquid_load(const LiquidPoints& lp, std::size_t p, double s, double gx,
                              double gy) {
  const double m = lp.mass[p], mi = m * s, V = lp.volume[p];
  return {mi,
          mi * lp.vx[p],
          mi * lp.vy[p],
          m * gx + lp.fx_ext[p],
          m * gy + lp.fy_ext[p],
          (lp.txx[p] - lp.pressure[p]) * V,
          (lp.tyy[p] - lp.pressure[p]) * V,
          lp.txy[p] * V,
          lp.drag[p] * V};
}
// The liquid loads into the accumulator acc (ML, PXL, ... fields).
template <class Value, class At>
inline void scatter_liquid(const LiquidLoad& L, const Value& N, const Value& dx, const Value& dy,
                           double* acc, int nn, At at) {
  at(acc + ML * nn) += N * L.mi;
  at(acc + PXL * nn) += N * L.mvx;
  at(acc + PYL * nn) += N * L.mvy;
  at(acc + FXL * nn) += N * L.fx;
  at(acc + FYL * nn) += N * L.fy;
  at(acc + GLX * nn) -= dx * L.sxx + dy * L.sxy;
  at(acc + GLY * nn) -= dx * L.sxy + dy * L.syy;
  at(acc + CD * nn) += N * L.beta_V;
}

}  // namespace granflow::mpm::solver_internal

namespace granflow::mpm {

// Run `body(acc, t, T)` on every thread with its own zeroed accumulator of `fields` fields, then
// sum the per-thread accumulators into acc_ in thread order (deterministic for a thread count).
template <class Body>
void Solver::scatter(int fields, Body&& body) {
  if (threads_ == 1) {
    body(scatter_buffer(0, fields), 0, 1);
    return;
  }
#pragma omp parallel num_threads(threads_)
  {
    const int t = omp_get_thread_num();
    body(scatter_buffer(t, fields), t, threads_);
    mark_dirty(t, fields, 0, nn_);
#pragma omp barrier
    reduce_part(fields, t);
  }
}

template <class G, ShapeKind S>
inline bool Solver::locate(const G& grid, int phase, std::size_t p, Stencil& st) {
  const PointFields& pts = phase == 0 ? static_cast<const PointFields&>(solid_)
                                      : static_cast<const PointFields&>(liquid_);
  if constexpr (std::is_same_v<G, PolarGrid>) {
    static_assert(S == ShapeKind::linear);
    StencilCache& c = cache_[phase];
    QuadStencil& q = c.quad[p];
    if (!c.valid && !grid.quad(pts.x[p], pts.y[p], c.sector[p], q)) q.node[0] = -1;
    if (q.node[0] < 0) return false;
    st.count = 4;
    for (int k = 0; k < 4; ++k) {
      st.node[k] = q.node[k / 2] + k % 2;
      st.N[k] = q.N[k];
      st.dNdx[k] = q.dNdx[k];
      st.dNdy[k] = q.dNdy[k];
    }
    return true;
  } else {
    // Cartesian: locating is a few flops, cheaper than reading a cache.
    return grid.template stencil<S>(pts.x[p], pts.y[p], options_.gimp_half_length_x,
                                    options_.gimp_half_length_y, st);
  }
}

inline void Solver::store_gradient(PointFields& pts, long p, double Lxx, double Lxy, double Lyx,
                                   double Lyy, bool extras, double div_s, double n_at,
                                   int first_node) {
  pts.Lxx[p] = Lxx;
  pts.Lxy[p] = Lxy;
  pts.Lyx[p] = Lyx;
  pts.Lyy[p] = Lyy;
  if (extras) {
    div_solid_[p] = div_s;
    liquid_cell_[p] = first_node;
    liquid_.porosity[p] = std::clamp(n_at, 1e-3, 1.0);  // floor: a point never sees n = 0
  }
}

// Σ_p V_p x_p and Σ_p V_p over the liquid points whose value(p) gives an x_p (per-point work may
// happen inside value); fixed chunks per thread added in thread order, so the result is
// reproducible for a thread count (unlike an OpenMP reduction's arrival order).
template <class PointValue>
std::pair<double, double> Solver::liquid_volume_sums(PointValue&& value) {
  auto part = [&](int t) {
    std::size_t b, e;
    solver_internal::chunk(liquid_.size(), t, threads_, b, e);
    double weighted = 0.0, volume = 0.0;
    for (std::size_t p = b; p < e; ++p) {
      const std::optional<double> x = value(p);
      if (!x) continue;
      weighted += liquid_.volume[p] * *x;
      volume += liquid_.volume[p];
    }
    slots_[t].sum[0] = weighted;
    slots_[t].sum[1] = volume;
  };
  if (threads_ == 1) {
    part(0);
  } else {
#pragma omp parallel num_threads(threads_)
    part(omp_get_thread_num());
  }
  double weighted = 0.0, volume = 0.0;
  for (const auto& slot : slots_) {
    weighted += slot.sum[0];
    volume += slot.sum[1];
  }
  return {weighted, volume};
}

}  // namespace granflow::mpm
