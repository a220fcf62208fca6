#include "continuum/rev/simple_shear.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "continuum/model/closures.hpp"
#include "continuum/rev/simple_shear_mixed_control.hpp"
#include "core/interrupt.hpp"
#include "core/run.hpp"

namespace granflow::rev {

namespace {

// Share of a part in a total (0 when the total is 0).
double share(double part, double total) { return total != 0.0 && part != 0.0 ? part / total : 0.0; }

// χ = f1² / (1.5 ν² df1/dν): the volumetric work of a constant-pressure point per unit of its
// granular heat capacity (see run_simple_shear). df1/dν by a central difference.
double compaction_capacity(const continuum::MultiRegimePoint& point, double nu) {
  const auto& p = point.settings().collisional_parameters;
  const double h = 1e-7 * nu;
  const double nu_hi = std::min(nu + h, model::maximum_solid_fraction(p) - 1e-13);
  const double f1 = model::collisional_coefficients(p, nu).f1;
  const double slope = (model::collisional_coefficients(p, nu_hi).f1 -
                        model::collisional_coefficients(p, nu - h).f1) /
                       (nu_hi - nu + h);
  return f1 * f1 / (1.5 * nu * nu * slope);
}

}  // namespace

double solid_fraction_at_pressure(const continuum::MultiRegimePoint& point, double pressure,
                                  double granular_temperature, double shear_rate) {
  const auto& p = point.settings().collisional_parameters;
  double lo = 1e-9, hi = model::maximum_solid_fraction(p) - 1e-13;
  // p_COL(ν, T) + p_IC(ν, γ̇) (the second 0 unless collisional.inertial_contact > 0)
  const auto p_col = [&](double nu) {
    return model::collisional_pressure(p, model::collisional_coefficients(p, nu),
                                       granular_temperature) +
           point.inertial_contact_pressure(nu, shear_rate);
  };
  // No root in the bracket: the point cannot carry p (too cold even at jamming, or too hot
  // even when dilute). The caller reports it.
  if (!(p_col(hi) >= pressure) || !(p_col(lo) <= pressure)) return std::nan("");
  // Bisection to machine precision: near jamming p_COL ∝ (ν_c - ν)^(-3/2) is steep, so stop only
  // when the bracket can no longer shrink.
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (p_col(mid) < pressure ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

SimpleShearResult run_simple_shear(const continuum::MultiRegimePoint& point,
                                   const SimpleShearControl& control) {
  SimpleShearResult result;
  run_simple_shear(point, control, result);
  return result;
}

InertialNumberBound maximum_steady_inertial_number(const model::CollisionalParameters& p) {
  InertialNumberBound best{0, 0};
  const double nu_max = model::maximum_solid_fraction(p);
  for (int i = 1; i < 2000; ++i) {
    const double nu = nu_max * i / 2000.0;
    const auto k = model::collisional_coefficients(p, nu);
    const double I = 1.0 / std::sqrt(k.f1 * k.f2 / k.f3);
    if (I > best.inertial_number) best = {I, nu};
  }
  return best;
}

void run_simple_shear(const continuum::MultiRegimePoint& point, const SimpleShearControl& control,
                      SimpleShearResult& result, const std::function<void(double)>& progress) {
  const auto& settings = point.settings();
  const auto& col = settings.collisional_parameters;
  const double d = col.diameter, rho_p = col.particle_density;
  // γ̇ of the current step (the rate step switches it once the strain reaches its strain)
  double gamma_dot = control.shear_rate;
  Eigen::Matrix3d shear = simple_shear_strain_rate(gamma_dot);

  const bool force_chains = settings.force_chains;
  const bool constant_pressure = control.control == ShearControl::constant_pressure;
  // Constant pressure with force chains: mixed control of every step (ε̇_yy solved for σ_yy = p).
  const bool mixed_control = constant_pressure && force_chains;
  const bool drained = control.drainage_length > 0.0;
  if (drained && !(mixed_control && settings.liquid))
    throw std::invalid_argument(
        "a drained simple shear needs constant pressure, the force chains and the liquid");
  if (control.height_resistance > 0.0 && !(mixed_control && !drained))
    throw std::invalid_argument(
        "a damped height needs constant pressure and the force chains, and no drainage length");
  if (control.rate_step_strain < INFINITY && !(control.rate_step_shear_rate > 0.0))
    throw std::invalid_argument("the rate step's shear rate must be positive");
  double effective_pressure = control.effective_pressure;
  if (mixed_control) {
    // The skeleton takes what p_COL(ν0, T0) leaves of p: σ_yy = p from the first step on.
    const auto& col = settings.collisional_parameters;
    const double nu0 = 1.0 / (1.0 + control.void_ratio);
    const double p_col0 = settings.collisional ? model::collisional_pressure(
                                                     col, model::collisional_coefficients(col, nu0),
                                                     control.initial_temperature)
                                               : 0.0;
    const double p_ic0 = point.inertial_contact_pressure(nu0, gamma_dot);
    effective_pressure = std::max(control.normal_stress - p_col0 - p_ic0, 0.0);
  }
  continuum::PointState state =
      point.initial_state(control.void_ratio, effective_pressure, control.overconsolidation,
                          control.initial_temperature);
  if (constant_pressure && !mixed_control)
    state.solid_fraction = solid_fraction_at_pressure(point, control.normal_stress,
                                                      state.granular_temperature, gamma_dot);
  result = SimpleShearResult{};
  if (std::isnan(state.solid_fraction))
    throw core::NumericalFailure(0, "REV point", "solid_fraction", state.solid_fraction,
                                 "no solid fraction carries the imposed normal stress at the "
                                 "initial temperature; raise initial.granular_temperature");

  auto& series = result.series;
  double time = 0, strain = 0;
  result.min_time_step = INFINITY;
  int quiet_steps = 0;  // consecutive steps below the steady tolerance
  // With force chains: the state at the start of the current window of strain, and the number of
  // consecutive windows whose change per unit strain was below the tolerance.
  struct WindowStart {
    double strain, temperature, solid_fraction;
    Eigen::Matrix3d stress;
  } window_start{0.0, state.granular_temperature, state.solid_fraction, state.force_chains.stress};
  int quiet_windows = 0;
  double vertical_strain_guess = 0.0;  // Δε_yy of the previous step (mixed control)

  for (long step = 1; step <= control.max_steps; ++step) {
    const bool before_rate_step = strain < control.rate_step_strain;
    if (!before_rate_step && gamma_dot != control.rate_step_shear_rate) {
      gamma_dot = control.rate_step_shear_rate;
      shear = simple_shear_strain_rate(gamma_dot);
      quiet_steps = quiet_windows = 0;  // steady is judged after the step
      window_start = {strain, state.granular_temperature, state.solid_fraction,
                      state.force_chains.stress};
    }
    const Eigen::Matrix3d& rate = shear;
    // Constant pressure slaves ν to T through p_COL(ν, T) = ρ_p f1(ν) T = p, so dν/dT =
    // -f1/(T f1'). The volumetric work p tr(ε̇) = p (dν/dT) Ṫ / ν then moves to the left of
    // (3/2) ρ_p ν Ṫ = ... as an effective heat capacity (1 + χ) with χ = f1² / (1.5 ν² f1') > 0,
    // independent of T. Treating it as an explicit source instead is unstable (period-2
    // oscillation of T and ν with a collapsing step). Steady states are unchanged.
    // The mixed control needs no such factor: there ε̇_yy of the step itself (solved implicitly)
    // enters the T balance through tr(ε̇).
    const double heat_capacity_factor = constant_pressure && !mixed_control
                                            ? 1.0 + compaction_capacity(point, state.solid_fraction)
                                            : 1.0;
    // Time step: a fraction of the shear time 1/γ̇ and of the relaxation time of T^½.
    const auto start = point.evaluate(state, rate);
    continuum::RiccatiCoefficients k = start.temperature_equation;
    k.a /= heat_capacity_factor;
    k.b /= heat_capacity_factor;
    k.c /= heat_capacity_factor;
    const double s_star = settings.collisional ? continuum::steady_sqrt_temperature(k) : 0.0;
    const double relaxation = settings.collisional && std::isfinite(s_star)
                                  ? 1.0 / std::max(std::abs(k.c + 2 * k.b * s_star), 1e-300)
                                  : INFINITY;
    double dt = control.time_step_factor * std::min(1.0 / gamma_dot, relaxation);
    if (force_chains) dt = std::min(dt, control.strain_increment / gamma_dot);
    // The last step before a rate step ends on its strain (a sliver below 1e-6 joins it).
    if (before_rate_step && strain + (1.0 + 1e-6) * gamma_dot * dt >= control.rate_step_strain)
      dt = (control.rate_step_strain - strain) / gamma_dot;
    core::check_finite(dt, step, "REV point", "time_step", true);
    const double s_now = std::sqrt(std::max(state.granular_temperature, 0.0));
    result.max_explicit_ratio =
        std::max(result.max_explicit_ratio, dt / continuum::explicit_step_limit(k, s_now));

    const double T_old = state.granular_temperature, nu_old = state.solid_fraction;
    const Eigen::Matrix3d fc_old = state.force_chains.stress;
    continuum::StressParts parts;
    double vertical_strain_rate = 0.0;
    if (mixed_control) {
      // Drained: r = η0 H² / κ(ν) at the step's start (the lumped Darcy flow over H).
      const double resistance =
          drained ? settings.liquid_parameters.viscosity * control.drainage_length *
                        control.drainage_length /
                        model::permeability(settings.liquid_parameters, d, state.solid_fraction)
                  : control.height_resistance;
      NormalStressStep mixed = advance_at_normal_stress(
          point, state, gamma_dot, dt, control.normal_stress, vertical_strain_guess,
          control.normal_stress_tolerance, step, 8, resistance);
      state = mixed.state;
      parts = mixed.parts;
      vertical_strain_guess = mixed.vertical_strain;
      vertical_strain_rate = mixed.vertical_strain / dt;
      result.solver_evaluations += mixed.evaluations;
      result.max_normal_stress_residual = std::max(
          result.max_normal_stress_residual, std::abs(mixed.residual) / control.normal_stress);
    } else {
      parts = force_chains ? point.advance(state, rate, dt)
                           : point.update(state, rate, dt, heat_capacity_factor);
    }
    if (constant_pressure && !mixed_control) {
      state.solid_fraction = solid_fraction_at_pressure(point, control.normal_stress,
                                                        state.granular_temperature, gamma_dot);
      if (std::isnan(state.solid_fraction))
        throw core::NumericalFailure(
            step, "REV point", "solid_fraction", state.solid_fraction,
            fmt::format("no solid fraction in (0, ν_c) gives p_COL = {:g} Pa at T = {:g} m²/s²: "
                        "the collisional term alone cannot carry this normal stress at this "
                        "shear rate",
                        control.normal_stress, state.granular_temperature));
      parts = point.evaluate(state, rate);
    }
    time += dt;
    strain = before_rate_step && strain + gamma_dot * dt >= control.rate_step_strain
                 ? control.rate_step_strain  // exactly on the step (no rounding residue)
                 : strain + gamma_dot * dt;
    result.min_time_step = std::min(result.min_time_step, dt);
    result.max_time_step = std::max(result.max_time_step, dt);

    const double T = state.granular_temperature, nu = state.solid_fraction;
    core::check_finite(T, step, "REV point", "granular_temperature", true);
    core::check_finite(nu, step, "REV point", "solid_fraction", true);
    const double tau_col = -parts.collisional(0, 1), tau_liq = -parts.liquid(0, 1);
    const double tau_fc = 0.0 - parts.force_chain(0, 1);
    const double tau_ic = -parts.inertial_contact(0, 1);
    const double tau = tau_col + tau_liq + tau_fc + tau_ic;
    const double p_eff = parts.force_chain.trace() / 3.0;
    const Eigen::Matrix3d total = parts.total_without_pore_pressure();
    // constant pressure: the normal stress σ_yy (= p_COL without force chains, exactly)
    const double p = constant_pressure
                         ? total(1, 1)
                         : parts.collisional_pressure + parts.inertial_contact_pressure + p_eff;
    core::check_finite(tau, step, "REV point", "shear_stress");
    series.time.push_back(time);
    series.strain.push_back(strain);
    series.time_step.push_back(dt);
    series.granular_temperature.push_back(T);
    series.void_ratio.push_back(1.0 / nu - 1.0);
    series.solid_fraction.push_back(nu);
    series.pressure.push_back(p);
    series.shear_stress.push_back(tau);
    series.collisional_shear_stress.push_back(tau_col);
    series.liquid_shear_stress.push_back(tau_liq);
    series.friction.push_back(p > 0 ? tau / p : INFINITY);
    series.inertial_number.push_back(p > 0 ? gamma_dot * d / std::sqrt(p / rho_p) : INFINITY);
    series.force_chain_shear_stress.push_back(tau_fc);
    series.effective_pressure.push_back(p_eff);
    series.locus_size.push_back(state.force_chains.r_c);
    series.normal_stress.push_back(total(1, 1));
    series.force_chain_normal_stress.push_back(parts.force_chain(1, 1));
    series.collisional_pressure.push_back(parts.collisional_pressure);
    series.vertical_strain_rate.push_back(vertical_strain_rate);
    series.inertial_contact_pressure.push_back(parts.inertial_contact_pressure);
    result.steps = step;

    // Steady: relative change of T and ν per unit strain below the tolerance for 5 steps.
    const double dstrain = gamma_dot * dt;
    double change =
        std::max(std::abs(T - T_old) / std::max(T, 1e-300), std::abs(nu - nu_old) / nu) / dstrain;
    if (force_chains)  // the skeleton's stress must be stationary too (relative to |σ_FC| + 1 Pa)
      change = std::max(change, (state.force_chains.stress - fc_old).norm() /
                                    (state.force_chains.stress.norm() + 1.0) / dstrain);
    if (force_chains) {
      // σ_FC jitters by ~1e-9 (relative) per step (drift correction to FTOL), which per unit
      // strain is ~1e-6 at Δγ = 1e-3: measure the change over windows of 0.1 strain instead,
      // where the jitter weighs 100x less, and call the state steady after 3 quiet windows.
      constexpr double window = 0.1;
      if (strain - window_start.strain >= window) {
        const double span = strain - window_start.strain;
        const double windowed =
            std::max({std::abs(T - window_start.temperature) / std::max(T, 1e-300),
                      std::abs(nu - window_start.solid_fraction) / nu,
                      (state.force_chains.stress - window_start.stress).norm() /
                          (state.force_chains.stress.norm() + 1.0)}) /
            span;
        quiet_windows = windowed < control.steady_tolerance ? quiet_windows + 1 : 0;
        window_start = {strain, T, nu, state.force_chains.stress};
      }
      quiet_steps = quiet_windows >= 3 ? 5 : 0;
    } else {
      quiet_steps =
          (!settings.collisional || change < control.steady_tolerance) ? quiet_steps + 1 : 0;
    }
    if (progress && step % 1000 == 0) progress(strain);
    // SIGINT/SIGTERM: stop here with the state so far (steady.reached says whether it was).
    result.final_state = state;
    if (before_rate_step && std::isfinite(control.rate_step_strain))
      quiet_steps = 0;  // no steady state before the rate step
    if (quiet_steps >= 5 || strain >= control.max_strain || core::interrupted()) {
      auto& s = result.steady;
      s.reached = quiet_steps >= 5;
      s.strain = strain;
      s.solid_fraction = nu;
      s.void_ratio = 1.0 / nu - 1.0;
      s.granular_temperature = T;
      s.pressure = p;
      s.shear_stress = tau;
      s.collisional_shear_stress = tau_col;
      s.liquid_shear_stress = tau_liq;
      s.force_chain_shear_stress = tau_fc;
      s.effective_pressure = p_eff;
      s.locus_size = state.force_chains.r_c;
      s.friction = series.friction.back();
      s.inertial_number = series.inertial_number.back();
      s.viscous_number =
          settings.liquid && p > 0 ? settings.liquid_parameters.viscosity * gamma_dot / p : 0.0;
      s.normal_stress = total(1, 1);
      s.force_chain_normal_stress = parts.force_chain(1, 1);
      s.collisional_normal_stress = parts.collisional(1, 1);
      s.liquid_normal_stress = parts.liquid(1, 1);
      s.share_tau_force_chains = share(tau_fc, tau);
      s.share_tau_collisional = share(tau_col, tau);
      s.share_tau_liquid = share(tau_liq, tau);
      s.share_normal_force_chains = share(s.force_chain_normal_stress, s.normal_stress);
      s.share_normal_collisional = share(s.collisional_normal_stress, s.normal_stress);
      s.share_normal_liquid = share(s.liquid_normal_stress, s.normal_stress);
      s.force_chain_stress = parts.force_chain;
      s.fluidized = force_chains && state.force_chains.fluidized;
      break;
    }
  }
}

}  // namespace granflow::rev
