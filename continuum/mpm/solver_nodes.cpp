// The nodal part of the Solver's step (solver.hpp): the velocity conditions and nodal forces, the
// nodal porosity, the momentum balance of each phase with drag and the shared liquid-stress force
// (semi-implicit or explicit drag, Cundall local damping), and the MUSL nodal velocities.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <variant>

#include "continuum/mpm/solver_internal.hpp"

namespace granflow::mpm {

using namespace solver_internal;

double Solver::node_angle(int n) const {
  return std::visit([n](const auto& g) { return g.node_angle(n); }, grid_);
}

void Solver::fix_velocity(Phase phase, int node, Frame frame, int component, double value,
                          double ramp_time) {
  if (node < 0 || node >= nn_ || component < 0 || component > 1) {
    throw std::invalid_argument("fix_velocity: node or component out of range");
  }
  if (frame == Frame::polar && !std::holds_alternative<PolarGrid>(grid_)) {
    throw std::invalid_argument("(r, θ) velocity conditions need a polar grid");
  }
  auto& c = conditions_[static_cast<int>(phase)];
  if (c.mask[node] != 0 && c.frame[node] != static_cast<std::uint8_t>(frame)) {
    throw std::invalid_argument("fix_velocity: a node's conditions must share one frame");
  }
  if (c.mask[node] == 0) c.list.push_back(node);
  c.mask[node] |= static_cast<std::uint8_t>(1u << component);
  c.frame[node] = static_cast<std::uint8_t>(frame);
  (component == 0 ? c.value0 : c.value1)[node] = value;
  c.ramp[node] = ramp_time;
  if (frame == Frame::polar) {  // the node's angle is fixed: its cos and sin once, not per step
    const double th = node_angle(node);
    c.cos[node] = std::cos(th);
    c.sin[node] = std::sin(th);
  }
}

void Solver::add_nodal_force(Phase phase, int node, double fx, double fy) {
  if (node < 0 || node >= nn_) throw std::invalid_argument("add_nodal_force: node out of range");
  nodal_forces_.push_back({static_cast<int>(phase), node, fx, fy});
}

void Solver::solve_porosity_only() {
  const double s = options_.mass_scaling;
  for (int a = 0; a < nn_; ++a) {
    const double m = acc_[MS * nn_ + a] / s;
    porosity_[a] = m > mass_floor_ ? std::clamp(acc_[NMS * nn_ + a] / m, 0.0, 1.0) : 1.0;
  }
}

void Solver::solve_nodes(int begin, int end) {
  const bool wet = liquid_.size() > 0;
  const int nn = nn_;
  for (const auto& f : nodal_forces_) {
    if ((f.phase == 1 && !wet) || f.node < begin || f.node >= end) continue;
    acc_[(f.phase == 0 ? FXS : FXL) * nn + f.node] += f.fx;
    acc_[(f.phase == 0 ? FYS : FYL) * nn + f.node] += f.fy;
  }
  const double dt = dt_, s = options_.mass_scaling, alpha = options_.local_damping;
  const double floor = mass_floor_ * s;
  const bool implicit_drag = options_.drag_integration == DragIntegration::semi_implicit;
  double* A = acc_.data();
  NodeFields& out = nodes_;
  // One division per phase and node: the nodal velocities and accelerations are the sums times
  // 1/m (a division costs several multiplications; the results move by an ulp).
  const double inv_dt = 1.0 / dt;
  for (int a = begin; a < end; ++a) {
    const double ms = A[MS * nn + a];
    const double inv_ms = ms > floor ? 1.0 / ms : 0.0;
    const double n = ms > floor ? std::clamp(A[NMS * nn + a] * s * inv_ms, 0.0, 1.0) : 1.0;
    porosity_[a] = n;
    out.porosity[a] = n;
    out.mass_solid[a] = ms / s;
    double fxs = A[FXS * nn + a], fys = A[FYS * nn + a];
    const double vxs0 = A[PXS * nn + a] * inv_ms;
    const double vys0 = A[PYS * nn + a] * inv_ms;
    if (!wet) {
      if (alpha > 0) {  // Cundall local damping: f -= α |f| sign(v)
        fxs -= alpha * std::fabs(fxs) * sign(vxs0);
        fys -= alpha * std::fabs(fys) * sign(vys0);
      }
      if (ms > floor) {
        asx_[a] = fxs * inv_ms;
        asy_[a] = fys * inv_ms;
        out.vx_solid[a] = vxs0 + dt * asx_[a];
        out.vy_solid[a] = vys0 + dt * asy_[a];
      } else {
        out.vx_solid[a] = out.vy_solid[a] = asx_[a] = asy_[a] = 0.0;
      }
      continue;
    }
    const double ml = A[ML * nn + a];
    const double inv_ml = ml > floor ? 1.0 / ml : 0.0;
    out.mass_liquid[a] = ml / s;
    const double vxl0 = A[PXL * nn + a] * inv_ml;
    const double vyl0 = A[PYL * nn + a] * inv_ml;
    double fxl = A[FXL * nn + a], fyl = A[FYL * nn + a];
    // Liquid-stress force shared by volume fraction: n to the liquid, (1 - n) to the solid
    // (this carries the buoyancy/interaction term p ∇n; see docs/mpm.md).
    const double glx = A[GLX * nn + a], gly = A[GLY * nn + a];
    if (ms > floor) {
      fxl += n * glx;
      fyl += n * gly;
      fxs += (1.0 - n) * glx;
      fys += (1.0 - n) * gly;
    } else {
      fxl += glx;
      fyl += gly;
    }
    if (alpha > 0) {
      fxs -= alpha * std::fabs(fxs) * sign(vxs0);
      fys -= alpha * std::fabs(fys) * sign(vys0);
      fxl -= alpha * std::fabs(fxl) * sign(vxl0);
      fyl -= alpha * std::fabs(fyl) * sign(vyl0);
    }
    double vxs, vys, vxl, vyl;
    const double C = A[CD * nn + a];
    if (ms > floor && ml > floor && C > 0) {
      if (implicit_drag) {
        // Backward Euler in the drag only: with P = m v + dt f per phase, the relative velocity
        // w = v_L - v_S solves w (1 + dt C (1/m_L + 1/m_S)) = P_L/m_L - P_S/m_S, and the total
        // momentum P_L + P_S is kept exactly.
        const double Psx = ms * vxs0 + dt * fxs, Psy = ms * vys0 + dt * fys;
        const double Plx = ml * vxl0 + dt * fxl, Ply = ml * vyl0 + dt * fyl;
        const double k = 1.0 / (1.0 + dt * C * (inv_ml + inv_ms));
        const double wx = (Plx * inv_ml - Psx * inv_ms) * k, wy = (Ply * inv_ml - Psy * inv_ms) * k;
        const double inv_m = 1.0 / (ms + ml);
        vxs = (Psx + Plx - ml * wx) * inv_m;
        vys = (Psy + Ply - ml * wy) * inv_m;
        vxl = vxs + wx;
        vyl = vys + wy;
      } else {
        const double dx = C * (vxl0 - vxs0), dy = C * (vyl0 - vys0);
        vxs = vxs0 + dt * (fxs + dx) * inv_ms;
        vys = vys0 + dt * (fys + dy) * inv_ms;
        vxl = vxl0 + dt * (fxl - dx) * inv_ml;
        vyl = vyl0 + dt * (fyl - dy) * inv_ml;
      }
    } else {
      vxs = ms > floor ? vxs0 + dt * fxs * inv_ms : 0.0;
      vys = ms > floor ? vys0 + dt * fys * inv_ms : 0.0;
      vxl = ml > floor ? vxl0 + dt * fxl * inv_ml : 0.0;
      vyl = ml > floor ? vyl0 + dt * fyl * inv_ml : 0.0;
    }
    out.vx_solid[a] = vxs;
    out.vy_solid[a] = vys;
    out.vx_liquid[a] = vxl;
    out.vy_liquid[a] = vyl;
    asx_[a] = (vxs - vxs0) * inv_dt;
    asy_[a] = (vys - vys0) * inv_dt;
    alx_[a] = (vxl - vxl0) * inv_dt;
    aly_[a] = (vyl - vyl0) * inv_dt;
  }
  // Velocity conditions at t + dt; the acceleration follows the prescribed velocity.
  for (int phase = 0; phase < (wet ? 2 : 1); ++phase) {
    double* vx = phase == 0 ? out.vx_solid.data() : out.vx_liquid.data();
    double* vy = phase == 0 ? out.vy_solid.data() : out.vy_liquid.data();
    double* ax = phase == 0 ? asx_.data() : alx_.data();
    double* ay = phase == 0 ? asy_.data() : aly_.data();
    const int fm = phase == 0 ? MS : ML, fpx = phase == 0 ? PXS : PXL, fpy = phase == 0 ? PYS : PYL;
    apply_conditions(static_cast<Phase>(phase), vx, vy, begin, end);
    for (int a : conditions_[phase].list) {
      if (a < begin || a >= end) continue;
      const double m = A[fm * nn + a];
      const double v0x = m > floor ? A[fpx * nn + a] / m : 0.0;
      const double v0y = m > floor ? A[fpy * nn + a] / m : 0.0;
      ax[a] = (vx[a] - v0x) / dt;
      ay[a] = (vy[a] - v0y) / dt;
    }
  }
}

void Solver::apply_conditions(Phase phase, double* vx, double* vy, int begin, int end) const {
  const auto& c = conditions_[static_cast<int>(phase)];
  const double t = time_ + dt_;
  for (int a : c.list) {
    if (a < begin || a >= end) continue;
    const double f = c.ramp[a] > 0 ? std::min(1.0, t / c.ramp[a]) : 1.0;
    if (c.frame[a] == static_cast<std::uint8_t>(Frame::xy)) {
      if (c.mask[a] & 1u) vx[a] = f * c.value0[a];
      if (c.mask[a] & 2u) vy[a] = f * c.value1[a];
    } else {
      const double cs = c.cos[a], sn = c.sin[a];
      double vr = vx[a] * cs + vy[a] * sn, vt = -vx[a] * sn + vy[a] * cs;
      if (c.mask[a] & 1u) vr = f * c.value0[a];
      if (c.mask[a] & 2u) vt = f * c.value1[a];
      vx[a] = vr * cs - vt * sn;
      vy[a] = vr * sn + vt * cs;
    }
  }
}

void Solver::remap_nodes(int begin, int end) {
  const bool wet = liquid_.size() > 0;
  const int nn = nn_;
  const double floor = mass_floor_ * options_.mass_scaling;
  const double* A = acc_.data();
  NodeFields& out = nodes_;
  for (int a = begin; a < end; ++a) {
    const double ms = A[R_MS * nn + a];
    const double inv_ms = ms > floor ? 1.0 / ms : 0.0;
    out.vx_solid[a] = A[R_PXS * nn + a] * inv_ms;
    out.vy_solid[a] = A[R_PYS * nn + a] * inv_ms;
    if (wet) {
      const double ml = A[R_ML * nn + a];
      const double inv_ml = ml > floor ? 1.0 / ml : 0.0;
      out.vx_liquid[a] = A[R_PXL * nn + a] * inv_ml;
      out.vy_liquid[a] = A[R_PYL * nn + a] * inv_ml;
    }
  }
  apply_conditions(Phase::solid, out.vx_solid.data(), out.vy_solid.data(), begin, end);
  if (wet) {
    apply_conditions(Phase::liquid, out.vx_liquid.data(), out.vy_liquid.data(), begin, end);
  }
}

}  // namespace granflow::mpm
