// The time step of the Solver (solver.hpp): the critical steps of the wave speed, viscous
// diffusion, explicit drag and explicit conduction, Δt = CFL factor × their minimum (or a fixed
// Δt), and the FLIP fraction per step.
#include <algorithm>
#include <cmath>

#include "continuum/mpm/solver_internal.hpp"

namespace granflow::mpm {

using namespace solver_internal;

double TimeStepLimits::critical() const { return std::min({wave, viscous, drag, conduction}); }

TimeStepLimits Solver::compute_limits() const {
  TimeStepLimits lim{inf, inf, inf, inf};
  const double h = std::visit([](const auto& g) { return g.min_spacing(); }, grid_);
  const double s = options_.mass_scaling;
  const bool wet = liquid_.size() > 0;
  const double rho_w = liquid_options_.density, K = liquid_options_.bulk_modulus;
  double max_speed = 0;
  double rho_s_min = inf;
  for (const auto& m : materials_) {
    const double M = m->p_wave_modulus(), rho_s = m->grain_density();
    rho_s_min = std::min(rho_s_min, rho_s);
    for (std::size_t p = m->begin(); p < m->end(); ++p) {
      const double n = solid_.porosity[p];
      double c2 = M / ((1.0 - n) * rho_s);  // drained (dry) P wave
      if (wet) {  // undrained P wave of the mixture (Biot's fast wave, no relative motion)
        c2 = std::max(c2, (M + K / n) / ((1.0 - n) * rho_s + n * rho_w));
      }
      const double v = std::hypot(solid_.vx[p], solid_.vy[p]);
      max_speed = std::max(max_speed, std::sqrt(c2 / s) + v);
    }
  }
  double max_eta = 0, max_beta = 0, n_of_max_beta = 1;
  for (std::size_t p = 0; p < liquid_.size(); ++p) {
    const double v = std::hypot(liquid_.vx[p], liquid_.vy[p]);
    max_speed = std::max(max_speed, std::sqrt(K / (rho_w * s)) + v);  // sound in the liquid
    max_eta = std::max(max_eta, viscosity_at(1.0 - liquid_.porosity[p]));
    if (liquid_.drag[p] > max_beta) {
      max_beta = liquid_.drag[p];
      n_of_max_beta = liquid_.porosity[p];
    }
  }
  if (max_speed > 0) lim.wave = h / max_speed;
  // Explicit viscous diffusion in 2D: η dt / (ρ h²) <= 1/4.
  if (max_eta > 0) lim.viscous = 0.25 * h * h * rho_w * s / max_eta;
  // Explicit drag: two masses coupled by β, dt < 2 / (β (1/(n ρ_w) + 1/((1-n) ρ_s))).
  if (max_beta > 0 && options_.drag_integration == DragIntegration::explicit_euler &&
      n_of_max_beta < 1.0) {
    lim.drag =
        2.0 * s /
        (max_beta * (1.0 / (n_of_max_beta * rho_w) + 1.0 / ((1.0 - n_of_max_beta) * rho_s_min)));
  }
  // Explicit conduction in 2D: κ_T Δt / (C h²) <= 1/4 with C = (3/2) ρ_s (1 - n).
  double kappa_max = options_.temperature_conductivity;
  if (options_.material_conductivity)
    for (double k : point_conductivity_) kappa_max = std::max(kappa_max, k);
  if (kappa_max > 0) {
    double C = inf;
    for (std::size_t p = 0; p < solid_.size(); ++p) {
      C = std::min(C, 1.5 * solid_.mass[p] / solid_.volume[p]);
    }
    if (std::isfinite(C)) lim.conduction = 0.25 * h * h * C / kappa_max;
  }
  return lim;
}

void Solver::update_dt() {
  limits_ = compute_limits();
  const double critical = limits_.critical();
  if (options_.fixed_dt > 0) {
    dt_ = options_.fixed_dt;
  } else {
    if (!std::isfinite(critical)) {
      throw core::NumericalFailure(step_, "all points", "dt", critical,
                                   "no wave speed to set the time step (give a fixed dt)");
    }
    dt_ = options_.cfl_factor * critical;
  }
}

// The PIC part of the blend relaxes the point velocity towards the grid field: per step
// v ← f v + (1 − f) v_PIC, i.e. over a time t the point–grid difference of a mode the grid does
// not see decays as f^(t/Δt). With f fixed that is exp(t ln f / Δt): a rate ∝ 1/Δt, so a stiffer
// liquid (smaller Δt, K_w) means more numerical viscosity. With f = exp(−Δt/t_PIC) it decays as
// exp(−t/t_PIC) for any Δt (the exact integral of dv/dt = −(v − v_PIC)/t_PIC over one step).
double Solver::flip_fraction() const {
  return options_.pic_relaxation_time > 0.0 ? std::exp(-dt_ / options_.pic_relaxation_time)
                                            : options_.flip;
}

}  // namespace granflow::mpm
