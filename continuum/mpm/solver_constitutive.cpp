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

void Solver::constitutive_update(bool move) {
  const double dt = dt_;
  // Solid: one call per material over its range, then volume and porosity.
  StressUpdateView view{solid_.Lxx.data(),
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
  try {
    for (auto& m : materials_) m->update_stress(view, dt);
  } catch (const core::NumericalFailure& f) {
    if (f.step >= 0) throw;
    // A material does not know the step (step -1): it failed in the one being taken.
    throw core::NumericalFailure(step_ + 1, f.point, f.variable, f.value, f.why);
  }
  const long ns = static_cast<long>(solid_.size());
  const long nl = static_cast<long>(liquid_.size());
  const double K = liquid_options_.bulk_modulus;
  const double inv_K = 1.0 / K, inv_rho0 = 1.0 / liquid_options_.density;
  const bool viscous = liquid_options_.viscosity > 0.0;
  double* rate = volumetric_rate_.data();
  // The pore pressure needs the volumetric rate of all liquid points first only when it is
  // cell-averaged or its mean removed; otherwise each point uses its own, in the same pass.
  const bool rate_pass = options_.liquid_volumetric_smoothing || options_.closed_domain ||
                         options_.pressure_relaxation_time > 0.0;
  // Volumetric rate of the mixture seen by the liquid: n tr(D_L) + (1 - n) tr(D_S).
  auto liquid_rate = [&](long p) {
    const double n = liquid_.porosity[p];
    rate[p] = n * (liquid_.Lxx[p] + liquid_.Lyy[p]) + (1.0 - n) * div_solid_[p];
  };
  // The arrays as local pointers, and Darcy's β inline: the pass then keeps them in registers
  // (a call or a member access per point makes the compiler reload every array's address).
  LiquidPoints& lq = liquid_;
  const double* const l_n = lq.porosity.data();
  const double* const l_m = lq.mass.data();
  const double* const l_Lxx = lq.Lxx.data();
  const double* const l_Lyy = lq.Lyy.data();
  double* const l_p = lq.pressure.data();
  double* const l_V = lq.volume.data();
  double* const l_drag = lq.drag.data();
  double* const l_x = lq.x.data();
  double* const l_y = lq.y.data();
  const double* const l_dx = displacement_x_[1].data();
  const double* const l_dy = displacement_y_[1].data();
  const bool darcy = liquid_options_.drag_law == DragLaw::darcy;
  const double gamma_over_k = darcy_gamma_over_k(liquid_options_);
  auto liquid_point = [&](long p) {
    const double n = l_n[p], inv_n = 1.0 / n;
    const double tr_l = l_Lxx[p] + l_Lyy[p];
    // Storage equation of the double-point formulation (incompressible grains):
    //   dp = -(K_w / n) [ n tr(D_L) + (1 - n) tr(D_S) ] dt
    const double pressure = l_p[p] - dt * (K * inv_n) * rate[p];
    l_p[p] = pressure;
    // Mixture volume the point stands for: V = m / (n ρ_w), ρ_w = ρ_w0 exp(p / K_w).
    l_V[p] = liquid_point_volume(l_m[p], inv_n, inv_rho0, pressure, inv_K);
    if (viscous) {
      const double eta = viscosity_at(1.0 - n);
      const double third = tr_l / 3.0;
      lq.txx[p] = 2.0 * eta * (l_Lxx[p] - third);
      lq.tyy[p] = 2.0 * eta * (l_Lyy[p] - third);
      lq.tzz[p] = -2.0 * eta * third;
      lq.txy[p] = eta * (lq.Lxy[p] + lq.Lyx[p]);
    }
    l_drag[p] = darcy ? darcy_drag(n, gamma_over_k) : drag_at(n, p);
    const double check = pressure + lq.txy[p] + lq.vx[p] + lq.vy[p] + l_x[p] + l_y[p];
    if (move) {
      l_x[p] += l_dx[p];
      l_y[p] += l_dy[p];
    }
    return !std::isfinite(check);
  };
  long bad_solid = -1, bad_liquid = -1;
  // One parallel region for both phases (no barrier between the loops: they share nothing).
#pragma omp parallel num_threads(threads_) if (threads_ > 1) reduction(max : bad_solid, bad_liquid)
  {
    std::size_t b, e;
    chunk(static_cast<std::size_t>(ns), omp_get_thread_num(), omp_get_num_threads(), b, e);
    const SolidPoints& sp = solid_;
    bad_solid = std::max(
        bad_solid, solid_volume_pass(
                       b, e, dt, sp.Lxx.data(), sp.Lyy.data(), sp.solid_volume.data(),
                       solid_.volume.data(), solid_.porosity.data(), sp.sxx.data(), sp.syy.data(),
                       sp.sxy.data(), sp.vx.data(), sp.vy.data(), solid_.x.data(), solid_.y.data(),
                       move ? displacement_x_[0].data() : nullptr, displacement_y_[0].data()));
#pragma omp for schedule(static) nowait
    for (long p = 0; p < nl; ++p) {
      liquid_rate(p);
      if (!rate_pass && liquid_point(p)) bad_liquid = std::max(bad_liquid, p);
    }
  }
  if (nl > 0 && rate_pass) {
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
      if (liquid_point(p)) bad_liquid = std::max(bad_liquid, p);
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
