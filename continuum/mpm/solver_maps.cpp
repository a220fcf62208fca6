// The step of the Solver (solver.hpp) and its particle-grid maps: P2G of mass, momentum, forces,
// porosity and drag; G2P with the FLIP/PIC blend and the MUSL momentum remap; the velocity
// gradients; the lost-point checks; the point motion at the end of the step (docs/mpm.md). A
// Cartesian grid with linear shapes runs the same maps in solver_quad.cpp (fixed 2 x 2 stencils).
#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "continuum/mpm/solver_internal.hpp"

namespace granflow::mpm {

using namespace solver_internal;

void Solver::step() {
  if (!initialized_) throw std::logic_error("Solver::initialize() must be called before step()");
  std::visit(
      [&](const auto& g) {
        using G = std::decay_t<decltype(g)>;
        if constexpr (std::is_same_v<G, CartesianGrid>) {
          if (options_.shape == ShapeKind::gimp) {
            step_impl<G, ShapeKind::gimp>(g);
            return;
          }
        }
        step_impl<G, ShapeKind::linear>(g);
      },
      grid_);
}

template <class G, ShapeKind S>
void Solver::step_impl(const G& grid) {
  const bool wet = liquid_.size() > 0;
  const bool musl = options_.scheme == UpdateScheme::musl;
  const int T = threads_;
  for (auto& slot : slots_) slot.lost[0] = slot.lost[1] = -1;
  const bool conduct = (options_.temperature_conductivity > 0 || options_.material_conductivity) &&
                       solid_.size() > 0;
  // Without conduction (which still needs the start-of-step positions) the points move in the
  // constitutive pass. Materials whose points update independently are updated in this region,
  // each thread on the chunk whose velocity gradients it has just computed (no fork/join).
  const bool move = !conduct;
  const bool in_region = materials_in_step_region();
  const bool smoothing_in_region = in_region && liquid_smoothing_in_region();
  if (in_region)
    for (auto& m : materials_) m->begin_ranges(T);
  // The grid part of the step as ONE parallel region: every piece is split among the threads
  // (points in fixed contiguous chunks, nodes in fixed contiguous shares) and the pieces are
  // separated by barriers, instead of a fork/join per loop (each costs a futex wake-up of the
  // sleeping thread with OMP_WAIT_POLICY=passive). Lost points are found in the first map; every
  // thread reads the same flags after the first barrier and the region stops there.
  auto grid_part = [&](int t) {
    int b, e;
    node_share(nn_, t, T, b, e);
    map_first_part<G, S>(grid, t);
    if (T > 1) {
#pragma omp barrier
    }
    for (const auto& slot : slots_) {
      if (slot.lost[0] >= 0 || slot.lost[1] >= 0) return;
    }
    // No thread locates a point between this barrier and the next one, so the flag can be set
    // here by one thread without a race.
    if (t == 0) cache_[0].valid = cache_[1].valid = true;
    reduce_part(wet ? NF : solid_fields, t);
    solve_nodes(b, e);
    if (T > 1) {
#pragma omp barrier
    }
    update_points_part<G, S>(grid, t, musl);
    if (musl) {
      if (T > 1) {
#pragma omp barrier
      }
      reduce_part(wet ? 6 : 3, t);
      remap_nodes(b, e);
      if (T > 1) {
#pragma omp barrier
      }
      velocity_gradients_part<G, S>(grid, t, wet);
    }
    if (in_region) constitutive_points(t, move, true);
    if (smoothing_in_region) liquid_smoothing_part(t, move);
    if (in_region && conduct) {
      if (T > 1 && smoothing_in_region) {  // its reads of acc_ are done before conduction clears it
#pragma omp barrier
      }
      slots_[t].cold = conduct_part<G, S>(grid, t);
      move_points_part(t);
    }
  };
  if (T == 1) {
    grid_part(0);
  } else {
#pragma omp parallel num_threads(T)
    grid_part(omp_get_thread_num());
  }
  throw_if_lost();
  cache_[0].valid = cache_[1].valid = true;
  if (in_region) {
    finish_constitutive(move, true);
    if (conduct) {
      long cold = -1;
      for (const auto& slot : slots_) cold = std::max(cold, slot.cold);
      throw_if_negative_temperature(cold);
    }
  } else {
    constitutive_update(move);
    if (conduct) {
      conduct_temperature<G, S>(grid);
      move_points();
    }
  }
  cache_[0].valid = cache_[1].valid = false;  // the points moved: locate again next step
  time_ += dt_;
  ++step_;
  if (options_.dt_update_interval > 0 && step_ % options_.dt_update_interval == 0) update_dt();
}

template <class G, ShapeKind S>
void Solver::map_first_part(const G& grid, int t) {
  if constexpr (fixed_quad<G, S>) {
    map_first_quad(grid, t);  // solver_quad.cpp
    return;
  }
  const bool wet = liquid_.size() > 0;
  const int nn = nn_, T = threads_;
  const int fields = wet ? NF : solid_fields;
  const double s = options_.mass_scaling, gx = options_.gravity_x, gy = options_.gravity_y;
  double* acc = scatter_buffer(t, fields);
  NodeSpan span;
  long* lost = slots_[t].lost;
  std::size_t b, e;
  chunk(solid_.size(), t, T, b, e);
  const SolidPoints& sp = solid_;
  Stencil st{};
  for (std::size_t p = b; p < e; ++p) {
    if (!locate<G, S>(grid, 0, p, st)) {
      if (lost[0] < 0) lost[0] = static_cast<long>(p);
      continue;
    }
    if (T > 1) span.add<G>(st);
    const SolidLoad load = solid_load(sp, p, s, gx, gy);
    for (int k = 0; k < st.count; ++k) {
      const int a = st.node[k];
      scatter_solid(load, st.N[k], st.dNdx[k], st.dNdy[k], acc, nn,
                    [a](double* f) -> double& { return f[a]; });
    }
  }
  if (wet) {
    const LiquidPoints& lp = liquid_;
    chunk(lp.size(), t, T, b, e);
    for (std::size_t p = b; p < e; ++p) {
      if (!locate<G, S>(grid, 1, p, st)) {
        if (lost[1] < 0) lost[1] = static_cast<long>(p);
        continue;
      }
      if (T > 1) span.add<G>(st);
      const LiquidLoad load = liquid_load(lp, p, s, gx, gy);
      for (int k = 0; k < st.count; ++k) {
        const int a = st.node[k];
        scatter_liquid(load, st.N[k], st.dNdx[k], st.dNdy[k], acc, nn,
                       [a](double* f) -> double& { return f[a]; });
      }
    }
  }
  mark_dirty(t, fields, span.begin, span.end);
}

template <class G, ShapeKind S>
void Solver::map_first(const G& grid) {
  const int fields = liquid_.size() > 0 ? NF : solid_fields;
  for (auto& slot : slots_) slot.lost[0] = slot.lost[1] = -1;
  if (threads_ == 1) {
    map_first_part<G, S>(grid, 0);
  } else {
#pragma omp parallel num_threads(threads_)
    {
      const int t = omp_get_thread_num();
      map_first_part<G, S>(grid, t);
#pragma omp barrier
      reduce_part(fields, t);
    }
  }
  throw_if_lost();
  cache_[0].valid = cache_[1].valid = true;  // stencils at the current positions
}

void Solver::throw_if_lost() const {
  // The lowest index over the threads (each slot holds the first of its chunk), solid first.
  for (int phase = 0; phase < 2; ++phase) {
    long first = -1;
    for (const auto& slot : slots_) {
      if (slot.lost[phase] >= 0 && (first < 0 || slot.lost[phase] < first))
        first = slot.lost[phase];
    }
    if (first >= 0) lost_point(static_cast<Phase>(phase), first);
  }
}

void Solver::lost_point(Phase phase, long index) const {
  const PointFields& p = phase == Phase::solid ? static_cast<const PointFields&>(solid_)
                                               : static_cast<const PointFields&>(liquid_);
  const double x = p.x[index], y = p.y[index];
  const bool finite = std::isfinite(x) && std::isfinite(y);
  throw core::NumericalFailure(step_ + 1,
                               fmt::format("{} point {} at ({}, {})",
                                           phase == Phase::solid ? "solid" : "liquid", index, x, y),
                               "position", finite ? x : (std::isfinite(x) ? y : x),
                               finite
                                   ? "left the background grid (lost point)"
                                   : "non-finite position (a NaN/Inf upstream: stress, pressure or "
                                     "velocity)");
}

// G2P; with `remap` (MUSL) the updated momentum m v of each point is mapped back to the nodes in
// the same pass (it needs nothing but the point's own new velocity).
template <class G, ShapeKind S>
void Solver::update_points_part(const G& grid, int t, bool remap) {
  if constexpr (fixed_quad<G, S>) {
    update_points_quad(grid, t, remap);  // solver_quad.cpp
    return;
  }
  const double dt = dt_, flip = flip_fraction(), s = options_.mass_scaling;
  const bool usl = options_.scheme == UpdateScheme::usl;
  const bool wet = liquid_.size() > 0;
  const int nn = nn_, T = threads_;
  const int fields = wet ? 6 : 3;
  double* acc = remap ? scatter_buffer(t, fields) : nullptr;
  NodeSpan span;
  auto g2p = [&](PointFields& pts, const double* vx, const double* vy, const double* ax,
                 const double* ay, bool extras, double* m_, double* px_, double* py_) {
    const int phase = &pts == static_cast<PointFields*>(&liquid_) ? 1 : 0;
    double* dx = displacement_x_[phase].data();
    double* dy = displacement_y_[phase].data();
    std::size_t b, e;
    chunk(pts.size(), t, T, b, e);
    Stencil st{};
    for (std::size_t p = b; p < e; ++p) {
      if (!locate<G, S>(grid, phase, p, st)) continue;  // reported by the first map
      double vpx = 0, vpy = 0, apx = 0, apy = 0, Lxx = 0, Lxy = 0, Lyx = 0, Lyy = 0;
      double div_s = 0, n_at = 0, wx = 0, wy = 0;
      for (int k = 0; k < st.count; ++k) {
        const int a = st.node[k];
        const double N = st.N[k];
        vpx += N * vx[a];
        vpy += N * vy[a];
        apx += N * ax[a];
        apy += N * ay[a];
        if (usl) {
          Lxx += st.dNdx[k] * vx[a];
          Lxy += st.dNdy[k] * vx[a];
          Lyx += st.dNdx[k] * vy[a];
          Lyy += st.dNdy[k] * vy[a];
          if (extras) {
            div_s += st.dNdx[k] * nodes_.vx_solid[a] + st.dNdy[k] * nodes_.vy_solid[a];
            n_at += N * porosity_[a];
            if (forchheimer_) {
              wx += N * (vx[a] - nodes_.vx_solid[a]);
              wy += N * (vy[a] - nodes_.vy_solid[a]);
            }
          }
        }
      }
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
        store_gradient(pts, p, Lxx, Lxy, Lyx, Lyy, extras, div_s, n_at, st.node[0]);
        if (extras && forchheimer_) relative_speed_[p] = std::hypot(wx, wy);
      }
      if (remap) {  // MUSL: m_a = Σ N m, (m v)_a = Σ N m v_new
        if (T > 1) span.add<G>(st);
        const double mi = pts.mass[p] * s, mvx = mi * vx_new, mvy = mi * vy_new;
        for (int k = 0; k < st.count; ++k) {
          const int a = st.node[k];
          m_[a] += st.N[k] * mi;
          px_[a] += st.N[k] * mvx;
          py_[a] += st.N[k] * mvy;
        }
      }
    }
  };
  double* none = nullptr;
  g2p(solid_, nodes_.vx_solid.data(), nodes_.vy_solid.data(), asx_.data(), asy_.data(), false,
      remap ? acc + R_MS * nn : none, remap ? acc + R_PXS * nn : none,
      remap ? acc + R_PYS * nn : none);
  if (wet) {
    g2p(liquid_, nodes_.vx_liquid.data(), nodes_.vy_liquid.data(), alx_.data(), aly_.data(), true,
        remap ? acc + R_ML * nn : none, remap ? acc + R_PXL * nn : none,
        remap ? acc + R_PYL * nn : none);
  }
  if (remap) mark_dirty(t, fields, span.begin, span.end);
}

template <class G, ShapeKind S>
void Solver::velocity_gradients_part(const G& grid, int t, bool liquid_extras) {
  if constexpr (fixed_quad<G, S>) {
    velocity_gradients_quad(grid, t, liquid_extras);  // solver_quad.cpp
    return;
  }
  auto grad = [&](PointFields& pts, const double* vx, const double* vy, bool extras) {
    const int phase = &pts == static_cast<PointFields*>(&liquid_) ? 1 : 0;
    std::size_t b, e;
    chunk(pts.size(), t, threads_, b, e);
    Stencil st{};
    for (std::size_t p = b; p < e; ++p) {
      if (!locate<G, S>(grid, phase, p, st)) continue;
      double Lxx = 0, Lxy = 0, Lyx = 0, Lyy = 0, div_s = 0, n_at = 0, wx = 0, wy = 0;
      for (int k = 0; k < st.count; ++k) {
        const int a = st.node[k];
        Lxx += st.dNdx[k] * vx[a];
        Lxy += st.dNdy[k] * vx[a];
        Lyx += st.dNdx[k] * vy[a];
        Lyy += st.dNdy[k] * vy[a];
        if (extras) {
          div_s += st.dNdx[k] * nodes_.vx_solid[a] + st.dNdy[k] * nodes_.vy_solid[a];
          n_at += st.N[k] * porosity_[a];
          if (forchheimer_) {
            wx += st.N[k] * (vx[a] - nodes_.vx_solid[a]);
            wy += st.N[k] * (vy[a] - nodes_.vy_solid[a]);
          }
        }
      }
      store_gradient(pts, static_cast<long>(p), Lxx, Lxy, Lyx, Lyy, extras, div_s, n_at,
                     st.node[0]);
      if (extras && forchheimer_) relative_speed_[p] = std::hypot(wx, wy);
    }
  };
  grad(solid_, nodes_.vx_solid.data(), nodes_.vy_solid.data(), false);
  if (liquid_.size() > 0) {
    grad(liquid_, nodes_.vx_liquid.data(), nodes_.vy_liquid.data(), liquid_extras);
  }
}

template <class G, ShapeKind S>
void Solver::velocity_gradients(const G& grid, bool liquid_extras) {
  if (threads_ == 1) {
    velocity_gradients_part<G, S>(grid, 0, liquid_extras);
  } else {
#pragma omp parallel num_threads(threads_)
    velocity_gradients_part<G, S>(grid, omp_get_thread_num(), liquid_extras);
  }
  cache_[0].valid = cache_[1].valid = true;
}

void Solver::move_points_part(int t) {
  for (int phase = 0; phase < 2; ++phase) {
    PointFields& pts =
        phase == 0 ? static_cast<PointFields&>(solid_) : static_cast<PointFields&>(liquid_);
    std::size_t b, e;
    chunk(pts.size(), t, threads_, b, e);
    const double* dx = displacement_x_[phase].data();
    const double* dy = displacement_y_[phase].data();
    for (std::size_t p = b; p < e; ++p) {
      pts.x[p] += dx[p];
      pts.y[p] += dy[p];
    }
  }
}

void Solver::move_points() {
#pragma omp parallel num_threads(threads_) if (threads_ > 1)
  for (int phase = 0; phase < 2; ++phase) {
    PointFields& pts =
        phase == 0 ? static_cast<PointFields&>(solid_) : static_cast<PointFields&>(liquid_);
    const long n = static_cast<long>(pts.size());
    const double* dx = displacement_x_[phase].data();
    const double* dy = displacement_y_[phase].data();
#pragma omp for schedule(static) nowait
    for (long p = 0; p < n; ++p) {
      pts.x[p] += dx[p];
      pts.y[p] += dy[p];
    }
  }
}

// The whole-grid maps of initialize() (solver.cpp), for the grids and shapes step() runs.
template void Solver::map_first<CartesianGrid, ShapeKind::linear>(const CartesianGrid&);
template void Solver::map_first<CartesianGrid, ShapeKind::gimp>(const CartesianGrid&);
template void Solver::map_first<PolarGrid, ShapeKind::linear>(const PolarGrid&);
template void Solver::velocity_gradients<CartesianGrid, ShapeKind::linear>(const CartesianGrid&,
                                                                           bool);
template void Solver::velocity_gradients<CartesianGrid, ShapeKind::gimp>(const CartesianGrid&,
                                                                         bool);
template void Solver::velocity_gradients<PolarGrid, ShapeKind::linear>(const PolarGrid&, bool);

}  // namespace granflow::mpm
