#include "continuum/rev/simple_shear_mixed_control.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/run.hpp"

namespace granflow::rev {

Eigen::Matrix3d simple_shear_strain_rate(double shear_rate, double vertical_strain_rate) {
  // compression-positive strain rate of u_x = γ̇ y: ε̇ = -sym(∇u), ε̇_xy = -γ̇/2
  Eigen::Matrix3d rate = Eigen::Matrix3d::Zero();
  rate(0, 1) = rate(1, 0) = -0.5 * shear_rate;
  rate(1, 1) = vertical_strain_rate;
  return rate;
}

namespace {

// dσ_yy/dΔε_yy estimate for the first secant step: the constrained modulus of the skeleton,
// M = K + 4G/3 at p_FC (docs/model/force_chains.md §1), plus ν ∂p_COL/∂ν (dν = ν dε_v, central
// difference), plus 1 Pa so that it stays positive when both terms are off or vanish.
double vertical_stiffness(const continuum::MultiRegimePoint& point,
                          const continuum::PointState& start) {
  const auto& settings = point.settings();
  double stiffness = 1.0;
  if (const auto* fc = point.force_chain_model(); fc && !start.force_chains.fluidized) {
    const double p_fc = std::max(start.force_chains.stress.trace() / 3.0,
                                 settings.force_chain_parameters.pressure_floor);
    const auto& elastic = fc->elasticity();
    stiffness += elastic.bulk_modulus(p_fc) + 4.0 / 3.0 * elastic.shear_modulus(p_fc);
  }
  if (settings.collisional) {
    const auto& col = settings.collisional_parameters;
    const double nu = start.solid_fraction, T = start.granular_temperature;
    const double h = 1e-7 * nu;
    const double nu_hi = std::min(nu + h, model::maximum_solid_fraction(col) - 1e-13);
    const auto p_col = [&](double n) {
      return model::collisional_pressure(col, model::collisional_coefficients(col, n), T);
    };
    stiffness += nu * (p_col(nu_hi) - p_col(nu - h)) / (nu_hi - nu + h);
  }
  return stiffness;
}

}  // namespace

NormalStressStep constant_normal_stress_step(const continuum::MultiRegimePoint& point,
                                             const continuum::PointState& start, double shear_rate,
                                             double dt, double normal_stress, double guess,
                                             double relative_tolerance, long step,
                                             double drainage_resistance) {
  const auto& settings = point.settings();
  const double tolerance = relative_tolerance * std::abs(normal_stress);
  int evaluations = 0;
  const auto trial = [&](double x) {
    NormalStressStep out;
    out.state = start;
    out.strain_rate = simple_shear_strain_rate(shear_rate, x / dt);
    out.parts = point.advance(out.state, out.strain_rate, dt);
    out.vertical_strain = x;
    // σ_yy + u - p, u = r Δε_yy / Δt the excess pore pressure driving the drainage (r = 0: none)
    out.residual = out.parts.total_without_pore_pressure()(1, 1) + drainage_resistance * x / dt -
                   normal_stress;
    out.evaluations = ++evaluations;
    return out;
  };
  // Admissible Δε_yy: ν exp(Δε_yy) in [0.05, ν_lim) (the closures are singular at ν_c and the
  // mixture viscosity at its maximum packing; with neither term, half-way to e = 0, inside the
  // force-chain model's bound ln(1+e)).
  const double nu = start.solid_fraction;
  const double x_max = settings.collisional || settings.liquid
                           ? std::log(point.solid_fraction_limit() / nu)
                           : 0.5 * std::log(1.0 / nu);
  const double x_min = std::log(0.05 / nu);  // ν >= 0.05: a dilute gas

  NormalStressStep a = trial(std::clamp(guess, x_min, x_max));
  if (std::abs(a.residual) <= tolerance) return a;
  // Bracketing: R increases with Δε_yy. First step from the stiffness estimate, then secant
  // extrapolation overshooting by 1 % (a tight bracket), at least doubling and at most 16 × the
  // last move.
  double move = -a.residual / (vertical_stiffness(point, start) + drainage_resistance / dt);
  NormalStressStep b = trial(std::clamp(a.vertical_strain + move, x_min, x_max));
  for (int it = 0; it < 200 && (b.residual > 0) == (a.residual > 0); ++it) {
    if (std::abs(b.residual) <= tolerance) return b;
    const double dx = b.vertical_strain - a.vertical_strain;
    if (b.vertical_strain == x_min || b.vertical_strain == x_max || dx == 0.0)
      throw core::NumericalFailure(
          step, "REV point", "vertical_strain_increment", b.vertical_strain,
          fmt::format("no vertical strain increment in [{:.3g}, {:.3g}] gives σ_yy = {:g} Pa "
                      "(residual {:g} Pa at the bound): the point cannot carry the imposed "
                      "normal stress at this state",
                      x_min, x_max, normal_stress, b.residual));
    const double slope = (b.residual - a.residual) / dx;
    double next = slope > 0 ? -1.01 * b.residual / slope : 4.0 * dx;
    if (!(std::abs(next) >= std::abs(dx))) next = std::copysign(std::abs(dx), next);
    next = std::copysign(std::min(std::abs(next), 16.0 * std::abs(dx)), dx);
    if (std::abs(b.residual) < std::abs(a.residual)) a = std::move(b);  // keep the nearer end
    b = trial(std::clamp(a.vertical_strain + next, x_min, x_max));
    if (std::abs(b.residual) > std::abs(a.residual) && (b.residual > 0) == (a.residual > 0)) {
      // moved away from the root (R not monotone here): go the other way from the better end
      b = trial(std::clamp(a.vertical_strain - next, x_min, x_max));
    }
  }
  if (std::abs(b.residual) <= tolerance) return b;
  if ((b.residual > 0) == (a.residual > 0))
    throw core::NumericalFailure(step, "REV point", "vertical_strain_increment", b.vertical_strain,
                                 "the bracket search for σ_yy = p did not converge");

  // Illinois between lo (R < 0) and hi (R > 0): the retained end's residual is halved when the
  // same end is kept twice (Dowell & Jarratt 1971); bisection when the secant leaves the bracket.
  NormalStressStep lo = std::move(a), hi = std::move(b);
  if (lo.residual > 0) std::swap(lo, hi);
  double r_lo = lo.residual, r_hi = hi.residual;
  int side = 0;
  for (int it = 0; it < 200; ++it) {
    const double x_lo = lo.vertical_strain, x_hi = hi.vertical_strain;
    double x = x_hi - r_hi * (x_hi - x_lo) / (r_hi - r_lo);
    if (!(x > std::min(x_lo, x_hi) && x < std::max(x_lo, x_hi))) x = 0.5 * (x_lo + x_hi);
    if (x == x_lo || x == x_hi) break;  // the bracket cannot shrink (R discontinuous here)
    NormalStressStep t = trial(x);
    if (std::abs(t.residual) <= tolerance) return t;
    if (t.residual < 0) {
      lo = std::move(t);
      r_lo = lo.residual;
      if (side == -1) r_hi *= 0.5;
      side = -1;
    } else {
      hi = std::move(t);
      r_hi = hi.residual;
      if (side == 1) r_lo *= 0.5;
      side = 1;
    }
  }
  NormalStressStep& best = std::abs(lo.residual) <= std::abs(hi.residual) ? lo : hi;
  best.evaluations = evaluations;
  return best;
}

NormalStressStep advance_at_normal_stress(const continuum::MultiRegimePoint& point,
                                          const continuum::PointState& start, double shear_rate,
                                          double dt, double normal_stress, double guess,
                                          double relative_tolerance, long step, int max_splits,
                                          double drainage_resistance) {
  NormalStressStep whole =
      constant_normal_stress_step(point, start, shear_rate, dt, normal_stress, guess,
                                  relative_tolerance, step, drainage_resistance);
  if (std::abs(whole.residual) <= relative_tolerance * std::abs(normal_stress) || max_splits <= 0)
    return whole;
  const double half = 0.5 * dt;
  NormalStressStep first =
      advance_at_normal_stress(point, start, shear_rate, half, normal_stress, 0.5 * guess,
                               relative_tolerance, step, max_splits - 1, drainage_resistance);
  NormalStressStep second = advance_at_normal_stress(
      point, first.state, shear_rate, half, normal_stress, first.vertical_strain,
      relative_tolerance, step, max_splits - 1, drainage_resistance);
  // keep the better of the whole step and the split one
  if (std::abs(second.residual) >= std::abs(whole.residual)) {
    whole.evaluations += first.evaluations + second.evaluations;
    return whole;
  }
  second.vertical_strain += first.vertical_strain;
  second.strain_rate = simple_shear_strain_rate(shear_rate, second.vertical_strain / dt);
  second.evaluations += first.evaluations + whole.evaluations;
  return second;
}

}  // namespace granflow::rev
