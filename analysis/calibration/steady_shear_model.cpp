#include "analysis/calibration/steady_shear_model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "continuum/model/correlation_length_jenkins.hpp"
#include "continuum/model/correlation_length_toward_jamming.hpp"
#include "continuum/model/force_chains/critical_state_lade_duncan.hpp"
#include "continuum/model/force_chains/force_chain_model.hpp"

namespace granflow::calibration {

namespace {

// s solving d f2 γ̇² = f3 s³ / (d max(s, a)) + λ s (see the header).
double solve_sqrt_temperature(double d, double f2, double f3, double lambda, double speed,
                              double shear_rate) {
  const double production = d * f2 * shear_rate * shear_rate;  // C
  // s ≥ a: (f3/d) s² + λ s - C = 0, stable root 2C / (λ + sqrt(λ² + 4 (f3/d) C)).
  const double quad = f3 / d;
  const double s_quadratic =
      2.0 * production / (lambda + std::sqrt(lambda * lambda + 4.0 * quad * production));
  if (s_quadratic >= speed) return s_quadratic;
  // s < a: g(s) = (f3/(d a)) s³ + λ s - C, increasing and convex for s > 0; Newton from s = a
  // (g(a) > 0 here) decreases monotonically to the root.
  const double cubic = f3 / (d * speed);
  double s = speed;
  for (int i = 0; i < 200; ++i) {
    const double g = cubic * s * s * s + lambda * s - production;
    const double slope = 3.0 * cubic * s * s + lambda;
    const double next = s - g / slope;
    if (!(next < s) || next <= 0.0) break;  // converged to rounding (or the root is at 0)
    s = next;
  }
  return s;
}

// s solving d f2 γ̇² + W/s = f3 s³/(d max(s, a)) + λ s with W > 0: h(s) = right - left rises
// strictly with s (each term of the right side rises, -W/s rises), h(0+) = -∞. Bracket from the
// root without contact work (where h = -W/s < 0), then Newton kept inside the bracket.
double solve_sqrt_temperature_with_work(double d, double f2, double f3, double lambda, double speed,
                                        double shear_rate, double work) {
  const double production = d * f2 * shear_rate * shear_rate;
  const auto h = [&](double s, double& slope) {
    const double L_term = s >= speed ? f3 * s * s / d : f3 * s * s * s / (d * speed);
    const double L_slope = s >= speed ? 2.0 * f3 * s / d : 3.0 * f3 * s * s / (d * speed);
    slope = L_slope + lambda + work / (s * s);
    return L_term + lambda * s - production - work / s;
  };
  double lo = solve_sqrt_temperature(d, f2, f3, lambda, speed, shear_rate);
  if (!(lo > 0)) lo = 1e-300;
  double hi = std::max(2.0 * lo, 1e-300), slope = 0;
  for (int i = 0; i < 2000 && h(hi, slope) < 0; ++i) hi *= 2.0;
  double s = hi;
  for (int i = 0; i < 200; ++i) {
    const double value = h(s, slope);
    if (value == 0.0) return s;
    (value < 0 ? lo : hi) = s;
    double next = s - value / slope;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - s) <= 4e-16 * s || hi - lo <= 4e-16 * hi) return next;
    s = next;
  }
  return s;
}

}  // namespace

double critical_state_pressure(const model::force_chains::ForceChainParameters& p,
                               double solid_fraction) {
  const double e = 1.0 / solid_fraction - 1.0;
  if (!(e < p.e_Gamma)) return 0.0;
  // e_cs = e_Γ - λ_c (p/p_ref)^ξ_c inverted (critical_state_lade_duncan.hpp)
  return p.atmospheric_pressure * std::pow((p.e_Gamma - e) / p.lambda_c, 1.0 / p.xi_c);
}

double critical_state_friction(const model::force_chains::ForceChainParameters& p) {
  // Plane strain, isochoric plastic flow coaxial with D: σ_zz = p, J3 = 0 (cos 3θ = 0), so
  // τ/σ_yy = q/(√3 p) = M(θ = 0)/√3 on the Lade-Duncan locus.
  return model::force_chains::CriticalStateLadeDuncan(p).stress_ratio(0.0) / std::sqrt(3.0);
}

std::string in_parallel_caveat(const continuum::MultiRegimeSettings& settings) {
  if (!settings.force_chains) return "";
  const double nu_line = 1.0 / (1.0 + settings.force_chain_parameters.e_Gamma);
  const double nu_max = model::maximum_solid_fraction(settings.collisional_parameters);
  if (nu_line < nu_max) return "";
  return fmt::format(
      "the critical state line starts at φ = 1/(1+e_Γ) = {:.4f}, at or beyond the largest solid "
      "fraction of the collisional closures ({:.4f}): the force chains never carry a "
      "rate-independent load (their friction still shears collisional.inertial_contact's stress, "
      "if "
      "set); if that is not meant, set force_chains.e_Gamma for this material (e.g. include "
      "cases/rev/materials/dem_spheres_force_chains.yaml)",
      nu_line, nu_max);
}

SkeletonShearState skeleton_simple_shear_state(
    const model::force_chains::ForceChainParameters& parameters) {
  thread_local model::force_chains::ForceChainParameters cached_parameters{};
  thread_local SkeletonShearState cached{};
  thread_local bool has_cache = false;
  // ForceChainParameters is doubles then two ints: no padding, so bytes compare values.
  if (has_cache && std::memcmp(&cached_parameters, &parameters, sizeof parameters) == 0)
    return cached;
  using model::force_chains::Tensor;
  const model::force_chains::ForceChainModel model(parameters);
  // Start isotropic on the line at p_ref; constant volume keeps e = e_cs(p_ref) and the skeleton
  // relaxes to the critical state with the same mean stress.
  const double p0 = parameters.atmospheric_pressure;
  const double e0 = model.critical_state().critical_void_ratio(p0);
  auto state = model.isotropic_state(p0, e0, 1.0);
  Tensor increment = Tensor::Zero();
  constexpr double dgamma = 2e-3;                     // shear strain per update
  increment(0, 1) = increment(1, 0) = -0.5 * dgamma;  // compression-positive ε_xy of u_x = γ̇ y
  SkeletonShearState out;
  double last_ratio = 0, last_pressure = 0;
  int quiet = 0;
  for (int i = 1; i <= 50000 && quiet < 20; ++i) {
    model.update(state, increment, 1.0, 0.0);
    const Tensor& sigma = state.stress;
    const double ratio = -sigma(0, 1) / sigma(1, 1), pressure = sigma.trace() / 3.0 / sigma(1, 1);
    const double change =
        std::max(std::abs(ratio - last_ratio), std::abs(pressure - last_pressure)) / dgamma;
    quiet = change < 1e-10 ? quiet + 1 : 0;
    last_ratio = ratio, last_pressure = pressure;
    out.strain = i * dgamma;
  }
  const Tensor& sigma = state.stress;
  out.friction = last_ratio;
  out.pressure_ratio = last_pressure;
  out.cos3theta = model::force_chains::lode_cos3theta(model::force_chains::deviator(sigma));
  cached_parameters = parameters, cached = out, has_cache = true;
  return out;
}

double steady_sqrt_temperature_at(const continuum::MultiRegimeSettings& settings,
                                  const ModelFactors& factors, double solid_fraction,
                                  double shear_rate, double contact_work) {
  const auto& p = settings.collisional_parameters;
  const auto c = model::collisional_coefficients(p, solid_fraction);
  double lambda = 0.0;
  if (settings.fluctuation_dissipation)  // Λ(T = 1) / ρ_p, Λ ∝ T (Koch & Sangani 1999)
    lambda = factors.fluctuation_dissipation *
             model::liquid_fluctuation_dissipation(settings.liquid_parameters, p.diameter,
                                                   solid_fraction, c.g0, 1.0) /
             p.particle_density;
  // Γ/ρ_p = f3 s³ / L: Jenkins' L = d max(s, a)/s enters through the speed a; a length
  // independent of T (L = d ℓ(ν)) through f3/ℓ.
  double speed = 0.0, f3_over_ratio = c.f3;
  switch (p.correlation_length) {
    case model::CorrelationLengthKind::jenkins:
      speed = model::jenkins_correlation_speed(p.correlation_length_constant, c.J, c.epsilon,
                                               p.diameter, shear_rate);
      break;
    case model::CorrelationLengthKind::toward_jamming:
      f3_over_ratio = c.f3 / model::correlation_length_ratio_toward_jamming(
                                 p.correlation_length_constant, p.correlation_length_onset,
                                 p.correlation_length_exponent, p.jamming_fraction, solid_fraction);
      break;
    case model::CorrelationLengthKind::diameter:
      break;
  }
  if (contact_work > 0)
    return solve_sqrt_temperature_with_work(p.diameter, c.f2, f3_over_ratio, lambda, speed,
                                            shear_rate, contact_work);
  return solve_sqrt_temperature(p.diameter, c.f2, f3_over_ratio, lambda, speed, shear_rate);
}

namespace {

// The in-parallel state at a given shear rate, with the quantities that depend on the flow's
// normal stress p (the friction rise through X, the viscous dilatancy through J, and the contact
// work through μ_FC) evaluated at `p_flow`: the imposed p at constant pressure, the unknown p
// at constant volume.
struct InParallel {
  const continuum::MultiRegimeSettings& settings;
  const ModelFactors& factors;
  double shear_rate;
  bool chains = false;
  double rho_p = 0, d = 0, nu_max = 0;
  model::force_chains::ForceChainParameters line{};
  double r_p = 1, mu_fc = 0, production_per_pressure = 0;

  InParallel(const continuum::MultiRegimeSettings& s, const ModelFactors& f, double rate,
             double p_flow)
      : settings(s), factors(f), shear_rate(rate) {
    if (!settings.collisional)
      throw std::invalid_argument(
          "steady simple shear: needs collisional.enabled (the collisions carry T and, without "
          "force chains, the whole normal stress)");
    chains = settings.force_chains;
    const auto& fc = settings.force_chain_parameters;
    if (chains && !(fc.lambda_c > 0))
      throw std::invalid_argument(
          "steady in-parallel simple shear: needs force_chains.lambda_c > 0 (a critical state "
          "line with a slope, so that p_FC(e) is a function)");
    const auto& p = settings.collisional_parameters;
    rho_p = p.particle_density, d = p.diameter;
    nu_max = model::maximum_solid_fraction(p);
    // μ_FC: the critical state's, plus the optional rise with the mixed number
    // X = sqrt(I² + J/α) of p_flow (X = I dry).
    const double imposed_I = shear_rate * d / std::sqrt(p_flow / rho_p);
    const double imposed_J =
        settings.liquid ? settings.liquid_parameters.viscosity * shear_rate / p_flow : 0.0;
    const double mixed_number =
        std::sqrt(imposed_I * imposed_I + imposed_J / factors.mixed_number_alpha);
    // The critical state line, moved looser by the optional viscous dilatancy e_Γ + a_J √J.
    line = fc;
    line.e_Gamma += factors.viscous_dilatancy * std::sqrt(imposed_J);
    // The skeleton's stress state: τ_FC = μ_FC σ_yy,FC, p_FC = r_p σ_yy,FC (p_FC on the line).
    SkeletonShearState skeleton_state;
    if (chains) {
      if (factors.skeleton_from_model)
        skeleton_state = skeleton_simple_shear_state(fc);
      else
        skeleton_state.friction = critical_state_friction(fc);
    }
    r_p = skeleton_state.pressure_ratio;
    mu_fc = chains ? skeleton_state.friction +
                         factors.friction_rise / (1.0 + factors.friction_rise_I0 / mixed_number)
                   : 0.0;
    production_per_pressure =
        chains ? factors.contact_production * mu_fc * shear_rate / rho_p : 0.0;
  }
  // σ_yy,FC(ν) from the line's mean stress
  double skeleton(double nu) const {
    return chains ? critical_state_pressure(line, nu) / r_p : 0.0;
  }
  double sqrt_T(double nu, double p_fc) const {
    return steady_sqrt_temperature_at(settings, factors, nu, shear_rate,
                                      production_per_pressure * p_fc);
  }
  // σ_yy,IC(ν) = [ρ_p (a_c d γ̇)² + b_v η0 γ̇] (ν_c - ν)^-m (continuum::contact_pressure)
  double inertial_contact(double nu) const {
    return continuum::contact_pressure(settings, nu, shear_rate);
  }
  // σ_yy,FC(ν) + σ_yy,IC(ν) + p_COL(ν, s(ν)): the normal stress the state at ν carries
  double pressure(double nu) const {
    const double p_fc = skeleton(nu);
    const double s = sqrt_T(nu, p_fc);
    return p_fc + inertial_contact(nu) +
           rho_p * model::collisional_coefficients(settings.collisional_parameters, nu).f1 * s * s;
  }
  // The state at ν (its normal stress is pressure(ν)).
  SteadyShearState state(double nu) const {
    SteadyShearState out;
    const auto& p = settings.collisional_parameters;
    const double p_fc = skeleton(nu);
    const double s = sqrt_T(nu, p_fc);
    const auto c = model::collisional_coefficients(p, nu);
    const double p_col = rho_p * c.f1 * s * s;
    const double p_ic = inertial_contact(nu);
    const double p_total = p_fc + p_ic + p_col;
    out.force_chain_normal_stress = p_fc;
    out.collisional_pressure = p_col;
    out.inertial_contact_normal_stress = p_ic;
    // τ_IC = μ_IC σ_yy,IC: collisional.inertial_contact_friction if set, else μ_FC (without
    // force chains the critical state's M(θ=0)/√3)
    const double mu_contacts = settings.inertial_contact_friction > 0
                                   ? settings.inertial_contact_friction
                               : chains ? mu_fc
                                        : critical_state_friction(settings.force_chain_parameters);
    out.force_chain_shear_stress = mu_fc * p_fc + mu_contacts * p_ic;
    out.collisional_shear_stress = rho_p * d * c.f2 * s * shear_rate;  // τ_COL = η_COL γ̇
    if (settings.liquid) {
      if (nu >= model::maximum_mixture_solid_fraction(settings.liquid_parameters)) {
        out.why = "steady solid fraction above the maximum packing of η(ν)";
        return out;
      }
      out.liquid_shear_stress =
          model::mixture_viscosity(settings.liquid_parameters, nu) * shear_rate;  // τ_L
      out.viscous_number = settings.liquid_parameters.viscosity * shear_rate / p_total;
    }
    const double tau =
        out.force_chain_shear_stress + out.collisional_shear_stress + out.liquid_shear_stress;
    out.ok = std::isfinite(tau) && std::isfinite(s) && p_total > 0;
    out.solid_fraction = nu;
    out.granular_temperature = s * s;
    out.scaled_temperature = s * s / (d * d * shear_rate * shear_rate);
    out.shear_stress = tau;
    out.normal_stress = p_total;
    out.scaled_pressure = p_total / (rho_p * d * d * shear_rate * shear_rate);
    out.friction = tau / p_total;
    out.inertial_number = shear_rate * d / std::sqrt(p_total / rho_p);
    if (!out.ok) out.why = "non-finite steady state";
    return out;
  }
};

}  // namespace

SteadyShearState steady_simple_shear(const continuum::MultiRegimeSettings& settings,
                                     const ModelFactors& factors, double shear_rate,
                                     double normal_stress) {
  const InParallel model(settings, factors, shear_rate, normal_stress);
  const double nu_max = model.nu_max;
  const auto pressure = [&](double nu) { return model.pressure(nu); };
  SteadyShearState out;
  // Dense branch: from the minimum of p(ν) (coarse scan) up to ν_max, where p_COL -> ∞.
  constexpr int scan = 100;
  double nu_lo = nu_max / scan, p_lo = pressure(nu_lo);
  for (int i = 2; i < scan; ++i) {
    const double nu = nu_max * i / scan;
    const double pv = pressure(nu);
    if (pv < p_lo) nu_lo = nu, p_lo = pv;
  }
  nu_lo = std::max(nu_lo - nu_max / scan, nu_max / scan);  // the minimum lies within one cell
  double nu_hi = nu_max * (1.0 - 1e-12);
  if (!(pressure(nu_lo) <= normal_stress)) {
    out.why =
        "normal stress below the smallest steady p_COL (inertial number above the largest "
        "steady I of kinetic theory)";
    return out;
  }
  if (!(pressure(nu_hi) >= normal_stress)) {
    out.why = "normal stress above p_COL at the jamming fraction (quasi-static)";
    return out;
  }
  for (int i = 0; i < 200; ++i) {  // bisection to the last representable bracket
    const double mid = 0.5 * (nu_lo + nu_hi);
    if (mid <= nu_lo || mid >= nu_hi) break;
    (pressure(mid) < normal_stress ? nu_lo : nu_hi) = mid;
  }
  return model.state(0.5 * (nu_lo + nu_hi));
}

SteadyShearState steady_simple_shear_at_solid_fraction(
    const continuum::MultiRegimeSettings& settings, const ModelFactors& factors, double shear_rate,
    double solid_fraction) {
  SteadyShearState out;
  {
    const InParallel probe(settings, factors, shear_rate, 1.0);  // checks the settings
    if (!(solid_fraction > 0 && solid_fraction < probe.nu_max)) {
      out.why = "solid fraction outside (0, ν_max): no steady state carries it";
      return out;
    }
  }
  // The normal stress the state at ν carries, with the p-dependent terms evaluated at p.
  const auto carried = [&](double p) {
    return InParallel(settings, factors, shear_rate, p).pressure(solid_fraction);
  };
  const bool depends_on_p =
      settings.force_chains &&
      (factors.friction_rise != 0 || (settings.liquid && factors.viscous_dilatancy != 0));
  double p = carried(1.0);  // exact when nothing depends on p
  if (depends_on_p) {
    // G(x) = ln P(e^x) - x, P = carried: P does not rise with p (the friction rise and the
    // dilatancy fall with X and J, which fall with p), so G falls strictly: one root. Bracket it
    // by doubling the step in x from ln P(1), then bisection with a secant step inside the
    // bracket (regula falsi, Illinois variant) to |Δx| ≤ 1e-13.
    const auto G = [&](double x) { return std::log(carried(std::exp(x))) - x; };
    double x = std::log(p), g = G(x);
    double step = g > 0 ? 1.0 : -1.0;
    double x_other = x + step, g_other = G(x_other);
    for (int i = 0; i < 60 && (g > 0) == (g_other > 0) && std::isfinite(g_other); ++i) {
      x = x_other, g = g_other;
      step *= 2.0;
      x_other = x + step, g_other = G(x_other);
    }
    if (!std::isfinite(g) || !std::isfinite(g_other) || (g > 0) == (g_other > 0)) {
      out.why = "no normal stress carries the solid fraction (no root of the shared stress)";
      return out;
    }
    double a = x, ga = g, b = x_other, gb = g_other;
    int side = 0;
    for (int i = 0; i < 200 && std::abs(b - a) > 1e-13; ++i) {
      double c = (a * gb - b * ga) / (gb - ga);
      if (!(c > std::min(a, b) && c < std::max(a, b))) c = 0.5 * (a + b);
      const double gc = G(c);
      if (gc == 0) {
        a = b = c;
        break;
      }
      if ((gc > 0) == (ga > 0)) {
        a = c, ga = gc;
        if (side == -1) gb *= 0.5;
        side = -1;
      } else {
        b = c, gb = gc;
        if (side == 1) ga *= 0.5;
        side = 1;
      }
    }
    p = std::exp(0.5 * (a + b));
  }
  if (!(p > 0) || !std::isfinite(p)) {
    out.why = "non-finite normal stress at the solid fraction";
    return out;
  }
  return InParallel(settings, factors, shear_rate, p).state(solid_fraction);
}

}  // namespace granflow::calibration
