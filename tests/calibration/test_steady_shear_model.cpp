// The calibration's algebraic steady simple shear against (1) the closed form of
// docs/model/closures.md and (2) the time-stepped REV (rev::run_simple_shear, constant_pressure):
// two independent paths to the same steady state.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/calibration/steady_shear_model.hpp"
#include "continuum/rev/simple_shear.hpp"

namespace granflow::calibration {
namespace {

continuum::MultiRegimeSettings dry_settings() {
  continuum::MultiRegimeSettings s;
  s.collisional = true;
  auto& col = s.collisional_parameters;
  col.diameter = 1e-3;
  col.particle_density = 2500;
  col.restitution = 0.7;
  col.particle_friction = 0.5;
  col.jamming_fraction = 0.587;
  return s;
}

TEST(CalibrationSteadyShear, DryClosedForm) {
  // L = d, no liquid: T = (f2/f3) d² γ̇², μ = sqrt(f2 f3)/f1 and p_COL(ν, T) = p
  // (docs/model/closures.md).
  const auto s = dry_settings();
  const double gamma_dot = 20, p = 100;
  const auto st = steady_simple_shear(s, {}, gamma_dot, p);
  ASSERT_TRUE(st.ok) << st.why;
  const auto& col = s.collisional_parameters;
  const auto k = model::collisional_coefficients(col, st.solid_fraction);
  const double d = col.diameter;
  // 1e-12: both sides are the same closed expressions evaluated at a ν solved to rounding.
  EXPECT_NEAR(st.granular_temperature / (k.f2 / k.f3 * d * d * gamma_dot * gamma_dot), 1.0, 1e-12);
  EXPECT_NEAR(st.friction / (std::sqrt(k.f2 * k.f3) / k.f1), 1.0, 1e-12);
  // p_COL is steep near ν_c (∝ (ν_c - ν)^-1.5 · ...): ν to rounding gives p to ~1e-10.
  EXPECT_NEAR(col.particle_density * k.f1 * st.granular_temperature / p, 1.0, 1e-9);
  EXPECT_NEAR(st.inertial_number, 1.0 / std::sqrt(k.f1 * k.f2 / k.f3), 1e-12);
}

void expect_matches_rev(const continuum::MultiRegimeSettings& s, double gamma_dot, double p) {
  const auto st = steady_simple_shear(s, {}, gamma_dot, p);
  ASSERT_TRUE(st.ok) << st.why;
  rev::SimpleShearControl control;
  control.control = rev::ShearControl::constant_pressure;
  control.shear_rate = gamma_dot;
  control.normal_stress = p;
  control.steady_tolerance = 1e-12;
  const auto rev = rev::run_simple_shear(continuum::MultiRegimePoint(s), control);
  ASSERT_TRUE(rev.steady.reached);
  EXPECT_GT(rev.steps, 20);  // a real relaxation from T(0) = 1e-6 m²/s², not a trivial stop
  // The REV stops when T and ν change by < 1e-12 per unit strain; with relaxation strains of
  // O(1-100) its distance to the fixed point is < 1e-9 relative: 1e-7 leaves margin.
  EXPECT_NEAR(rev.steady.solid_fraction / st.solid_fraction, 1.0, 1e-7);
  EXPECT_NEAR(rev.steady.granular_temperature / st.granular_temperature, 1.0, 1e-7);
  EXPECT_NEAR(rev.steady.friction / st.friction, 1.0, 1e-7);
  EXPECT_NEAR(rev.steady.inertial_number / st.inertial_number, 1.0, 1e-7);
}

TEST(CalibrationSteadyShear, MatchesTimeSteppedRevDry) {
  expect_matches_rev(dry_settings(), 20, 100);  // I ≈ 0.1
  expect_matches_rev(dry_settings(), 2, 100);   // I ≈ 0.01, dense
}

TEST(CalibrationSteadyShear, MatchesTimeSteppedRevJenkins) {
  auto s = dry_settings();
  s.collisional_parameters.correlation_length = model::CorrelationLengthKind::jenkins;
  // Nearly elastic grains (ε = e_r = 0.95 with μ_p = 0) and c_L = 2 at I ≈ 0.01: L > d, so the
  // cubic branch of the balance is the one solved.
  s.collisional_parameters.restitution = 0.95;
  s.collisional_parameters.particle_friction = 0.0;
  s.collisional_parameters.correlation_length_constant = 2.0;
  const double gamma_dot = 2, p = 100;
  const auto& col = s.collisional_parameters;
  const auto st = steady_simple_shear(s, {}, gamma_dot, p);
  ASSERT_TRUE(st.ok);
  const auto k = model::collisional_coefficients(col, st.solid_fraction);
  EXPECT_GT(model::correlation_length(col, k, gamma_dot, st.granular_temperature),
            1.01 * col.diameter);  // the branch under test
  expect_matches_rev(s, gamma_dot, p);
  expect_matches_rev(s, 40, 100);
}

TEST(CalibrationSteadyShear, MatchesTimeSteppedRevWetWithLambda) {
  auto s = dry_settings();
  s.collisional_parameters.jamming_fraction = 0.6;
  s.liquid = true;
  s.fluctuation_dissipation = true;
  s.liquid_parameters.viscosity = 1e-2;
  s.liquid_parameters.maximum_packing = 0.62;
  expect_matches_rev(s, 20, 100);
  expect_matches_rev(s, 200, 100);
}

TEST(CalibrationSteadyShear, LambdaFactorCoolsAndUnreachablePressureIsReported) {
  auto s = dry_settings();
  s.collisional_parameters.jamming_fraction = 0.6;
  s.liquid = true;
  s.fluctuation_dissipation = true;
  s.liquid_parameters.viscosity = 1e-2;
  s.liquid_parameters.maximum_packing = 0.62;
  const auto base = steady_simple_shear(s, {}, 20, 100);
  const auto more = steady_simple_shear(s, {2.0}, 20, 100);
  ASSERT_TRUE(base.ok && more.ok);
  // More liquid dissipation Λ: lower T at fixed ν; p fixed -> denser, and colder.
  EXPECT_LT(more.scaled_temperature, base.scaled_temperature);
  EXPECT_GT(more.solid_fraction, base.solid_fraction);
  // Dry, L = d: a steady state needs I below the kinetic-theory bound.
  const auto bound = rev::maximum_steady_inertial_number(dry_settings().collisional_parameters);
  const double gamma_dot = 2.0 * bound.inertial_number * std::sqrt(100.0 / 2500.0) / 1e-3;
  EXPECT_FALSE(steady_simple_shear(dry_settings(), {}, gamma_dot, 100).ok);
}

}  // namespace
}  // namespace granflow::calibration
