#include "continuum/rev/shear_stop.hpp"

#include <algorithm>
#include <cmath>

#include "continuum/model/closures.hpp"
#include "continuum/rev/simple_shear_mixed_control.hpp"
#include "core/interrupt.hpp"
#include "core/numerical_failure.hpp"

namespace granflow::rev {
namespace {

// One row of a stopped point: time since the stop, the strain of the stop, T, ν, e and stresses.
void append_row(SimpleShearSeries& series, double time, double stop_strain, double dt,
                const continuum::PointState& state, const continuum::StressParts& parts) {
  const double nu = state.solid_fraction;
  const double p_eff = parts.force_chain.trace() / 3.0;
  const Eigen::Matrix3d total = parts.total_without_pore_pressure();
  series.time.push_back(time);
  series.strain.push_back(stop_strain);
  series.time_step.push_back(dt);
  series.granular_temperature.push_back(state.granular_temperature);
  series.solid_fraction.push_back(nu);
  series.void_ratio.push_back(1.0 / nu - 1.0);
  series.pressure.push_back(parts.collisional_pressure + parts.inertial_contact_pressure + p_eff);
  series.shear_stress.push_back(-total(0, 1));
  series.effective_pressure.push_back(p_eff);
  series.normal_stress.push_back(total(1, 1));
  series.collisional_pressure.push_back(parts.collisional_pressure);
}

}  // namespace

void run_shear_stop(const continuum::MultiRegimePoint& point, continuum::PointState state,
                    double stop_strain, const ShearStopControl& control,
                    SimpleShearSeries& series) {
  const Eigen::Matrix3d at_rest = Eigen::Matrix3d::Zero();
  const bool force_chains = point.settings().force_chains;
  const double largest = control.largest_step_fraction * control.duration;
  double time = 0.0;
  for (long step = 1; time < control.duration && !core::interrupted(); ++step) {
    const auto start = point.evaluate(state, at_rest);
    const continuum::RiccatiCoefficients& k = start.temperature_equation;
    const double s = std::sqrt(std::max(state.granular_temperature, 0.0));
    // The cooling rate of s, |d(ds/dt)/ds| = c + 2 b s; a cold or inert point takes the largest.
    const double rate = std::abs(k.c + 2.0 * k.b * s);
    double dt = rate > 0.0 ? control.time_step_factor / rate : largest;
    dt = std::min({dt, largest, control.duration - time});
    if (!(dt > 0.0)) break;
    const continuum::StressParts parts =
        force_chains ? point.advance(state, at_rest, dt) : point.update(state, at_rest, dt, 1.0);
    time += dt;
    core::check_finite(state.granular_temperature, step, "REV point (shear stopped)",
                       "granular_temperature", true);
    append_row(series, time, stop_strain, dt, state, parts);
  }
}

void run_drained_stop(const continuum::MultiRegimePoint& point, continuum::PointState state,
                      double stop_strain, const DrainedStopControl& control,
                      SimpleShearSeries& series) {
  const auto& settings = point.settings();
  const auto& liquid = settings.liquid_parameters;
  const ShearStopControl& stop = control.stop;
  const double largest = stop.largest_step_fraction * stop.duration;
  double time = 0.0, guess = 0.0, previous_dt = 0.0;
  double modulus = 0.0;  // M = dσ_yy/dε_yy of the last step
  double sigma_yy =
      point.evaluate(state, Eigen::Matrix3d::Zero()).total_without_pore_pressure()(1, 1);
  for (long step = 1; time < stop.duration && !core::interrupted(); ++step) {
    const double k = model::permeability(liquid, settings.collisional_parameters.diameter,
                                         state.solid_fraction) /
                     (liquid.viscosity * control.drainage_length * control.drainage_length);
    const auto start = point.evaluate(state, Eigen::Matrix3d::Zero());
    const double s = std::sqrt(std::max(state.granular_temperature, 0.0));
    const double rate =
        std::max(std::abs(start.temperature_equation.c + 2.0 * start.temperature_equation.b * s),
                 k * modulus);
    double dt = rate > 0.0 ? stop.time_step_factor / rate : largest;
    // at least smallest_step_fraction × duration: backward Euler in u is stable at any step, and
    // a stiff point (ν near ν_c) would otherwise take millions of steps
    dt = std::clamp(dt, control.smallest_step_fraction * stop.duration, largest);
    // The last step ends on the duration; a remainder below 1e-3 Δt joins this step (a sliver
    // of a step would make the drainage resistance 1/(k Δt) huge for nothing).
    const bool last = stop.duration - time < 1.001 * dt;
    if (last) dt = stop.duration - time;
    if (!(dt > 0.0)) break;
    // First trial: the last step's compaction rate over this step (u = ε̇/k carries over).
    if (previous_dt > 0.0) guess *= dt / previous_dt;
    previous_dt = dt;
    const NormalStressStep next =
        advance_at_normal_stress(point, state, 0.0, dt, control.normal_stress, guess,
                                 control.relative_tolerance, step, control.max_splits, 1.0 / k);
    const double sigma_next = next.parts.total_without_pore_pressure()(1, 1);
    if (next.vertical_strain != 0.0)
      modulus = std::max(0.0, (sigma_next - sigma_yy) / next.vertical_strain);
    sigma_yy = sigma_next;
    state = next.state;
    guess = next.vertical_strain;
    time = last ? stop.duration : time + dt;
    core::check_finite(state.granular_temperature, step, "REV point (drained stop)",
                       "granular_temperature", true);
    append_row(series, time, stop_strain, dt, state, next.parts);
    series.vertical_strain_rate.push_back(next.vertical_strain / dt);
  }
}

}  // namespace granflow::rev
