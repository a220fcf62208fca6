#include "analysis/calibration/calibration.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <Eigen/SVD>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>

#include "continuum/sections/model_sections.hpp"
#include "core/result_columns.hpp"
#include "core/result_file.hpp"
#include "core/run.hpp"
#include "statistics/least_squares.hpp"

namespace granflow::calibration {

const std::vector<ParameterSpec>& parameter_specs() {
  // Bounds: the schema's range of the case key where there is one; (0, 1) for e_r (ε = 1 makes
  // Γ vanish and T unbounded); factors positive.
  static const std::vector<ParameterSpec> specs = {
      {"restitution", "material.restitution", 0.01, 0.999,
       "normal restitution e_r (enters ε, J and the correlation length)"},
      {"jamming_fraction", "collisional.jamming_fraction", 0.49, 0.74, "ν_c, singularity of g0"},
      {"correlation_length_constant", "collisional.correlation_length_constant", 1e-6, 1e3,
       "c of Jenkins' correlation length or c_L of toward_jamming (needs one of them)"},
      {"correlation_length_onset", "collisional.correlation_length_onset", 0.3, 0.58,
       "ν_L where toward_jamming's L starts to grow (needs correlation_length: toward_jamming)"},
      {"correlation_length_exponent", "collisional.correlation_length_exponent", 0.1, 4.0,
       "n of toward_jamming's L/d ∝ (ν_c - ν)^-n (needs correlation_length: toward_jamming)"},
      {"liquid_viscosity_factor", "liquid.viscosity", 1e-6, 1e6,
       "factor on η0 (σ_L, Λ and drag); written as liquid.viscosity = factor × η0"},
      {"fluctuation_dissipation_factor", "", 1e-6, 1e6,
       "factor f_Λ on Λ (no case key yet: applied at the calibration's call site)"},
      // The critical state of the force chains (in-parallel steady model, force_chains on).
      {"critical_void_ratio", "force_chains.e_Gamma", 0.2, 2.0,
       "e_Γ of e_cs = e_Γ - λ_c (p/p_ref)^ξ_c (1/(1+e_Γ): φ of the critical state as p -> 0)"},
      {"critical_state_slope", "force_chains.lambda_c", 1e-6, 1.0,
       "λ_c of the critical state line"},
      {"critical_state_exponent", "force_chains.xi_c", 0.02, 5.0, "ξ_c of the critical state line"},
      {"critical_stress_ratio", "force_chains.M_c", 0.05, 2.9,
       "M_c, the Lade-Duncan ratio q/p in compression (simple shear: μ_FC = M(θ=0)/√3)"},
      {"contact_production", "steady.contact_production", 0.0, 1.0,
       "α_FC, fraction of τ_FC γ̇ fed to T (granflow's own term; start it above 0)"},
      {"friction_rise", "steady.friction_rise", 0.0, 2.0,
       "Δμ_FC of μ_FC(I) = μ_cs + Δμ_FC/(1 + I_0/I) (granflow's own; start it above 0)"},
      {"friction_rise_I0", "steady.friction_rise_I0", 1e-3, 10.0,
       "I_0 of the force chains' friction rise"},
      {"inertial_contact", "collisional.inertial_contact", 0.0, 10.0,
       "a_c of the contacts' dense inertial stress ρ_p (a_c d γ̇)² (ν_c - ν)^-m (granflow's own)"},
      {"inertial_contact_power", "collisional.inertial_contact_power", 0.5, 4.0,
       "m of the contacts' dense inertial stress ∝ (ν_c - ν)^-m (2: φ = φ_c - a I)"},
      {"inertial_contact_friction", "collisional.inertial_contact_friction", 0.0, 3.0,
       "μ_IC, the friction of the contacts' dense inertial stress (start it above 0)"},
      {"viscous_contact", "liquid.viscous_contact", 0.0, 1e4,
       "b_v, the viscous scale b_v η0 γ̇ (ν_c - ν)^-m of the contacts' stress (start it above 0)"},
      {"viscous_dilatancy", "steady.viscous_dilatancy", 0.0, 10.0,
       "a_J of e_Γ + a_J √J (granflow's own, immersed; start it above 0)"},
  };
  return specs;
}

const ParameterSpec& parameter_spec(const std::string& name) {
  for (const auto& s : parameter_specs())
    if (s.name == name) return s;
  std::string valid;
  for (const auto& s : parameter_specs()) valid += (valid.empty() ? "" : ", ") + s.name;
  throw std::invalid_argument(fmt::format("unknown parameter '{}' (valid: {})", name, valid));
}

double parameter_value(const CalibratedModel& m, const std::string& name) {
  const auto& col = m.settings.collisional_parameters;
  if (name == "restitution") return col.restitution;
  if (name == "jamming_fraction") return col.jamming_fraction;
  if (name == "correlation_length_constant") return col.correlation_length_constant;
  if (name == "correlation_length_onset") return col.correlation_length_onset;
  if (name == "correlation_length_exponent") return col.correlation_length_exponent;
  if (name == "liquid_viscosity_factor")
    return m.settings.liquid_parameters.viscosity / m.reference_liquid_viscosity;
  if (name == "fluctuation_dissipation_factor") return m.factors.fluctuation_dissipation;
  const auto& fc = m.settings.force_chain_parameters;
  if (name == "critical_void_ratio") return fc.e_Gamma;
  if (name == "critical_state_slope") return fc.lambda_c;
  if (name == "critical_state_exponent") return fc.xi_c;
  if (name == "critical_stress_ratio") return fc.M_c;
  if (name == "contact_production") return m.factors.contact_production;
  if (name == "friction_rise") return m.factors.friction_rise;
  if (name == "friction_rise_I0") return m.factors.friction_rise_I0;
  if (name == "viscous_dilatancy") return m.factors.viscous_dilatancy;
  if (name == "inertial_contact") return m.settings.inertial_contact;
  if (name == "inertial_contact_power") return m.settings.inertial_contact_power;
  if (name == "inertial_contact_friction") return m.settings.inertial_contact_friction;
  if (name == "viscous_contact") return m.settings.viscous_contact;
  return parameter_spec(name).lower;  // throws for unknown names
}

void set_parameter(CalibratedModel& m, const std::string& name, double value) {
  auto& col = m.settings.collisional_parameters;
  if (name == "restitution")
    col.restitution = value;
  else if (name == "jamming_fraction")
    col.jamming_fraction = value;
  else if (name == "correlation_length_constant")
    col.correlation_length_constant = value;
  else if (name == "correlation_length_onset")
    col.correlation_length_onset = value;
  else if (name == "correlation_length_exponent")
    col.correlation_length_exponent = value;
  else if (name == "liquid_viscosity_factor")
    m.settings.liquid_parameters.viscosity = value * m.reference_liquid_viscosity;
  else if (name == "fluctuation_dissipation_factor")
    m.factors.fluctuation_dissipation = value;
  else if (name == "critical_void_ratio")
    m.settings.force_chain_parameters.e_Gamma = value;
  else if (name == "critical_state_slope")
    m.settings.force_chain_parameters.lambda_c = value;
  else if (name == "critical_state_exponent")
    m.settings.force_chain_parameters.xi_c = value;
  else if (name == "critical_stress_ratio")
    m.settings.force_chain_parameters.M_c = value;
  else if (name == "contact_production")
    m.factors.contact_production = value;
  else if (name == "friction_rise")
    m.factors.friction_rise = value;
  else if (name == "friction_rise_I0")
    m.factors.friction_rise_I0 = value;
  else if (name == "viscous_dilatancy")
    m.factors.viscous_dilatancy = value;
  else if (name == "inertial_contact")
    m.settings.inertial_contact = value;
  else if (name == "inertial_contact_power")
    m.settings.inertial_contact_power = value;
  else if (name == "inertial_contact_friction")
    m.settings.inertial_contact_friction = value;
  else if (name == "viscous_contact")
    m.settings.viscous_contact = value;
  else
    parameter_spec(name);  // throws
}

double case_value(const CalibratedModel& m, const std::string& name) {
  if (name == "liquid_viscosity_factor") return m.settings.liquid_parameters.viscosity;
  return parameter_value(m, name);
}

const std::vector<std::string>& observable_names() {
  static const std::vector<std::string> names = {"friction", "solid_fraction", "scaled_temperature",
                                                 "scaled_pressure"};
  return names;
}

const char* protocol_name(Protocol protocol) {
  return protocol == Protocol::constant_volume ? "constant_volume" : "constant_pressure";
}

Protocol parse_protocol(const std::string& name) {
  if (name == "constant_pressure") return Protocol::constant_pressure;
  if (name == "constant_volume") return Protocol::constant_volume;
  throw std::invalid_argument(
      fmt::format("unknown protocol '{}' (valid: constant_pressure, constant_volume)", name));
}

Observable imposed_observable(Protocol protocol) {
  return protocol == Protocol::constant_volume ? Observable::solid_fraction
                                               : Observable::scaled_pressure;
}

double fit_error(const DataPoint& point, Observable observable) {
  const int k = static_cast<int>(observable);
  const double floor = point.floor[k] * std::abs(point.value[k]);
  return std::sqrt(point.error[k] * point.error[k] + floor * floor);
}

bool tests(const DataPoint& point, Observable observable) {
  const int k = static_cast<int>(observable);
  return observable != imposed_observable(point.protocol) && std::isfinite(point.value[k]) &&
         fit_error(point, observable) > 0;
}

Observable parse_observable(const std::string& name) {
  const auto& names = observable_names();
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<Observable>(i);
  throw std::invalid_argument(
      fmt::format("unknown observable '{}' (valid: friction, solid_fraction, scaled_temperature, "
                  "scaled_pressure)",
                  name));
}

DemDataset read_dem_dataset(const std::filesystem::path& file, int source_index) {
  if (!std::filesystem::exists(file))
    throw std::runtime_error(fmt::format("{}: no such DEM dataset", file.string()));
  DemDataset out;
  const auto column = [&](const std::string& name) {
    try {
      return core::read_dataset(file, "/steady/" + name);
    } catch (const std::exception& e) {
      throw std::runtime_error(fmt::format(
          "{}: /steady/{} missing or unreadable ({}); expected a DEM dataset (docs/results.md)",
          file.string(), name, e.what()));
    }
  };
  out.diameter = core::read_number_attribute(file, "/steady", "diameter");
  out.particle_density = core::read_number_attribute(file, "/steady", "particle_density");
  std::string control = "constant_pressure";  // datasets written before the attribute existed
  try {
    control = core::read_string_attribute(file, "/steady", "control");
  } catch (const std::exception&) {  // no attribute: constant pressure, as before
  }
  try {
    out.protocol = parse_protocol(control);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(
        fmt::format("{}: /steady attribute control: {}", file.string(), e.what()));
  }
  // The names of the DEM kind's /steady table (dem_coupling/kind/dem_columns.hpp).
  namespace c = core::columns;
  const std::string err = c::error_suffix;
  const auto shear_rate = column(c::shear_rate.name), sigma = column(c::normal_stress.name),
             mu = column(c::friction.name), mu_err = column(c::friction.name + err),
             phi = column(c::solid_fraction.name), phi_err = column(c::solid_fraction.name + err),
             T = column(c::granular_temperature.name),
             T_err = column(c::granular_temperature.name + err),
             T_scaled = column(c::scaled_temperature.name),
             mu_p = column(c::particle_friction.name), I = column(c::inertial_number.name);
  // Immersed datasets carry η0 per row (a wet sweep varies it); dry ones have no such column.
  std::vector<double> viscosity;
  try {
    viscosity = core::read_dataset(file, std::string("/steady/") + c::liquid_viscosity.name);
  } catch (const std::exception&) {  // dry datasets have no liquid viscosity column
    viscosity.clear();
  }
  std::vector<double> sigma_err;  // σ_yy's standard error (the scaled pressure's)
  try {
    sigma_err = core::read_dataset(file, std::string("/steady/") + c::normal_stress.name + err);
  } catch (const std::exception&) {  // written by every granflow DEM run; absent in older tables
    sigma_err.clear();
  }
  // One row per condition in every column: a shorter or longer column is a damaged dataset.
  const std::pair<std::string, const std::vector<double>*> columns[] = {
      {c::normal_stress.name, &sigma},
      {c::friction.name, &mu},
      {c::friction.name + err, &mu_err},
      {c::solid_fraction.name, &phi},
      {c::solid_fraction.name + err, &phi_err},
      {c::granular_temperature.name, &T},
      {c::granular_temperature.name + err, &T_err},
      {c::scaled_temperature.name, &T_scaled},
      {c::particle_friction.name, &mu_p},
      {c::inertial_number.name, &I},
      {c::liquid_viscosity.name, &viscosity},
      {c::normal_stress.name + err, &sigma_err}};
  for (const auto& [name, values] : columns)
    if (values->size() != shear_rate.size() &&
        !((values == &viscosity || values == &sigma_err) && values->empty()))
      throw std::runtime_error(fmt::format(
          "{}: /steady/{} has {} rows but /steady/shear_rate has {}; expected one row per "
          "condition in every column (docs/dem_dataset.md)",
          file.string(), name, values->size(), shear_rate.size()));
  for (std::size_t r = 0; r < shear_rate.size(); ++r) {
    DataPoint p;
    p.shear_rate = shear_rate[r];
    p.normal_stress = sigma[r];
    p.particle_friction = mu_p[r];
    p.inertial_number = I[r];
    if (!viscosity.empty()) p.liquid_viscosity = viscosity[r];
    p.value[0] = mu[r];
    p.error[0] = mu_err[r];
    p.value[1] = phi[r];
    p.error[1] = phi_err[r];
    p.value[2] = T_scaled[r];
    p.error[2] = T[r] > 0 ? T_err[r] * T_scaled[r] / T[r] : NAN;  // same relative error as T
    // p* = σ_yy/(ρ_p d² γ̇²) with the DEM's d and ρ_p, as its T* = T/(d γ̇)²
    const double stress_unit =
        out.particle_density * out.diameter * out.diameter * p.shear_rate * p.shear_rate;
    p.value[3] = sigma[r] / stress_unit;
    p.error[3] = sigma_err.empty() ? 0.0 : sigma_err[r] / stress_unit;
    p.protocol = out.protocol;
    p.source = source_index;
    p.row = static_cast<int>(r);
    // Usable: the controls, and every observable the protocol predicts with its error bar.
    const bool volume = out.protocol == Protocol::constant_volume;
    bool usable = p.shear_rate > 0 && p.normal_stress > 0 && (!volume || p.value[1] > 0);
    for (int k = 0; k < observable_count; ++k) {
      if (Observable(k) == imposed_observable(out.protocol)) continue;
      usable = usable && std::isfinite(p.value[k]) && std::isfinite(p.error[k]) && p.error[k] > 0;
    }
    if (usable)
      out.points.push_back(p);
    else
      out.skipped.push_back(fmt::format(
          "{} row {}: non-finite steady values or non-positive error bars (failed or too short "
          "condition)",
          file.string(), r));
  }
  return out;
}

SteadyShearState predict(const CalibratedModel& model, const DataPoint& point) {
  const bool own_friction =
      std::isfinite(point.particle_friction) &&
      point.particle_friction != model.settings.collisional_parameters.particle_friction;
  // A wet row is predicted at its own η0, scaled by the fitted liquid_viscosity_factor
  // (= settings viscosity / reference viscosity, 1 before the fit).
  const bool own_viscosity = std::isfinite(point.liquid_viscosity) && model.settings.liquid &&
                             model.reference_liquid_viscosity > 0;
  // Constant pressure: given p, predicts φ; constant volume: given φ, predicts p.
  const auto at = [&](const continuum::MultiRegimeSettings& s) {
    return point.protocol == Protocol::constant_volume
               ? steady_simple_shear_at_solid_fraction(s, model.factors, point.shear_rate,
                                                       point.value[1])
               : steady_simple_shear(s, model.factors, point.shear_rate, point.normal_stress);
  };
  if (!own_friction && !own_viscosity) return at(model.settings);
  continuum::MultiRegimeSettings s = model.settings;
  if (own_friction) s.collisional_parameters.particle_friction = point.particle_friction;
  if (own_viscosity)
    s.liquid_parameters.viscosity = point.liquid_viscosity *
                                    model.settings.liquid_parameters.viscosity /
                                    model.reference_liquid_viscosity;
  return at(s);
}

double predicted(const SteadyShearState& s, Observable observable) {
  switch (observable) {
    case Observable::friction:
      return s.friction;
    case Observable::solid_fraction:
      return s.solid_fraction;
    case Observable::scaled_temperature:
      return s.scaled_temperature;
    case Observable::scaled_pressure:
      return s.scaled_pressure;
  }
  return NAN;
}

CalibratedModel apply(const CalibratedModel& start, const std::vector<std::string>& names,
                      const Eigen::VectorXd& values) {
  CalibratedModel m = start;
  for (std::size_t j = 0; j < names.size(); ++j) set_parameter(m, names[j], values[j]);
  return m;
}

namespace {
FitResult fit_from(const CalibratedModel& start, const std::vector<std::string>& names,
                   const std::vector<DataPoint>& data, const std::vector<Observable>& observables,
                   int max_evaluations);
}  // namespace

FitResult fit(const CalibratedModel& start, const std::vector<std::string>& names,
              const std::vector<DataPoint>& data, const std::vector<Observable>& observables,
              int max_evaluations, int starts) {
  FitResult best = fit_from(start, names, data, observables, max_evaluations);
  std::mt19937 rng(20261201u);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int k = 1; k < starts; ++k) {
    CalibratedModel moved = start;
    for (const auto& name : names) {
      const ParameterSpec& spec = parameter_spec(name);
      const auto bounds = statistics::ParameterBounds::between(spec.lower, spec.upper);
      const double u = statistics::unconstrained_parameter(parameter_value(start, name), bounds);
      set_parameter(moved, name, statistics::bounded_parameter(u + normal(rng), bounds));
    }
    FitResult trial;
    try {
      trial = fit_from(moved, names, data, observables, max_evaluations);
    } catch (const std::exception&) {
      continue;  // a start where the model carries no condition at all
    }
    if (trial.chi2 < best.chi2) {
      trial.initial = best.initial;  // report the user's start
      trial.chi2_initial = best.chi2_initial;
      best = trial;
    }
  }
  return best;
}

namespace {
FitResult fit_from(const CalibratedModel& start, const std::vector<std::string>& names,
                   const std::vector<DataPoint>& data, const std::vector<Observable>& observables,
                   int max_evaluations) {
  FitResult out;
  out.names = names;
  const int n = static_cast<int>(names.size());
  // The residuals: the (point, observable) pairs the point tests (its protocol predicts the
  // observable, the value is measured, σ > 0), point-major.
  for (std::size_t i = 0; i < data.size(); ++i)
    for (std::size_t k = 0; k < observables.size(); ++k)
      if (tests(data[i], observables[k])) {
        out.residual_point.push_back(static_cast<int>(i));
        out.residual_observable.push_back(static_cast<int>(k));
      }
  const int m = static_cast<int>(out.residual_point.size());
  if (m <= n)
    throw std::invalid_argument(fmt::format(
        "{} residuals for {} parameters: need more data points or observables than parameters", m,
        n));
  // Each parameter inside its open interval by the transform of statistics/least_squares.hpp
  // (logistic map of an unconstrained coordinate): no trial leaves the box, so the penalty wall
  // of earlier versions (a residual of 1e3 σ outside the interval) is gone. What remains is a
  // condition the model cannot carry at a θ inside the box (e.g. no steady state): its residuals
  // are 1e3 σ, so LM rejects that step and shortens it.
  std::vector<statistics::ParameterBounds> bounds;
  for (const auto& name : names) {
    const ParameterSpec& spec = parameter_spec(name);
    bounds.push_back(statistics::ParameterBounds::between(spec.lower, spec.upper));
  }
  out.initial.resize(n);
  for (int j = 0; j < n; ++j) out.initial[j] = parameter_value(start, names[j]);
  for (int j = 0; j < n; ++j)
    if (!bounds[j].contains(out.initial[j]))
      throw std::invalid_argument(
          fmt::format("start value {} = {} is outside its interval ({}, {})", names[j],
                      out.initial[j], bounds[j].lower, bounds[j].upper));
  constexpr double unsupported_condition = 1e3;
  auto residuals = [&](const Eigen::VectorXd& theta, Eigen::VectorXd& r) {
    const CalibratedModel model = apply(start, names, theta);
    SteadyShearState s;
    for (int j = 0; j < m; ++j) {
      const auto& point = data[static_cast<std::size_t>(out.residual_point[j])];
      if (j == 0 || out.residual_point[j] != out.residual_point[j - 1]) {
        try {
          s = predict(model, point);
        } catch (const std::exception&) {
          s = SteadyShearState{};  // ν_c or e_r outside a closure's domain
        }
      }
      const Observable o = observables[static_cast<std::size_t>(out.residual_observable[j])];
      r[j] = s.ok ? (point.value[static_cast<int>(o)] - predicted(s, o)) / fit_error(point, o)
                  : unsupported_condition;
    }
  };
  statistics::LeastSquaresOptions options;
  options.max_evaluations = max_evaluations;
  // Jacobian step 1e-5 max(|θ|, 1e-3): the parameters are O(0.01-1) or factors around 1.
  options.step_floor = 1e-3;
  // A singular value below 1e-8 of the largest: a direction of θ the data do not constrain (e.g.
  // the correlation-length constant with L = d).
  options.rank_tolerance = 1e-8;
  options.failed_residual = unsupported_condition;
  const statistics::LeastSquaresFit lsq =
      statistics::minimise_residuals(residuals, m, out.initial, bounds, options);
  out.estimate = lsq.estimate;
  out.standard_error = lsq.standard_error;
  out.covariance = lsq.covariance;
  out.correlation = lsq.correlation;
  out.chi2 = lsq.chi2;
  out.chi2_initial = lsq.chi2_initial;
  out.residual_count = m;
  out.dof = lsq.dof;
  out.chi2_red = lsq.chi2_red;
  out.evaluations = lsq.evaluations;
  out.status = lsq.status;
  out.identifiable = lsq.identifiable;
  out.normalised_residuals = lsq.normalised_residuals;
  out.at_bound = lsq.parameter_at_bound;
  // Inside the domain: no estimate on a wall of its interval (where the data want the parameter
  // beyond it) and the model carries every condition at the estimate.
  out.inside_domain = !lsq.at_bound;
  const CalibratedModel at_estimate = apply(start, names, out.estimate);
  for (const auto& point : data) {
    try {
      out.inside_domain = out.inside_domain && predict(at_estimate, point).ok;
    } catch (const std::exception&) {
      out.inside_domain = false;
    }
  }
  return out;
}
}  // namespace

double mean_relative_error(const CalibratedModel& model, const std::vector<DataPoint>& data,
                           Observable observable) {
  double sum = 0;
  int count = 0;
  const int o = static_cast<int>(observable);
  for (const auto& point : data) {
    if (observable == imposed_observable(point.protocol) || !std::isfinite(point.value[o]))
      continue;
    const auto s = predict(model, point);
    if (!s.ok) return NAN;
    sum += std::abs(predicted(s, observable) - point.value[o]) / std::abs(point.value[o]);
    ++count;
  }
  return count ? sum / count : NAN;
}

Chi2 chi2_at(const CalibratedModel& model, const std::vector<DataPoint>& data,
             const std::vector<Observable>& observables, bool own_errors_only) {
  Chi2 out;
  for (const auto& point : data) {
    SteadyShearState s;
    bool predicted_once = false;
    for (const auto o : observables) {
      const int k = static_cast<int>(o);
      if (!tests(point, o) || (own_errors_only && !(point.error[k] > 0))) continue;
      if (!predicted_once) s = predict(model, point), predicted_once = true;
      if (!s.ok) return {NAN, out.residuals};
      const double sigma = own_errors_only ? point.error[k] : fit_error(point, o);
      const double r = (point.value[k] - predicted(s, o)) / sigma;
      out.chi2 += r * r;
      ++out.residuals;
    }
  }
  return out;
}

}  // namespace granflow::calibration
