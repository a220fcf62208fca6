// The particle-grid maps of the Solver's step (solver_maps.cpp has the general ones) for linear
// shapes, where every stencil is the 2 x 2 nodes of the point's cell: two rows of two adjacent
// nodes, on the Cartesian grid (a, a+1) and (a + nx + 1, a + nx + 2), on the polar grid (i, j),
// (i+1, j) and (i, j+1), (i+1, j+1) (QuadStencil). A row's shape values are one 2-vector
// (Eigen::Array2d), so a nodal field of a row is read or updated with one packed operation. On
// the Cartesian grid the points are located once per step in a loop the compiler vectorises
// (with 1/h for the division of CartesianGrid::stencil: ξ, η differ from its by an ulp), and the
// sums run in its node order (docs/mpm.md, docs/performance.md). On the polar grid the stencils
// of PolarGrid::quad are cached for the step; the sums run row by row (nodes (i,j), (i+1,j),
// (i,j+1), (i+1,j+1)), which changes round-off only against the general maps' order. With more
// than one thread, a point whose nodes lie in the thread's own node share is added straight into
// the reduced accumulator (OwnedNodes; Solver::scatter_buffer).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <type_traits>

#include "continuum/mpm/solver_internal.hpp"

namespace granflow::mpm {

using namespace solver_internal;

namespace {

using Pair = Eigen::Array2d;
using Row = Eigen::Map<Pair>;  // two adjacent nodes of a field (unaligned)
using ConstRow = Eigen::Map<const Pair>;

// The stencil of one point: bilinear (Q4) functions N = Nx(ξ) Ny(η), Nx = {1 - ξ, ξ},
// Ny = {1 - η, η}; ∂N/∂x = Nx'/h_x Ny, ∂N/∂y = Nx Ny'/h_y with Nx' = Ny' = {-1, 1}. Row r holds
// the nodes (i, j + r) and (i + 1, j + r).
struct QuadRows {
  int node[2];  // first node of each row
  Pair N[2], dNdx[2], dNdy[2];
};

// The located cells of one phase (Solver::cells_) and the grid constants the stencil needs.
struct CellView {
  const int* node;
  const double* xi;
  const double* eta;
  double inv_hx, inv_hy;  // 1/h_x, 1/h_y (−1/h = −(1/h) exactly, as the grid's −1.0/h)
  int row;                // nodes per grid row, nx + 1
  bool rows(std::size_t p, QuadRows& q) const {
    const int a = node[p];
    if (a < 0) return false;
    const double x = xi[p], y = eta[p];
    const Pair Nx(1.0 - x, x), dx(-inv_hx, inv_hx);
    const double Ny[2] = {1.0 - y, y}, dy[2] = {-inv_hy, inv_hy};
    for (int r = 0; r < 2; ++r) {
      q.node[r] = a + row * r;
      q.N[r] = Nx * Ny[r];
      q.dNdx[r] = dx * Ny[r];
      q.dNdy[r] = Nx * dy[r];
    }
    return true;
  }
};

// Σ_k w_k f(node_k) over the 4 nodes, added in the node order of CartesianGrid::stencil.
inline double dot(const QuadRows& q, const Pair* w, const double* f) {
  const Pair r0 = w[0] * ConstRow(f + q.node[0]), r1 = w[1] * ConstRow(f + q.node[1]);
  return ((r0(0) + r0(1)) + r1(0)) + r1(1);
}
inline double sum(const Pair& r0, const Pair& r1) { return ((r0(0) + r0(1)) + r1(0)) + r1(1); }

// The polar grid's located stencils (Solver::cache_, PolarGrid::quad) as QuadRows.
struct QuadView {
  const QuadStencil* quad;
  bool rows(std::size_t p, QuadRows& q) const {
    const QuadStencil& s = quad[p];
    if (s.node[0] < 0) return false;
    for (int r = 0; r < 2; ++r) {
      q.node[r] = s.node[r];
      q.N[r] = ConstRow(s.N + 2 * r);
      q.dNdx[r] = ConstRow(s.dNdx + 2 * r);
      q.dNdy[r] = ConstRow(s.dNdy + 2 * r);
    }
    return true;
  }
};

// The located stencils of one phase as QuadRows: the Cartesian grid's cells (Solver::cells_) or
// the polar grid's quads (Solver::cache_).
template <class G, class Cells, class Quads>
auto quad_rows(const G& grid, const Cells& c, const Quads& q) {
  if constexpr (std::is_same_v<G, CartesianGrid>)
    return CellView{c.node.data(), c.xi.data(), c.eta.data(),
                    c.inv_hx,      c.inv_hy,    grid.cells_x() + 1};
  else
    return QuadView{q.quad.data()};
}

// The velocity gradient L = Σ_a v_a ⊗ ∇N_a at one point and, with `extras` (liquid points),
// tr(D_S), the porosity n there and, with Forchheimer drag, |u_L - u_S|; handed to `store` as
// store(Lxx, Lxy, Lyx, Lyy, div_s, n_at) (Solver::store_gradient). One body for G2P (USL) and
// the separate gradient pass.
template <class Store>
inline void point_gradient(const QuadRows& q, const double* vx, const double* vy, const double* vxs,
                           const double* vys, const double* porosity, bool extras, bool forchheimer,
                           double* relative_speed, Store store) {
  double div_s = 0, n_at = 0;
  if (extras) {
    div_s = sum(q.dNdx[0] * ConstRow(vxs + q.node[0]) + q.dNdy[0] * ConstRow(vys + q.node[0]),
                q.dNdx[1] * ConstRow(vxs + q.node[1]) + q.dNdy[1] * ConstRow(vys + q.node[1]));
    n_at = dot(q, q.N, porosity);
    if (forchheimer) {
      const double wx = sum(q.N[0] * (ConstRow(vx + q.node[0]) - ConstRow(vxs + q.node[0])),
                            q.N[1] * (ConstRow(vx + q.node[1]) - ConstRow(vxs + q.node[1])));
      const double wy = sum(q.N[0] * (ConstRow(vy + q.node[0]) - ConstRow(vys + q.node[0])),
                            q.N[1] * (ConstRow(vy + q.node[1]) - ConstRow(vys + q.node[1])));
      *relative_speed = std::hypot(wx, wy);
    }
  }
  store(dot(q, q.dNdx, vx), dot(q, q.dNdy, vx), dot(q, q.dNdx, vy), dot(q, q.dNdy, vy), div_s,
        n_at);
}

// (On the polar grid the second row precedes the first in the last sector, where θ wraps.)
inline void add_span(NodeSpan& span, const QuadRows& q) { span.add_rows(q.node[0], q.node[1]); }

// The thread's share [b, e) of the nodes (node_share): a point whose four nodes all lie in it is
// added straight into acc_ (Solver::scatter_buffer), the others into the thread's buffer. On one
// thread the buffer is acc_ and every point is "owned".
struct OwnedNodes {
  int b, e;
  bool owns(const QuadRows& q) const {
    const int lo = std::min(q.node[0], q.node[1]), hi = std::max(q.node[0], q.node[1]) + 2;
    return lo >= b && hi <= e;
  }
};
inline OwnedNodes owned_nodes(int nn, int t, int T) {
  OwnedNodes o{};
  node_share(nn, t, T, o.b, o.e);
  return o;
}

}  // namespace

// fx = (x - x0)/h_x, i = min(floor(fx), nx - 1), ξ = fx - i (and so for y): the location of
// CartesianGrid::stencil, with (x - x0)(1/h_x) for the division (a packed division is the
// slowest operation of the loop; ξ changes by an ulp), without a branch so that the loop
// vectorises (the comparisons are made for every point, which -fno-trapping-math lets the
// compiler do in vectors).
void Solver::locate_cells(const CartesianGrid& grid, int phase, std::size_t b, std::size_t e) {
  const PointFields& pts = phase == 0 ? static_cast<const PointFields&>(solid_)
                                      : static_cast<const PointFields&>(liquid_);
  CellCache& c = cells_[phase];
  const double* __restrict x = pts.x.data();
  const double* __restrict y = pts.y.data();
  int* __restrict node = c.node.data();
  double* __restrict xi = c.xi.data();
  double* __restrict eta = c.eta.data();
  const double x0 = grid.x0(), y0 = grid.y0(), inv_hx = c.inv_hx, inv_hy = c.inv_hy;
  const int nx = grid.cells_x(), ny = grid.cells_y(), row = nx + 1;
  const double fx_max = nx, fy_max = ny;
  for (std::size_t p = b; p < e; ++p) {
    const double fx = (x[p] - x0) * inv_hx, fy = (y[p] - y0) * inv_hy;
    const bool inside = (fx >= 0.0) & (fy >= 0.0) & (fx <= fx_max) & (fy <= fy_max);
    const double gx = inside ? fx : 0.0, gy = inside ? fy : 0.0;  // no cast of a NaN or huge f
    const int i = std::min(static_cast<int>(gx), nx - 1);
    const int j = std::min(static_cast<int>(gy), ny - 1);
    xi[p] = gx - i;
    eta[p] = gy - j;
    node[p] = inside ? i + row * j : -1;
  }
}

void Solver::locate_cells(const PolarGrid& grid, int phase, std::size_t b, std::size_t e) {
  const PointFields& pts = phase == 0 ? static_cast<const PointFields&>(solid_)
                                      : static_cast<const PointFields&>(liquid_);
  StencilCache& c = cache_[phase];
  for (std::size_t p = b; p < e; ++p) {
    if (!grid.quad(pts.x[p], pts.y[p], c.sector[p], c.quad[p])) c.quad[p].node[0] = -1;
  }
}

template <class G>
void Solver::map_first_quad(const G& grid, int t) {
  // the located stencils of a phase as QuadRows
  auto view = [&](int phase) { return quad_rows(grid, cells_[phase], cache_[phase]); };
  const bool wet = liquid_.size() > 0;
  const int nn = nn_, T = threads_;
  const int fields = wet ? NF : solid_fields;
  const double s = options_.mass_scaling, gx = options_.gravity_x, gy = options_.gravity_y;
  double* const mine = scatter_buffer(t, fields);
  double* const direct = acc_.data();
  const OwnedNodes owned = owned_nodes(nn, t, T);
  NodeSpan span;
  long* lost = slots_[t].lost;
  std::size_t b, e;
  chunk(solid_.size(), t, T, b, e);
  locate_cells(grid, 0, b, e);
  {
    const SolidPoints& sp = solid_;
    const auto cells = view(0);
    QuadRows q;
    for (std::size_t p = b; p < e; ++p) {
      if (!cells.rows(p, q)) {
        if (lost[0] < 0) lost[0] = static_cast<long>(p);
        continue;
      }
      const bool own = owned.owns(q);
      if (!own) add_span(span, q);
      double* const acc = own ? direct : mine;
      const SolidLoad load = solid_load(sp, p, s, gx, gy);
      for (int r = 0; r < 2; ++r) {
        const int a = q.node[r];
        scatter_solid(load, q.N[r], q.dNdx[r], q.dNdy[r], acc, nn,
                      [a](double* f) { return Row(f + a); });
      }
    }
  }
  if (wet) {
    const LiquidPoints& lp = liquid_;
    chunk(lp.size(), t, T, b, e);
    locate_cells(grid, 1, b, e);
    const auto cells = view(1);
    QuadRows q;
    for (std::size_t p = b; p < e; ++p) {
      if (!cells.rows(p, q)) {
        if (lost[1] < 0) lost[1] = static_cast<long>(p);
        continue;
      }
      const bool own = owned.owns(q);
      if (!own) add_span(span, q);
      double* const acc = own ? direct : mine;
      const LiquidLoad load = liquid_load(lp, p, s, gx, gy);
      for (int r = 0; r < 2; ++r) {
        const int a = q.node[r];
        scatter_liquid(load, q.N[r], q.dNdx[r], q.dNdy[r], acc, nn,
                       [a](double* f) { return Row(f + a); });
      }
    }
  }
  mark_dirty(t, fields, span.begin, span.end, span.wrap_end);
}

// G2P with the FLIP/PIC blend (and the USL velocity gradient); with `remap` (MUSL) the updated
// momentum is mapped back to the nodes in the same pass, as update_points_part does.
template <class G>
void Solver::update_points_quad(const G& grid, int t, bool remap) {
  // the located stencils of a phase as QuadRows
  auto view = [&](int phase) { return quad_rows(grid, cells_[phase], cache_[phase]); };
  const double dt = dt_, flip = flip_fraction(), s = options_.mass_scaling;
  const bool usl = options_.scheme == UpdateScheme::usl;
  const bool wet = liquid_.size() > 0;
  const int nn = nn_, T = threads_;
  const int fields = wet ? 6 : 3;
  double* const mine = remap ? scatter_buffer(t, fields) : nullptr;
  double* const direct = acc_.data();
  const OwnedNodes owned = owned_nodes(nn, t, T);
  NodeSpan span;
  const double* vxs = nodes_.vx_solid.data();
  const double* vys = nodes_.vy_solid.data();
  auto g2p = [&](int phase, PointFields& pts, const double* vx, const double* vy, const double* ax,
                 const double* ay, bool extras, int field_m, int field_px, int field_py) {
    double* dx = displacement_x_[phase].data();
    double* dy = displacement_y_[phase].data();
    const auto cells = view(phase);
    std::size_t b, e;
    chunk(pts.size(), t, T, b, e);
    QuadRows q;
    for (std::size_t p = b; p < e; ++p) {
      if (!cells.rows(p, q)) continue;  // reported by the first map
      const double vpx = dot(q, q.N, vx), vpy = dot(q, q.N, vy);
      const double apx = dot(q, q.N, ax), apy = dot(q, q.N, ay);
      // FLIP/PIC blend: v <- flip (v + dt a) + (1 - flip) v_PIC; x <- x + dt v_PIC
      const double vx_new = flip * (pts.vx[p] + dt * apx) + (1.0 - flip) * vpx;
      const double vy_new = flip * (pts.vy[p] + dt * apy) + (1.0 - flip) * vpy;
      pts.vx[p] = vx_new;
      pts.vy[p] = vy_new;
      // Applied at the end of the step (move_points): every grid operation of the step uses
      // the shape functions of the start-of-step configuration.
      dx[p] = dt * vpx;
      dy[p] = dt * vpy;
      if (usl) {
        point_gradient(
            q, vx, vy, vxs, vys, porosity_.data(), extras, forchheimer_,
            forchheimer_ ? relative_speed_.data() + p : nullptr,
            [&](double Lxx, double Lxy, double Lyx, double Lyy, double div_s, double n_at) {
              store_gradient(pts, static_cast<long>(p), Lxx, Lxy, Lyx, Lyy, extras, div_s, n_at,
                             q.node[0]);
            });
      }
      if (remap) {  // MUSL: m_a = Σ N m, (m v)_a = Σ N m v_new
        const bool own = owned.owns(q);
        if (!own) add_span(span, q);
        double* const acc = own ? direct : mine;
        double* const m_ = acc + field_m * nn;
        double* const px_ = acc + field_px * nn;
        double* const py_ = acc + field_py * nn;
        const double mi = pts.mass[p] * s, mvx = mi * vx_new, mvy = mi * vy_new;
        for (int r = 0; r < 2; ++r) {
          const int a = q.node[r];
          Row(m_ + a) += q.N[r] * mi;
          Row(px_ + a) += q.N[r] * mvx;
          Row(py_ + a) += q.N[r] * mvy;
        }
      }
    }
  };
  g2p(0, solid_, vxs, vys, asx_.data(), asy_.data(), false, R_MS, R_PXS, R_PYS);
  if (wet) {
    g2p(1, liquid_, nodes_.vx_liquid.data(), nodes_.vy_liquid.data(), alx_.data(), aly_.data(),
        true, R_ML, R_PXL, R_PYL);
  }
  if (remap) mark_dirty(t, fields, span.begin, span.end, span.wrap_end);
}

// L = Σ_a v_a ⊗ ∇N_a at the points (and, for the liquid, tr(D_S), n and |u_L - u_S| there), as
// velocity_gradients_part does.
template <class G>
void Solver::velocity_gradients_quad(const G& grid, int t, bool liquid_extras) {
  // the located stencils of a phase as QuadRows
  auto view = [&](int phase) { return quad_rows(grid, cells_[phase], cache_[phase]); };
  const double* vxs = nodes_.vx_solid.data();
  const double* vys = nodes_.vy_solid.data();
  auto grad = [&](int phase, PointFields& pts, const double* vx, const double* vy, bool extras) {
    const auto cells = view(phase);
    std::size_t b, e;
    chunk(pts.size(), t, threads_, b, e);
    QuadRows q;
    for (std::size_t p = b; p < e; ++p) {
      if (!cells.rows(p, q)) continue;
      point_gradient(
          q, vx, vy, vxs, vys, porosity_.data(), extras, forchheimer_,
          forchheimer_ ? relative_speed_.data() + p : nullptr,
          [&](double Lxx, double Lxy, double Lyx, double Lyy, double div_s, double n_at) {
            store_gradient(pts, static_cast<long>(p), Lxx, Lxy, Lyx, Lyy, extras, div_s, n_at,
                           q.node[0]);
          });
    }
  };
  grad(0, solid_, vxs, vys, false);
  if (liquid_.size() > 0) {
    grad(1, liquid_, nodes_.vx_liquid.data(), nodes_.vy_liquid.data(), liquid_extras);
  }
}

template void Solver::map_first_quad<CartesianGrid>(const CartesianGrid&, int);
template void Solver::map_first_quad<PolarGrid>(const PolarGrid&, int);
template void Solver::update_points_quad<CartesianGrid>(const CartesianGrid&, int, bool);
template void Solver::update_points_quad<PolarGrid>(const PolarGrid&, int, bool);
template void Solver::velocity_gradients_quad<CartesianGrid>(const CartesianGrid&, int, bool);
template void Solver::velocity_gradients_quad<PolarGrid>(const PolarGrid&, int, bool);

}  // namespace granflow::mpm
