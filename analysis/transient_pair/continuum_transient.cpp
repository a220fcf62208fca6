#include "analysis/transient_pair/continuum_transient.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "continuum/rev/shear_stop.hpp"
#include "continuum/sections/model_sections.hpp"
#include "core/numerical_failure.hpp"
#include "statistics/least_squares.hpp"

namespace granflow::transient_pair {

void continuum_transient(const core::Case& condition, double phi0, double p0,
                         rev::SimpleShearResult& result) {
  const continuum::MultiRegimeSettings settings = continuum::read_multi_regime_settings(condition);
  rev::SimpleShearControl control;
  control.control = rev::ShearControl::constant_volume;
  control.shear_rate = condition.number("shear_rate");
  control.void_ratio = 1.0 / phi0 - 1.0;
  control.effective_pressure = p0;
  control.overconsolidation = 1.0;
  const double d = condition.number("material.diameter");
  control.initial_temperature =
      condition.number("continuum.initial_temperature") * std::pow(d * control.shear_rate, 2);
  control.strain_increment = condition.number("continuum.strain_increment");
  control.max_strain = condition.number("strain.total");
  if (condition.string("control.mode") == "drained") {
    control.control = rev::ShearControl::constant_pressure;
    control.normal_stress =
        condition.has("control.normal_stress") ? condition.number("control.normal_stress") : p0;
    control.drainage_length = condition.number("control.drainage_length");
  }
  if (condition.string("control.mode") == "damped_height") {
    control.control = rev::ShearControl::constant_pressure;
    control.normal_stress =
        condition.has("control.normal_stress") ? condition.number("control.normal_stress") : p0;
    control.height_resistance = condition.number("control.height_resistance");
  }
  if (condition.has("rate_step.strain")) {
    control.rate_step_strain = condition.number("rate_step.strain");
    control.rate_step_shear_rate = condition.number("rate_step.shear_rate");
  }
  control.steady_tolerance = 0.0;  // never steady: the series covers the DEM's strain
  control.max_steps = std::numeric_limits<long>::max() / 2;
  rev::run_simple_shear(continuum::MultiRegimePoint(settings), control, result);
}

void continuum_stop(const core::Case& condition, const rev::SimpleShearResult& sheared,
                    double normal_stress, rev::SimpleShearSeries& out) {
  const continuum::MultiRegimePoint point(continuum::read_multi_regime_settings(condition));
  rev::ShearStopControl control;
  control.duration = condition.number("stop.duration");
  const double strain = sheared.series.strain.empty() ? 0.0 : sheared.series.strain.back();
  if (const double length = condition.number("stop.drainage_length"); length > 0.0) {
    const rev::DrainedStopControl drained{control, normal_stress, length};
    rev::run_drained_stop(point, sheared.final_state, strain, drained, out);
    return;
  }
  rev::run_shear_stop(point, sheared.final_state, strain, control, out);
}

std::string fitted_key(const std::string& name) {
  return name.find('.') == std::string::npos ? "force_chains." + name : name;
}

core::Case with_force_chain_values(const core::Case& condition, const core::Schema& schema,
                                   const std::vector<std::string>& names,
                                   const std::vector<double>& values) {
  std::vector<std::string> overrides;
  for (std::size_t j = 0; j < names.size(); ++j)
    overrides.push_back(fmt::format("{}={:.17g}", fitted_key(names[j]), values[j]));
  return core::Case::parse(condition.resolved_yaml(), condition.origin(), overrides, schema);
}

double interpolate(const std::vector<double>& x, const std::vector<double>& y, double at) {
  if (x.empty()) return std::numeric_limits<double>::quiet_NaN();
  if (at <= x.front()) return y.front();
  if (at >= x.back()) return y.back();
  const auto hi = std::size_t(std::upper_bound(x.begin(), x.end(), at) - x.begin());
  const std::size_t lo = hi - 1;
  const double w = (at - x[lo]) / (x[hi] - x[lo]);
  return (1.0 - w) * y[lo] + w * y[hi];
}

TransientFit fit_force_chains(const core::Case& condition, const core::Schema& schema,
                              const std::vector<std::string>& names, const DemTransient& dem) {
  TransientFit out;
  out.names = names;
  for (const auto& name : names) out.start.push_back(condition.number(fitted_key(name)));
  const std::size_t n = dem.strain.size();
  std::vector<double> sigma_p(n), sigma_tau(n);
  for (std::size_t i = 0; i < n; ++i) {
    sigma_p[i] = std::max(0.5 * (dem.p_max[i] - dem.p_min[i]), 0.01 * dem.p0);
    sigma_tau[i] = std::max(0.5 * (dem.tau_max[i] - dem.tau_min[i]), 0.01 * dem.p0);
  }
  const auto residuals = [&](const Eigen::VectorXd& theta, Eigen::VectorXd& r) {
    r.resize(Eigen::Index(2 * n));
    rev::SimpleShearResult run;
    bool failed = false;
    try {
      const core::Case c = with_force_chain_values(
          condition, schema, names, std::vector<double>(theta.data(), theta.data() + theta.size()));
      continuum_transient(c, dem.phi0, dem.p0, run);
    } catch (const core::NumericalFailure&) {
      failed = true;
    }
    const auto& s = run.series;
    for (std::size_t i = 0; i < n; ++i) {
      if (failed || s.strain.empty()) {
        r[Eigen::Index(2 * i)] = r[Eigen::Index(2 * i + 1)] = 1e3;
        continue;
      }
      r[Eigen::Index(2 * i)] =
          (dem.p_mean[i] - interpolate(s.strain, s.pressure, dem.strain[i])) / sigma_p[i];
      r[Eigen::Index(2 * i + 1)] =
          (dem.tau_mean[i] - interpolate(s.strain, s.shear_stress, dem.strain[i])) / sigma_tau[i];
    }
  };
  Eigen::VectorXd start(Eigen::Index(names.size()));
  std::vector<statistics::ParameterBounds> bounds;
  // calibrate.range (20 by default) either way of the case's value: the constitutive parameters
  // are positive and the model's response to them is smooth only over a bounded range.
  const double range = condition.number("calibrate.range");
  for (std::size_t j = 0; j < names.size(); ++j) {
    start[Eigen::Index(j)] = out.start[j];
    bounds.push_back(
        statistics::ParameterBounds::between(out.start[j] / range, out.start[j] * range));
  }
  statistics::LeastSquaresOptions options;
  // The REV's stress integration is accurate to its sub-step tolerance (1e-5 relative), so the
  // central differences step 1 % of θ and the fit stops at 1e-6 relative change; each evaluation
  // is one REV run (0.1-1 s), hence the budget.
  options.relative_step = 1e-2;
  options.tolerance = 1e-6;
  options.max_evaluations = 200;
  options.failed_residual = 1e3;
  const auto fit = statistics::minimise_residuals(residuals, int(2 * n), start, bounds, options);
  for (Eigen::Index j = 0; j < fit.estimate.size(); ++j) {
    out.estimate.push_back(fit.estimate[j]);
    out.standard_error.push_back(fit.standard_error[j]);
    out.at_bound.push_back(std::size_t(j) < fit.parameter_at_bound.size() &&
                           fit.parameter_at_bound[std::size_t(j)]);
  }
  out.chi2_red = fit.chi2_red;
  out.chi2_initial = fit.chi2_initial;
  out.evaluations = fit.evaluations;
  out.points = fit.points;
  out.converged = fit.converged;
  return out;
}

}  // namespace granflow::transient_pair
