// The point update after the grid part of the Solver's step (solver.hpp): the materials' stresses,
// volume and porosity of the solid points; the storage equation, volume, viscous stress and drag
// of the liquid points, with the optional cell-averaged rate, closed-domain mean removal, pressure
// relaxation and cell-constant pressure (docs/mpm.md); the finite checks.
#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <type_traits>
#include <variant>

#include "continuum/model/closures.hpp"
#include "continuum/model/exp_near_zero.hpp"
#include "continuum/mpm/solver_internal.hpp"

namespace granflow::mpm {

using namespace solver_internal;

double Solver::viscosity_at(double nu) const {
  if (liquid_options_.viscosity_law == ViscosityLaw::constant) return liquid_options_.viscosity;
  return model::mixture_viscosity(liquid_options_.closure, std::max(nu, 0.0));
}

namespace {
// Darcy: n (v_L - v_S) = -(k_D/γ_w) ∇p  =>  β = n² (γ_w / k_D); none without solid.
inline double darcy_drag(double n, double gamma_over_k) {
  return n >= 1.0 - 1e-12 ? 0.0 : n * n * gamma_over_k;
}
inline double darcy_gamma_over_k(const LiquidOptions& o) {
  return o.density * o.darcy_gravity / o.hydraulic_conductivity;
}
}  // namespace

double Solver::drag_at(double n, long p) const {
  if (liquid_options_.drag_law == DragLaw::darcy) {
    return darcy_drag(n, darcy_gamma_over_k(liquid_options_));
  }
  if (n >= 1.0 - 1e-12) return 0.0;  // no solid: nothing to drag against
  if (forchheimer_) {
    // Ergun (1952) with its inertial term: -∇p = (η0/κ) q + c_F |q| q, q = n (u_L - u_S), so
    // β = η0 n / κ + c_F n² |u_L - u_S| (model::drag_coefficient_with_inertia), with the
    // relative speed of the last velocity-gradient pass (lagged by one step).
    return model::drag_coefficient_with_inertia(
        liquid_options_.closure, liquid_options_.grain_diameter, 1.0 - n, relative_speed_[p]);
  }
  return model::drag_coefficient(liquid_options_.closure, liquid_options_.grain_diameter, 1.0 - n);
}

void Solver::refresh_liquid_state() {
  // Volume, viscous stress and drag of the liquid points from p, n and L (no time increment).
  const double inv_K = 1.0 / liquid_options_.bulk_modulus, inv_rho0 = 1.0 / liquid_options_.density;
  for (std::size_t p = 0; p < liquid_.size(); ++p) {
    const double n = liquid_.porosity[p];
    liquid_.volume[p] =
        liquid_point_volume(liquid_.mass[p], 1.0 / n, inv_rho0, liquid_.pressure[p], inv_K);
    liquid_.drag[p] = drag_at(n, static_cast<long>(p));
  }
}

// Relaxation of the pore pressure towards its nodal average (numerics.pressure_relaxation_time
// t_p), applied to the start-of-step p with the start-of-step stencils:
//   p_a = Σ_q N_a(x_q) V_q p_q / Σ_q N_a(x_q) V_q,   p̃_p = Σ_a N_a(x_p) p_a,
//   p_p ← p_p − (1 − exp(−Δt/t_p)) (p_p − p̃_p) − mean,
// the volume-weighted mean of the change removed (Σ V Δp = 0, the mean pore pressure is kept).
// A pressure alternating from cell to cell has p̃ = 0 and decays as exp(−t/t_p); it is a
// near-zero-energy mode of the cell-constant rate (its nodal forces nearly cancel), which
// nothing else restrains. A smooth p changes by O(h² ∇²p): a diffusivity ~ h²/t_p, negligible
// against the physical one of a saturated sand, (κ/η0)(K_w/n) (docs/mpm.md).
template <class G>
void Solver::relax_pressure(const G& grid) {
  const int nn = nn_;
  LiquidPoints& lp = liquid_;
  const long np = static_cast<long>(lp.size());
  scatter(2, [&](double* acc, int t, int T) {
    std::size_t b, e;
    chunk(lp.size(), t, T, b, e);
    Stencil st{};
    for (std::size_t p = b; p < e; ++p) {
      if (!locate<G, ShapeKind::linear>(grid, 1, p, st)) continue;
      const double V = lp.volume[p], Vp = V * lp.pressure[p];
      for (int k = 0; k < st.count; ++k) {
        acc[st.node[k]] += st.N[k] * Vp;
        acc[nn + st.node[k]] += st.N[k] * V;
      }
    }
  });
  const double alpha = 1.0 - std::exp(-dt_ / options_.pressure_relaxation_time);
  double* change = pressure_change_.data();
  const auto [sum, volume] = liquid_volume_sums([&](std::size_t p) -> std::optional<double> {
    Stencil st{};
    change[p] = 0.0;
    if (!locate<G, ShapeKind::linear>(grid, 1, p, st)) return std::nullopt;
    double avg = 0.0, w = 0.0;
    for (int k = 0; k < st.count; ++k) {
      const int a = st.node[k];
      if (acc_[nn + a] > 0.0) {
        avg += st.N[k] * acc_[a] / acc_[nn + a];
        w += st.N[k];
      }
    }
    if (w > 0.0) change[p] = -alpha * (lp.pressure[p] - avg / w);
    return change[p];
  });
  const double mean = volume > 0.0 ? sum / volume : 0.0;
#pragma omp parallel for schedule(static) num_threads(threads_) if (threads_ > 1)
  for (long p = 0; p < np; ++p) lp.pressure[p] += change[p] - mean;
}

namespace {

// Solid points [b, e): dV/V = tr(D) dt (plane strain); grains incompressible: n = 1 - V_s / V;
// with dx (non-null) also x += Δx of the step. Returns the last point holding a non-finite
// value or a non-positive volume, -1 if none. The arrays do not overlap (__restrict); the motion
// is a separate loop, which vectorises (GCC 12 vectorises the first loop, with its reduction of
// the check, only for AVX-512: -DGRANFLOW_NATIVE=ON here).
long solid_volume_pass(std::size_t b, std::size_t e, double dt, const double* __restrict Lxx,
                       const double* __restrict Lyy, const double* __restrict solid_volume,
                       double* __restrict volume, double* __restrict porosity,
                       const double* __restrict sxx, const double* __restrict syy,
                       const double* __restrict sxy, const double* __restrict vx,
                       const double* __restrict vy, double* __restrict x, double* __restrict y,
                       const double* __restrict dx, const double* __restrict dy) {
  long bad = -1;
  for (std::size_t p = b; p < e; ++p) {
    const double V = volume[p] * (1.0 + dt * (Lxx[p] + Lyy[p]));
    volume[p] = V;
    porosity[p] = 1.0 - solid_volume[p] / V;
    const double check = sxx[p] + syy[p] + sxy[p] + vx[p] + vy[p] + x[p] + y[p];
    if (!std::isfinite(check) || !(V > 0.0)) bad = static_cast<long>(p);
  }
  if (dx) {
    for (std::size_t p = b; p < e; ++p) {
      x[p] += dx[p];
      y[p] += dy[p];
    }
  }
  return bad;
}

}  // namespace

StressUpdateView Solver::stress_view() {
  return {solid_.Lxx.data(),
          solid_.Lxy.data(),
          solid_.Lyx.data(),
          solid_.Lyy.data(),
          solid_.porosity.data(),
          solid_.temperature.data(),
          solid_.sxx.data(),
          solid_.syy.data(),
          solid_.szz.data(),
          solid_.sxy.data(),
          threads_,
          options_.material_conductivity ? point_conductivity_.data() : nullptr,
          solid_.x.data(),
          solid_.y.data(),
          solid_.volume.data()};
}

bool Solver::materials_in_step_region() const {
  for (const auto& m : materials_)
    if (!m->updates_points_independently()) return false;
  return true;
}

// The pore pressure needs the volumetric rate of all liquid points first only when it is
// cell-averaged or its mean removed; otherwise each point uses its own, in the same pass.
bool Solver::liquid_rate_pass() const {
  return options_.liquid_volumetric_smoothing || options_.closed_domain ||
         options_.pressure_relaxation_time > 0.0;
}

// The liquid points' part of the update, on local pointers with Darcy's β inline (a call or a
// member access per point makes the compiler reload every array's address).
struct Solver::LiquidPass {
  double* rate;
  const double *n_, *m_, *Lxx, *Lyy, *div_solid, *dx, *dy;
  double *pressure, *volume, *drag, *x, *y;
  LiquidPoints& lq;
  const Solver& solver;
  double dt, K, inv_K, inv_rho0, gamma_over_k;
  bool viscous, darcy, move;
  LiquidPass(Solver& s, bool move_points)
      : rate(s.volumetric_rate_.data()),
        n_(s.liquid_.porosity.data()),
        m_(s.liquid_.mass.data()),
        Lxx(s.liquid_.Lxx.data()),
        Lyy(s.liquid_.Lyy.data()),
        div_solid(s.div_solid_.data()),
        dx(s.displacement_x_[1].data()),
        dy(s.displacement_y_[1].data()),
        pressure(s.liquid_.pressure.data()),
        volume(s.liquid_.volume.data()),
        drag(s.liquid_.drag.data()),
        x(s.liquid_.x.data()),
        y(s.liquid_.y.data()),
        lq(s.liquid_),
        solver(s),
        dt(s.dt_),
        K(s.liquid_options_.bulk_modulus),
        inv_K(1.0 / s.liquid_options_.bulk_modulus),
        inv_rho0(1.0 / s.liquid_options_.density),
        gamma_over_k(darcy_gamma_over_k(s.liquid_options_)),
        viscous(s.liquid_options_.viscosity > 0.0),
        darcy(s.liquid_options_.drag_law == DragLaw::darcy),
        move(move_points) {}
  // Volumetric rate of the mixture seen by the liquid: n tr(D_L) + (1 - n) tr(D_S).
  void rate_of(long p) const {
    const double n = n_[p];
    rate[p] = n * (Lxx[p] + Lyy[p]) + (1.0 - n) * div_solid[p];
  }
  // Returns true if the point holds a non-finite value.
  bool point(long p) const {
    const double n = n_[p], inv_n = 1.0 / n;
    const double tr_l = Lxx[p] + Lyy[p];
    // Storage equation of the double-point formulation (incompressible grains):
    //   dp = -(K_w / n) [ n tr(D_L) + (1 - n) tr(D_S) ] dt
    const double p_new = pressure[p] - dt * (K * inv_n) * rate[p];
    pressure[p] = p_new;
    // Mixture volume the point stands for: V = m / (n ρ_w), ρ_w = ρ_w0 exp(p / K_w).
    volume[p] = liquid_point_volume(m_[p], inv_n, inv_rho0, p_new, inv_K);
    if (viscous) {
      const double eta = solver.viscosity_at(1.0 - n);
      const double third = tr_l / 3.0;
      lq.txx[p] = 2.0 * eta * (Lxx[p] - third);
      lq.tyy[p] = 2.0 * eta * (Lyy[p] - third);
      lq.tzz[p] = -2.0 * eta * third;
      lq.txy[p] = eta * (lq.Lxy[p] + lq.Lyx[p]);
    }
    drag[p] = darcy ? darcy_drag(n, gamma_over_k) : solver.drag_at(n, p);
    const double check = p_new + lq.txy[p] + lq.vx[p] + lq.vy[p] + x[p] + y[p];
    if (move) {
      x[p] += dx[p];
      y[p] += dy[p];
    }
    return !std::isfinite(check);
  }
};

// Thread t's chunk of the point update: with `materials`, the materials' update_range over the
// chunk (materials_in_step_region; begin_ranges was called); the solid points' volume and
// porosity (and, with `move`, positions); the liquid points' storage equation, volume and drag
// (only their volumetric rate when the rate is cell-averaged or its mean removed). Failures go to
// slots_[t].bad. Each point reads and writes its own entries only, so the step's parallel region
// runs this right after the velocity gradients, on the same chunks, without a barrier.
void Solver::constitutive_points(int t, bool move, bool materials) {
  const int T = threads_;
  std::size_t b, e;
  chunk(solid_.size(), t, T, b, e);
  if (materials) {
    const StressUpdateView view = stress_view();
    for (auto& m : materials_) {
      const std::size_t mb = std::max(b, m->begin()), me = std::min(e, m->end());
      if (mb < me) m->update_range(view, dt_, mb, me, t);
    }
  }
  SolidPoints& sp = solid_;
  ThreadSlot& slot = slots_[t];
  slot.bad[0] =
      solid_volume_pass(b, e, dt_, sp.Lxx.data(), sp.Lyy.data(), sp.solid_volume.data(),
                        sp.volume.data(), sp.porosity.data(), sp.sxx.data(), sp.syy.data(),
                        sp.sxy.data(), sp.vx.data(), sp.vy.data(), sp.x.data(), sp.y.data(),
                        move ? displacement_x_[0].data() : nullptr, displacement_y_[0].data());
  slot.bad[1] = -1;
  if (liquid_.size() == 0) return;
  const LiquidPass liquid(*this, move);
  const bool rate_pass = liquid_rate_pass();
  chunk(liquid_.size(), t, T, b, e);
  for (long p = static_cast<long>(b); p < static_cast<long>(e); ++p) {
    liquid.rate_of(p);
    if (!rate_pass && liquid.point(p)) slot.bad[1] = p;
  }
}

// The cell-averaged rate (less its volume-weighted mean in a closed domain) and the cell-constant
// pressure of the liquid for thread t's chunk, inside the parallel region of the step (or of
// constitutive_update), when no pressure relaxation is asked for (liquid_smoothing_in_region):
// after constitutive_points has stored every point's own rate.
// The cell sums, keyed by the cell's first node, are added by the owner of that node straight
// into acc_ and by the other threads into their buffers, then reduced (as the grid maps); the
// barriers separate the sums from their reads. On one thread the operations are those of
// finish_constitutive's pass, in the same order.
void Solver::liquid_smoothing_part(int t, bool move) {
  const int nn = nn_, T = threads_;
  std::size_t b, e;
  chunk(liquid_.size(), t, T, b, e);
  int nb, ne;
  node_share(nn, t, T, nb, ne);
  const int* cell = liquid_cell_.data();
  double* rate = volumetric_rate_.data();
  LiquidPoints& lq = liquid_;
  // acc_[c] = Σ V value, acc_[nn + c] = Σ V over the liquid points of cell c
  auto cell_sums = [&](const double* value) {
    double* const mine = scatter_buffer(t, 2);
    double* const direct = acc_.data();
    int lo = nn, hi = 0;
    for (std::size_t p = b; p < e; ++p) {
      const int c = cell[p];
      const bool own = c >= nb && c < ne;
      if (!own) {
        lo = std::min(lo, c);
        hi = std::max(hi, c + 1);
      }
      double* const acc = own ? direct : mine;
      acc[c] += lq.volume[p] * value[p];
      acc[nn + c] += lq.volume[p];
    }
    mark_dirty(t, 2, lo, hi);
    if (T > 1) {
#pragma omp barrier
    }
    reduce_part(2, t);
    if (T > 1) {
#pragma omp barrier
    }
  };
  // Cell average of the volumetric rate (Anura3D's strain smoothing; Mast et al. 2012), then the
  // storage equation with it.
  cell_sums(rate);
  double mean_rate = 0.0;
  if (options_.closed_domain) {
    // Volume-weighted mean of the smoothed rate, removed (liquid_volume_sums: per thread over its
    // chunk, then the threads' sums in thread order, which every thread forms alike).
    double weighted = 0.0, volume = 0.0;
    for (std::size_t p = b; p < e; ++p) {
      rate[p] = acc_[cell[p]] / acc_[nn + cell[p]];
      weighted += lq.volume[p] * rate[p];
      volume += lq.volume[p];
    }
    slots_[t].sum[0] = weighted;
    slots_[t].sum[1] = volume;
    if (T > 1) {
#pragma omp barrier
    }
    weighted = volume = 0.0;
    for (const auto& slot : slots_) {
      weighted += slot.sum[0];
      volume += slot.sum[1];
    }
    mean_rate = weighted / volume;
  }
  const LiquidPass liquid(*this, move);
  long bad = -1;
  for (std::size_t p = b; p < e; ++p) {
    if (options_.closed_domain)
      rate[p] -= mean_rate;
    else
      rate[p] = acc_[cell[p]] / acc_[nn + cell[p]];
    if (liquid.point(static_cast<long>(p))) bad = static_cast<long>(p);
  }
  slots_[t].bad[1] = bad;
  if (T > 1) {  // every thread has read the rate sums before they are cleared
#pragma omp barrier
  }
  // The cell-constant pressure (cell_constant_pressure): each point takes its cell's
  // volume-weighted mean p, and its volume with it.
  cell_sums(lq.pressure.data());
  const double inv_K = 1.0 / liquid_options_.bulk_modulus;
  const double inv_rho0 = 1.0 / liquid_options_.density;
  for (std::size_t p = b; p < e; ++p) {
    lq.pressure[p] = acc_[cell[p]] / acc_[nn + cell[p]];
    lq.volume[p] =
        liquid_point_volume(lq.mass[p], 1.0 / lq.porosity[p], inv_rho0, lq.pressure[p], inv_K);
  }
}

bool Solver::liquid_smoothing_in_region() const {
  return liquid_.size() > 0 && options_.liquid_volumetric_smoothing &&
         !(options_.pressure_relaxation_time > 0.0);
}

void Solver::constitutive_update(bool move) {
  const StressUpdateView view = stress_view();
  try {
    for (auto& m : materials_) m->update_stress(view, dt_);
  } catch (const core::NumericalFailure& f) {
    if (f.step >= 0) throw;
    // A material does not know the step (step -1): it failed in the one being taken.
    throw core::NumericalFailure(step_ + 1, f.point, f.variable, f.value, f.why);
  }
  const bool smoothing = liquid_smoothing_in_region();
  auto part = [&](int t) {
    constitutive_points(t, move, false);
    if (smoothing) liquid_smoothing_part(t, move);
  };
  if (threads_ == 1) {
    part(0);
  } else {
#pragma omp parallel num_threads(threads_)
    part(omp_get_thread_num());
  }
  finish_constitutive(move, false);
}

// After constitutive_points (and liquid_smoothing_part) on every thread: the materials'
// finish_ranges (with `materials`), the liquid's rate passes that need the pressure relaxation,
// and the failure checks.
void Solver::finish_constitutive(bool move, bool materials) {
  if (materials) {
    const StressUpdateView view = stress_view();
    try {
      for (auto& m : materials_) m->finish_ranges(view);
    } catch (const core::NumericalFailure& f) {
      if (f.step >= 0) throw;
      throw core::NumericalFailure(step_ + 1, f.point, f.variable, f.value, f.why);
    }
  }
  long bad_solid = -1, bad_liquid = -1;
  for (const ThreadSlot& slot : slots_) {
    bad_solid = std::max(bad_solid, slot.bad[0]);
    bad_liquid = std::max(bad_liquid, slot.bad[1]);
  }
  const long nl = static_cast<long>(liquid_.size());
  double* rate = volumetric_rate_.data();
  if (nl > 0 && liquid_rate_pass() && !liquid_smoothing_in_region()) {
    const LiquidPass liquid(*this, move);
    const int nn = nn_;
    if (options_.liquid_volumetric_smoothing) {
      // Cell average of the volumetric rate (volume-weighted over the liquid points of each
      // cell, cells keyed by their first node): removes the checkerboard pressure modes of
      // equal-order velocity/pressure interpolation (Anura3D's strain smoothing; Mast et al.
      // 2012).
      scatter(2, [&](double* acc, int t, int T) {
        std::size_t b, e;
        chunk(static_cast<std::size_t>(nl), t, T, b, e);
        for (std::size_t p = b; p < e; ++p) {
          acc[liquid_cell_[p]] += liquid_.volume[p] * rate[p];
          acc[nn + liquid_cell_[p]] += liquid_.volume[p];
        }
      });
    }
    // The cell sums live in acc_ only until the next scatter: relax_pressure scatters its own
    // nodal sums into acc_, so every point takes its cell-averaged rate into its own slot of
    // `rate` (volumetric_rate_) before that.
    bool smoothed = !options_.liquid_volumetric_smoothing;
    auto smooth = [&](long p) { rate[p] = acc_[liquid_cell_[p]] / acc_[nn + liquid_cell_[p]]; };
    double mean_rate = 0.0;
    if (options_.closed_domain) {
      // Volume-weighted mean rate (smoothing the rate of each point on the way).
      const auto [rate_volume, volume] =
          liquid_volume_sums([&](std::size_t p) -> std::optional<double> {
            if (!smoothed) smooth(static_cast<long>(p));
            return rate[p];
          });
      smoothed = true;
      mean_rate = rate_volume / volume;
    }
    if (options_.pressure_relaxation_time > 0.0) {
      if (!smoothed) {
#pragma omp parallel for schedule(static) num_threads(threads_) if (threads_ > 1)
        for (long p = 0; p < nl; ++p) smooth(p);
        smoothed = true;
      }
      std::visit([&](const auto& g) { relax_pressure<std::decay_t<decltype(g)>>(g); }, grid_);
    }
#pragma omp parallel for schedule(static) num_threads(threads_) if (threads_ > 1) \
    reduction(max                                                                 \
              : bad_liquid)
    for (long p = 0; p < nl; ++p) {
      if (options_.closed_domain) {
        rate[p] -= mean_rate;
      } else if (!smoothed) {
        smooth(p);
      }
      if (liquid.point(p)) bad_liquid = std::max(bad_liquid, p);
    }
    if (options_.liquid_volumetric_smoothing && bad_liquid < 0) cell_constant_pressure();
  }
  if (bad_solid >= 0) {
    const long p = bad_solid;
    const bool bad_volume = !(solid_.volume[p] > 0);
    const bool bad_stress = !std::isfinite(solid_.sxx[p] + solid_.syy[p] + solid_.sxy[p]);
    const char* var = bad_volume ? "volume" : bad_stress ? "stress" : "velocity/position";
    const double val = bad_volume ? solid_.volume[p] : bad_stress ? solid_.sxx[p] : solid_.vx[p];
    throw core::NumericalFailure(step_ + 1, fmt::format("solid point {}", p), var, val,
                                 "non-finite or non-positive value");
  }
  if (bad_liquid >= 0) {
    throw core::NumericalFailure(step_ + 1, fmt::format("liquid point {}", bad_liquid), "pressure",
                                 liquid_.pressure[bad_liquid], "non-finite value");
  }
}

// The pressure work of the internal force, -Σ_p V_p p_p tr(D)_p, and the storage equation driven
// by the cell-averaged rate, dp_p = -(K_w/n) <tr D>_cell dt, are adjoint (the stored energy
// Σ V p²/2K_w changes by exactly the pressure work) only when p is uniform within each cell:
//   Σ_{p∈c} V_p p_p <tr D>_c = p_c Σ_{p∈c} V_p tr(D)_p   iff   p_p = p_c.
// A within-cell spread of p (round-off, points that crossed a cell face) is invisible to the
// smoothed rate but drives the nodes, so the discrete operator is no longer skew-adjoint; on the
// polar grid in Couette flow an azimuthal mode of wavenumber about 0.45 × cells_theta grew from
// round-off with an e-folding time of 0.17 s (10 × 64 cells) and reached 0.3 V at 7 s. Making the
// pressure constant per cell after each update (its volume-weighted mean; the cell-constant
// pressure of the Q1-P0 element, Hughes 2000 ch. 4, carried by the points as in the strain
// smoothing of Mast et al. 2012) restores the adjoint pair: the mode stays at round-off.
void Solver::cell_constant_pressure() {
  const long nl = static_cast<long>(liquid_.size());
  const int nn = nn_;
  scatter(2, [&](double* acc, int t, int T) {
    std::size_t b, e;
    chunk(static_cast<std::size_t>(nl), t, T, b, e);
    for (std::size_t p = b; p < e; ++p) {
      acc[liquid_cell_[p]] += liquid_.volume[p] * liquid_.pressure[p];
      acc[nn + liquid_cell_[p]] += liquid_.volume[p];
    }
  });
  const double inv_K = 1.0 / liquid_options_.bulk_modulus, inv_rho0 = 1.0 / liquid_options_.density;
#pragma omp parallel for schedule(static) num_threads(threads_) if (threads_ > 1)
  for (long p = 0; p < nl; ++p) {
    liquid_.pressure[p] = acc_[liquid_cell_[p]] / acc_[nn + liquid_cell_[p]];
    // V = m / (n ρ_w), ρ_w = ρ_w0 exp(p / K_w), with the cell's pressure.
    liquid_.volume[p] = liquid_point_volume(liquid_.mass[p], 1.0 / liquid_.porosity[p], inv_rho0,
                                            liquid_.pressure[p], inv_K);
  }
}

}  // namespace granflow::mpm
