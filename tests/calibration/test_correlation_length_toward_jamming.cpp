// The correlation length growing toward jamming (collisional.correlation_length: toward_jamming,
// continuum/model/correlation_length_toward_jamming.hpp): its closed form, and the steady state
// at constant volume it gives, by three paths: the closed form T/(dγ̇)² = (L/d) f2/f3,
// τ = ρ_p d f2 T^½ γ̇, p = ρ_p f1 T (no force chains, no liquid); the calibration's algebraic
// steady state; the time-stepped REV at constant volume.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/calibration/steady_shear_model.hpp"
#include "continuum/model/closures.hpp"
#include "continuum/rev/simple_shear.hpp"

namespace granflow::calibration {
namespace {

continuum::MultiRegimeSettings kinetic_with_growing_length() {
  continuum::MultiRegimeSettings s;
  s.collisional = true;
  auto& col = s.collisional_parameters;
  col.diameter = 1e-3, col.particle_density = 2500, col.restitution = 0.7;
  col.particle_friction = 0.5, col.jamming_fraction = 0.60;
  col.radial_distribution = model::RadialDistributionKind::torquato;
  col.correlation_length = model::CorrelationLengthKind::toward_jamming;
  col.correlation_length_constant = 0.02, col.correlation_length_onset = 0.49;
  col.correlation_length_exponent = 1.5;
  return s;
}

TEST(CorrelationLengthTowardJamming, ClosedFormOnsetAndDivergence) {
  const auto s = kinetic_with_growing_length();
  const auto& col = s.collisional_parameters;
  const auto L_over_d = [&](double nu) {
    return model::correlation_length(col, model::collisional_coefficients(col, nu), 20.0, 0.1) /
           col.diameter;
  };
  // L = d up to the onset, whatever γ̇ and T.
  EXPECT_EQ(L_over_d(0.30), 1.0);
  EXPECT_EQ(L_over_d(0.49), 1.0);
  // 1 + c (ν - ν_L)/(ν_c - ν)^n at ν = 0.55: 1 + 0.02 · 0.06 / 0.05^1.5 = 1.1073313...
  EXPECT_NEAR(L_over_d(0.55), 1.0 + 0.02 * 0.06 / std::pow(0.05, 1.5), 1e-15);
  // Grows without bound toward ν_c: (ν_c - ν)^-1.5 from ν_c - 1e-2 to ν_c - 1e-4 is 1000x.
  const double near = L_over_d(0.60 - 1e-4) - 1.0, far = L_over_d(0.60 - 1e-2) - 1.0;
  EXPECT_NEAR(near / far, 1000.0 * (0.11 - 1e-4) / (0.11 - 1e-2), 1e-6);
  double last = 1.0;
  for (double nu = 0.491; nu < 0.5999; nu += 0.001) {
    EXPECT_GT(L_over_d(nu), last) << nu;
    last = L_over_d(nu);
  }
  // The dissipation written finite at T = 0 is Γ = ρ_p f3 T^{3/2} / L.
  const auto k = model::collisional_coefficients(col, 0.58);
  const double T = 0.04;
  EXPECT_NEAR(model::collisional_dissipation_at_shear_rate(col, k, 20.0, T) /
                  model::collisional_dissipation(col, k, T, L_over_d(0.58) * col.diameter),
              1.0, 1e-14);
}

TEST(CorrelationLengthTowardJamming, ConstantVolumeSteadyStateIsTheClosedForm) {
  const auto s = kinetic_with_growing_length();
  const auto& col = s.collisional_parameters;
  const double rate = 20.0, d = col.diameter, rho = col.particle_density;
  double T_first = 0, T_last = 0;
  for (const double phi : {0.45, 0.52, 0.56, 0.58, 0.59}) {
    const auto st = steady_simple_shear_at_solid_fraction(s, {}, rate, phi);
    ASSERT_TRUE(st.ok) << st.why;
    const auto k = model::collisional_coefficients(col, phi);
    const double ratio = model::correlation_length(col, k, rate, 0.0) / d;
    const double T = ratio * k.f2 / k.f3 * d * d * rate * rate;
    // The steady balance is a quadratic in T^½ solved in closed form: rounding only.
    EXPECT_NEAR(st.granular_temperature / T, 1.0, 1e-13) << phi;
    EXPECT_NEAR(st.shear_stress / (rho * d * k.f2 * std::sqrt(T) * rate), 1.0, 1e-13) << phi;
    EXPECT_NEAR(st.normal_stress / (rho * k.f1 * T), 1.0, 1e-13) << phi;
    if (phi == 0.45) T_first = st.scaled_temperature;
    T_last = st.scaled_temperature;
  }
  // The point of the closure: T/(dγ̇)² rises toward jamming, where L = d keeps f2/f3 nearly flat;
  // the rise over L = d's is L/d at 0.59, 1 + 0.02 · 0.1 / 0.01^1.5 = 3 (L = d at 0.45).
  auto flat = s;
  flat.collisional_parameters.correlation_length = model::CorrelationLengthKind::diameter;
  const double flat_rise =
      steady_simple_shear_at_solid_fraction(flat, {}, rate, 0.59).scaled_temperature /
      steady_simple_shear_at_solid_fraction(flat, {}, rate, 0.45).scaled_temperature;
  EXPECT_LT(std::abs(flat_rise - 1.0), 0.2);
  EXPECT_NEAR(T_last / T_first / flat_rise, 3.0, 1e-12);
}

TEST(CorrelationLengthTowardJamming, ConstantVolumeStateIsTheTimeSteppedRevs) {
  const auto s = kinetic_with_growing_length();
  for (const double phi : {0.52, 0.58}) {
    const auto algebraic = steady_simple_shear_at_solid_fraction(s, {}, 20.0, phi);
    ASSERT_TRUE(algebraic.ok) << algebraic.why;
    rev::SimpleShearControl control;
    control.control = rev::ShearControl::constant_volume;
    control.shear_rate = 20.0;
    control.void_ratio = 1.0 / phi - 1.0;
    const auto r = rev::run_simple_shear(continuum::MultiRegimePoint(s), control);
    ASSERT_TRUE(r.steady.reached) << phi;
    EXPECT_GT(r.steps, 20);  // a real relaxation, not a trivial stop
    // the REV stops at 1e-10 relative change per unit strain
    EXPECT_NEAR(r.steady.friction / algebraic.friction, 1.0, 1e-8) << phi;
    EXPECT_NEAR(r.steady.granular_temperature / algebraic.granular_temperature, 1.0, 1e-8) << phi;
  }
}

}  // namespace
}  // namespace granflow::calibration
