#include "continuum/rev/shear_stop.hpp"

#include <algorithm>
#include <cmath>

#include "core/interrupt.hpp"
#include "core/numerical_failure.hpp"

namespace granflow::rev {

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
    const double T = state.granular_temperature, nu = state.solid_fraction;
    core::check_finite(T, step, "REV point (shear stopped)", "granular_temperature", true);
    const double p_eff = parts.force_chain.trace() / 3.0;
    const Eigen::Matrix3d total = parts.total_without_pore_pressure();
    series.time.push_back(time);
    series.strain.push_back(stop_strain);
    series.time_step.push_back(dt);
    series.granular_temperature.push_back(T);
    series.solid_fraction.push_back(nu);
    series.void_ratio.push_back(1.0 / nu - 1.0);
    series.pressure.push_back(parts.collisional_pressure + parts.inertial_contact_pressure + p_eff);
    series.shear_stress.push_back(-total(0, 1));
    series.effective_pressure.push_back(p_eff);
    series.normal_stress.push_back(total(1, 1));
    series.collisional_pressure.push_back(parts.collisional_pressure);
  }
}

}  // namespace granflow::rev
