// The contacts' dense inertial stress (collisional.inertial_contact a_c, _power m;
// MultiRegimeSettings::inertial_contact): σ_yy,IC = ρ_p (a_c d γ̇)² (ν_c - ν)^-m, sheared at μ_FC
// in the steady model and at the critical state friction M(θ=0)/√3 in the material point.
// Checked against its closed form at constant volume (it adds to the normal and shear stress and
// leaves T alone), the constant-volume state against the constant-pressure state at the pressure
// it finds (two solvers: bisection in ν at given p, and the explicit state at given ν), and the
// steady model against the time-stepped REV (MultiRegimePoint's σ_IC) at constant volume and at
// constant pressure, with and without force chains.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/calibration/steady_shear_model.hpp"
#include "continuum/model/closures.hpp"
#include "continuum/rev/simple_shear.hpp"
#include "continuum/rev/simple_shear_mixed_control.hpp"

namespace granflow::calibration {
namespace {

continuum::MultiRegimeSettings spheres(bool chains) {
  continuum::MultiRegimeSettings s;
  s.collisional = true;
  s.force_chains = chains;
  auto& col = s.collisional_parameters;
  col.diameter = 1e-3, col.particle_density = 2500, col.restitution = 0.7;
  col.particle_friction = 0.5, col.jamming_fraction = 0.5915;
  col.radial_distribution = model::RadialDistributionKind::torquato;
  auto& fc = s.force_chain_parameters;
  fc.M_c = 0.75, fc.e_Gamma = 1.07, fc.lambda_c = 0.43, fc.xi_c = 1, fc.atmospheric_pressure = 100;
  return s;
}

TEST(InertialContact, ConstantVolumeClosedForm) {
  const auto s = spheres(false);
  const double rate = 20, rho = 2500, d = 1e-3, nu_c = 0.5915;
  const double mu_cs = critical_state_friction(s.force_chain_parameters);
  for (const double m : {2.0, 3.3})
    for (const double phi : {0.50, 0.56, 0.585}) {
      auto with = s;
      with.inertial_contact = 0.12, with.inertial_contact_power = m;
      const auto bare = steady_simple_shear_at_solid_fraction(s, {}, rate, phi);
      const auto st = steady_simple_shear_at_solid_fraction(with, {}, rate, phi);
      ASSERT_TRUE(bare.ok && st.ok) << st.why;
      const double p_ic = rho * std::pow(0.12 * d * rate, 2) * std::pow(nu_c - phi, -m);
      // Same closed expressions on both sides: rounding only.
      EXPECT_NEAR(st.inertial_contact_normal_stress / p_ic, 1.0, 1e-14) << phi;
      EXPECT_NEAR(st.normal_stress / (bare.normal_stress + p_ic), 1.0, 1e-14) << phi;
      EXPECT_NEAR(st.shear_stress / (bare.shear_stress + mu_cs * p_ic), 1.0, 1e-14) << phi;
      EXPECT_EQ(st.granular_temperature, bare.granular_temperature) << phi;  // no production
    }
  // It scales as γ̇² like the collisions': the scaled pressure does not depend on the rate.
  auto with = s;
  with.inertial_contact = 0.12;
  const auto slow = steady_simple_shear_at_solid_fraction(with, {}, 2.0, 0.56);
  const auto fast = steady_simple_shear_at_solid_fraction(with, {}, 20.0, 0.56);
  EXPECT_NEAR(slow.scaled_pressure / fast.scaled_pressure, 1.0, 1e-12);
}

TEST(InertialContact, ConstantVolumeStateIsTheConstantPressureStateAtItsPressure) {
  ModelFactors f;
  f.friction_rise = 1.2, f.friction_rise_I0 = 2;
  for (const bool chains : {false, true}) {
    auto s = spheres(chains);
    s.inertial_contact = 0.12;
    for (const double rate : {2.0, 20.0}) {
      const auto cp = steady_simple_shear(s, f, rate, 100.0);
      ASSERT_TRUE(cp.ok) << cp.why;
      EXPECT_GT(cp.inertial_contact_normal_stress, 0.0);
      const auto cv = steady_simple_shear_at_solid_fraction(s, f, rate, cp.solid_fraction);
      ASSERT_TRUE(cv.ok) << cv.why;
      // ν bisected to rounding, dlnp/dν ≲ 1e3 near ν_c, |Δ ln p| ≤ 1e-13 in the root: 1e-10.
      EXPECT_NEAR(cv.normal_stress / 100.0, 1.0, 1e-10) << chains << " " << rate;
      EXPECT_NEAR(cv.friction / cp.friction, 1.0, 1e-10) << chains << " " << rate;
    }
  }
}

// The material point's σ_IC: its closed form in simple shear (p_IC I, τ_IC = μ_IC p_IC), zero when
// switched off.
TEST(InertialContact, MaterialPointClosedForm) {
  auto s = spheres(false);
  s.inertial_contact = 0.12, s.inertial_contact_power = 3.3;
  const continuum::MultiRegimePoint point(s);
  continuum::PointState state;
  state.solid_fraction = 0.575, state.granular_temperature = 1e-6;
  const double rate = 20;
  const auto parts = point.evaluate(state, rev::simple_shear_strain_rate(rate));
  const double p_ic = 2500 * std::pow(0.12 * 1e-3 * rate, 2) * std::pow(0.5915 - 0.575, -3.3);
  const double mu = critical_state_friction(s.force_chain_parameters);
  EXPECT_NEAR(parts.inertial_contact_pressure / p_ic, 1.0, 1e-14);
  EXPECT_NEAR(parts.inertial_contact.trace() / 3 / p_ic, 1.0, 1e-14);
  EXPECT_NEAR(-parts.inertial_contact(0, 1) / (mu * p_ic), 1.0, 1e-14);  // compression positive
  EXPECT_NEAR(point.inertial_contact_friction() / mu, 1.0, 1e-14);
  // The viscous scale (liquid.viscous_contact b_v, with the liquid on): p_IC adds b_v η0 γ̇ (ν_c -
  // ν)^-m, and the steady model's σ_yy,IC is the same number (one definition, two users).
  auto wet = s;
  wet.liquid = true, wet.liquid_parameters.viscosity = 1e-3, wet.viscous_contact = 0.7;
  const double p_wet = p_ic + 0.7 * 1e-3 * rate * std::pow(0.5915 - 0.575, -3.3);
  EXPECT_NEAR(continuum::MultiRegimePoint(wet)
                      .evaluate(state, rev::simple_shear_strain_rate(rate))
                      .inertial_contact_pressure /
                  p_wet,
              1.0, 1e-14);
  const auto steady_wet = steady_simple_shear_at_solid_fraction(wet, {}, rate, 0.575);
  ASSERT_TRUE(steady_wet.ok) << steady_wet.why;
  EXPECT_NEAR(steady_wet.inertial_contact_normal_stress / p_wet, 1.0, 1e-14);
  wet.liquid = false;  // b_v needs the liquid: dry, only the inertial scale is left
  EXPECT_NEAR(continuum::contact_pressure(wet, 0.575, rate) / p_ic, 1.0, 1e-14);
  const continuum::MultiRegimePoint off(spheres(false));
  EXPECT_EQ(off.evaluate(state, rev::simple_shear_strain_rate(rate)).inertial_contact.norm(), 0.0);
}

// Two independent paths: the steady model's algebraic state and the time-stepped REV (the material
// point's σ_IC) relaxed to its steady state, kinetic theory + σ_IC (no force chains: both shear
// σ_IC at M(θ=0)/√3 of the same parameters).
TEST(InertialContact, SteadyStateIsTheTimeSteppedRevs) {
  auto s = spheres(false);
  s.inertial_contact = 0.12, s.inertial_contact_power = 2.5;
  const continuum::MultiRegimePoint point(s);
  // constant volume at φ: the REV's σ_yy and τ against the algebraic prediction
  const double phi = 0.57, rate = 20;
  const auto cv = steady_simple_shear_at_solid_fraction(s, {}, rate, phi);
  ASSERT_TRUE(cv.ok) << cv.why;
  EXPECT_GT(cv.inertial_contact_normal_stress, 0.2 * cv.collisional_pressure);  // it matters here
  rev::SimpleShearControl control;
  control.control = rev::ShearControl::constant_volume;
  control.shear_rate = rate;
  control.void_ratio = 1.0 / phi - 1.0;
  const auto r = rev::run_simple_shear(point, control);
  ASSERT_TRUE(r.steady.reached);
  EXPECT_GT(r.steps, 20);  // a real relaxation, not a trivial stop
  // the REV stops at a relative change of 1e-10 per unit strain: 1e-8
  EXPECT_NEAR(r.steady.normal_stress / cv.normal_stress, 1.0, 1e-8);
  EXPECT_NEAR(r.steady.shear_stress / cv.shear_stress, 1.0, 1e-8);
  EXPECT_NEAR(r.series.inertial_contact_pressure.back() / cv.inertial_contact_normal_stress, 1.0,
              1e-12);  // ν is fixed: the same closed form
  // constant pressure at that σ_yy: the REV finds the same ν (bisection in p_COL + p_IC)
  control.control = rev::ShearControl::constant_pressure;
  control.normal_stress = cv.normal_stress;
  const auto rp = rev::run_simple_shear(point, control);
  ASSERT_TRUE(rp.steady.reached);
  EXPECT_NEAR(rp.steady.solid_fraction / phi, 1.0, 1e-8);
  EXPECT_NEAR(rp.steady.friction / cv.friction, 1.0, 1e-7);
}

}  // namespace
}  // namespace granflow::calibration
