#include "continuum/rev/element_test.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/interrupt.hpp"
#include "core/run.hpp"

namespace granflow::rev {

namespace {

using continuum::MultiRegimePoint;
using continuum::PointState;
using continuum::StressParts;

// Largest solid fraction the enabled closures admit (g0 diverges at ν_c, η(ν) at ν_m), with a
// relative margin so that a trial step never evaluates a closure at its singularity.
double deviator_q(const Eigen::Matrix3d& stress) { return stress(0, 0) - stress(1, 1); }

struct Trial {
  PointState state;
  StressParts parts;
  double pore_pressure = 0;
  double residual = 0;  // σ_r - σ_cell, Pa
};

void record(ElementSeries& s, double time, double eps_d, double eps_v, double eps_a,
            const PointState& state, const StressParts& parts, double pore_pressure,
            double yield_value, int stage) {
  const Eigen::Matrix3d total =
      parts.total_without_pore_pressure() + pore_pressure * Eigen::Matrix3d::Identity();
  s.time.push_back(time);
  s.deviatoric_strain.push_back(eps_d);
  s.volumetric_strain.push_back(eps_v);
  s.axial_strain.push_back(eps_a);
  s.q.push_back(deviator_q(total));
  s.q_force_chain.push_back(deviator_q(parts.force_chain));
  s.q_collisional.push_back(deviator_q(parts.collisional));
  s.q_liquid.push_back(deviator_q(parts.liquid));
  s.mean_stress.push_back(total.trace() / 3.0);
  s.effective_pressure.push_back(parts.force_chain.trace() / 3.0);
  s.collisional_pressure.push_back(parts.collisional_pressure);
  s.pore_pressure.push_back(pore_pressure);
  s.granular_temperature.push_back(state.granular_temperature);
  s.locus_size.push_back(state.force_chains.r_c);
  s.void_ratio.push_back(1.0 / state.solid_fraction - 1.0);
  s.fluidized.push_back(state.force_chains.fluidized ? 1.0 : 0.0);
  s.yield_value.push_back(yield_value);
  s.stage.push_back(stage);
  s.collisional_dissipation.push_back(parts.collisional_dissipation);
  s.liquid_dissipation.push_back(parts.liquid_dissipation);
}

// Drift d ln|y| / dε_d between series entries i0 < i1 (finite: |y| is floored at 1e-300, so a
// quantity that leaves 0 shows a large drift, one that stays 0 none).
double log_drift(const std::vector<double>& y, const std::vector<double>& eps_d, std::size_t i0,
                 std::size_t i1) {
  const double floor = 1e-300;
  return (std::log(std::max(std::abs(y[i1]), floor)) - std::log(std::max(std::abs(y[i0]), floor))) /
         (eps_d[i1] - eps_d[i0]);
}

void check_state(long step, const PointState& state, const StressParts& parts) {
  core::check_finite(state.granular_temperature, step, "REV point", "granular_temperature", true);
  core::check_finite(state.force_chains.r_c, step, "REV point", "locus_size r_c", true);
  core::check_finite(state.solid_fraction, step, "REV point", "solid_fraction", true);
  core::check_finite(parts.force_chain.norm() + parts.collisional.norm() + parts.liquid.norm(),
                     step, "REV point", "stress");
}

// Ratio r of geometric steps dt0 r^k, k < n, summing to `duration` (bisection on r >= 1);
// 1 when uniform steps are no larger than dt0.
double growth_ratio(double dt0, double duration, int n) {
  if (!(dt0 > 0) || dt0 * n >= duration) return 1.0;
  double lo = 1.0, hi = 2.0;
  const auto total = [&](double r) { return dt0 * (std::pow(r, n) - 1.0) / (r - 1.0); };
  while (total(hi) < duration) hi *= 2.0;
  for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (total(mid) < duration ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

ElementResult run_triaxial(const MultiRegimePoint& point, const TriaxialControl& control) {
  ElementResult result;
  run_triaxial(point, control, result);
  return result;
}

void run_triaxial(const MultiRegimePoint& point, const TriaxialControl& control,
                  ElementResult& result, const std::function<void(double)>& progress) {
  result = ElementResult{};
  const auto& settings = point.settings();
  const auto& liquid = settings.liquid_parameters;
  const double K_w = liquid.bulk_modulus;
  const double nu_limit = point.solid_fraction_limit();
  const double u_b = control.pore_pressure;

  PointState state = point.initial_state(control.void_ratio, control.effective_pressure,
                                         control.overconsolidation, control.initial_temperature);
  StressParts parts = point.evaluate(state, Eigen::Matrix3d::Zero());
  parts.force_chain = state.force_chains.stress;
  double u_w = control.pore_pressure;
  // Cell (total radial) stress held through the test: the initial isotropic total stress.
  const double cell = parts.total_without_pore_pressure()(1, 1) + u_w;
  const double tolerance = control.stress_tolerance * std::max(std::abs(cell), 1.0);

  double time = 0, eps_d = 0, eps_v = 0, eps_a = 0;
  auto& series = result.series;
  record(series, time, eps_d, eps_v, eps_a, state, parts, u_w,
         point.force_chain_model() ? point.force_chain_model()->yield_value(state.force_chains) : 0,
         0);
  double total_time = 0;
  for (const auto& st : control.stages) total_time += st.duration;

  long step = 0;
  for (std::size_t stage_index = 0; stage_index < control.stages.size(); ++stage_index) {
    const TriaxialStage& stage = control.stages[stage_index];
    const double ratio = growth_ratio(stage.first_time_step, stage.duration, stage.steps);
    double dt = ratio > 1.0 ? stage.first_time_step / ratio : stage.duration / stage.steps;
    double x_guess = 0.0;  // Δε_v of the previous step
    // Run on until steady: equal steps and a deviatoric rate only (the drift is per unit ε_d).
    StageEnd end;
    end.steady_checked =
        stage.steady_tolerance > 0 && ratio == 1.0 && stage.deviatoric_strain_rate > 0;
    const int window = std::min(
        stage.steady_window > 0 ? stage.steady_window : std::max(1, stage.steps / 10), stage.steps);
    const int max_steps = end.steady_checked ? std::max(stage.max_steps, stage.steps) : stage.steps;
    for (int k = 0; k < max_steps; ++k) {
      dt *= ratio;
      const double d_eps_d = stage.deviatoric_strain_rate * dt;
      ++step;
      const double porosity = 1.0 - state.solid_fraction;
      const double drainage_rate =  // k = κ / (η0 H²), 1/(Pa s)
          stage.drainage == Drainage::consolidating
              ? model::permeability(liquid, settings.collisional_parameters.diameter,
                                    state.solid_fraction) /
                    (liquid.viscosity * stage.drainage_length * stage.drainage_length)
              : 0.0;
      const auto trial = [&](double x, Trial& out) {
        out.state = state;
        Eigen::Matrix3d rate = Eigen::Matrix3d::Zero();
        rate(0, 0) = (d_eps_d + x / 3.0) / dt;
        rate(1, 1) = rate(2, 2) = (-0.5 * d_eps_d + x / 3.0) / dt;
        out.parts = point.advance(out.state, rate, dt);
        switch (stage.drainage) {
          case Drainage::drained:
            out.pore_pressure = u_b;
            break;
          case Drainage::undrained:
            out.pore_pressure = u_w + K_w / porosity * x;
            break;
          case Drainage::consolidating: {
            const double m = K_w / porosity;
            out.pore_pressure =
                (u_w + m * (x + dt * drainage_rate * u_b)) / (1.0 + m * dt * drainage_rate);
            break;
          }
        }
        out.residual = out.parts.total_without_pore_pressure()(1, 1) + out.pore_pressure - cell;
        ++result.solver_evaluations;
      };
      // Bracket the root of the radial residual, increasing in Δε_v (compaction stiffens every
      // term), inside the admissible range of ν.
      const double x_max = std::log(nu_limit / state.solid_fraction);
      const double x_min = std::log(0.05 / state.solid_fraction);  // ν >= 0.05: a dilute gas
      Trial a, b, t;
      double xa = std::clamp(x_guess, x_min, x_max);
      trial(xa, a);
      Trial* best = &a;
      double x_best = xa;
      if (std::abs(a.residual) > tolerance) {
        const double p_eff = std::max(state.force_chains.stress.trace() / 3.0,
                                      settings.force_chain_parameters.pressure_floor);
        double stiffness = (stage.drainage == Drainage::drained ? 0.0 : K_w / porosity) +
                           (point.force_chain_model()
                                ? 3.0 * point.force_chain_model()->elasticity().bulk_modulus(p_eff)
                                : 0.0) +
                           1e3;
        double h = std::abs(a.residual) / stiffness;
        const double direction = a.residual < 0 ? 1.0 : -1.0;
        double xb = xa;
        bool bracketed = false;
        for (int it = 0; it < 200; ++it) {
          xb = std::clamp(xa + direction * h, x_min, x_max);
          trial(xb, b);
          if ((b.residual > 0) != (a.residual > 0) || std::abs(b.residual) <= tolerance) {
            bracketed = true;
            break;
          }
          if (xb == x_min || xb == x_max) break;
          xa = xb;  // keep the nearer point as the other end
          std::swap(a, b);
          h *= 4.0;
        }
        if (!bracketed)
          throw core::NumericalFailure(
              step, "REV point", "volumetric_strain_increment", xb,
              fmt::format("no volumetric strain increment in [{:.3g}, {:.3g}] brings the radial "
                          "stress to the cell pressure {:g} Pa (residual {:g} Pa): the point "
                          "cannot carry the cell pressure at this state",
                          x_min, x_max, cell, b.residual));
        if (std::abs(b.residual) <= tolerance) {
          best = &b;
          x_best = xb;
        } else {
          // Illinois (modified regula falsi) between xa (residual ra) and xb (rb), opposite signs
          double lo = xa, hi = xb, r_lo = a.residual, r_hi = b.residual;
          Trial* t_lo = &a;
          Trial* t_hi = &b;
          int side = 0;
          for (int it = 0; it < 200; ++it) {
            double x = hi - r_hi * (hi - lo) / (r_hi - r_lo);
            if (!(x > std::min(lo, hi) && x < std::max(lo, hi))) x = 0.5 * (lo + hi);
            trial(x, t);
            if (std::abs(t.residual) <= tolerance ||
                std::abs(hi - lo) <= 1e-15 * std::max(std::abs(x), 1e-3)) {
              best = &t;
              x_best = x;
              break;
            }
            if ((t.residual > 0) == (r_hi > 0)) {
              hi = x;
              r_hi = t.residual;
              std::swap(*t_hi, t);
              if (side == 1) r_lo *= 0.5;
              side = 1;
            } else {
              lo = x;
              r_lo = t.residual;
              std::swap(*t_lo, t);
              if (side == -1) r_hi *= 0.5;
              side = -1;
            }
            // the end with the smaller residual is the best so far
            best = std::abs(t_lo->residual) < std::abs(t_hi->residual) ? t_lo : t_hi;
            x_best = best == t_lo ? lo : hi;
          }
        }
      }
      result.max_radial_residual = std::max(result.max_radial_residual, std::abs(best->residual));
      const bool was_fluid = state.force_chains.fluidized;
      state = best->state;
      parts = best->parts;
      u_w = best->pore_pressure;
      x_guess = x_best * ratio;
      check_state(step, state, parts);
      core::check_finite(u_w, step, "REV point", "pore_pressure");
      time += dt;
      eps_d += d_eps_d;
      eps_v += x_best;
      eps_a += d_eps_d + x_best / 3.0;
      if (point.force_chain_model()) {
        if (!was_fluid && state.force_chains.fluidized && result.liquefaction_strain < 0)
          result.liquefaction_strain = eps_d;
        if (was_fluid && !state.force_chains.fluidized && result.resolidification_time < 0)
          result.resolidification_time = time;
      }
      record(series, time, eps_d, eps_v, eps_a, state, parts, u_w,
             parts.force_chain_update.yield_value, static_cast<int>(stage_index));
      result.steps = step;
      if (progress && step % 500 == 0) progress(std::min(time / total_time, 1.0));
      end.last = series.time.size() - 1;
      if (core::interrupted()) {  // SIGINT/SIGTERM: the series so far is the result
        result.stage_ends.push_back(end);
        return;
      }
      if (end.steady_checked && k + 1 >= stage.steps) {
        // drifts over the last `window` steps (the window the residual is averaged over)
        const std::size_t i0 = end.last - static_cast<std::size_t>(window);
        end.drift_temperature =
            log_drift(series.granular_temperature, series.deviatoric_strain, i0, end.last);
        end.drift_q = log_drift(series.q, series.deviatoric_strain, i0, end.last);
        end.steady = std::abs(end.drift_temperature) <= stage.steady_tolerance &&
                     std::abs(end.drift_q) <= stage.steady_tolerance;
        end.extra_steps = k + 1 - stage.steps;
        if (end.steady) break;
      }
    }
    result.stage_ends.push_back(end);
  }
}

ElementResult run_isotropic_compression(const MultiRegimePoint& point,
                                        const IsotropicControl& control) {
  ElementResult result;
  PointState state = point.initial_state(control.void_ratio, control.effective_pressure,
                                         control.overconsolidation, 0.0);
  StressParts parts = point.evaluate(state, Eigen::Matrix3d::Zero());
  parts.force_chain = state.force_chains.stress;
  const double dt =
      control.final_volumetric_strain / control.volumetric_strain_rate / control.steps;
  const Eigen::Matrix3d rate = control.volumetric_strain_rate / 3.0 * Eigen::Matrix3d::Identity();
  double time = 0, eps_v = 0;
  record(result.series, 0, 0, 0, 0, state, parts, control.pore_pressure, 0, 0);
  for (int step = 1; step <= control.steps; ++step) {
    parts = point.advance(state, rate, dt);
    check_state(step, state, parts);
    time += dt;
    eps_v += control.volumetric_strain_rate * dt;
    record(result.series, time, 0, eps_v, eps_v / 3.0, state, parts, control.pore_pressure,
           parts.force_chain_update.yield_value, 0);
    result.steps = step;
  }
  return result;
}

}  // namespace granflow::rev
