// The contacts' dense inertial stress of the steady in-parallel model (steady.inertial_contact,
// ModelFactors::inertial_contact, _power m): σ_yy,IC = ρ_p (a_c d γ̇)² (ν_c - ν)^-m, sheared at
// μ_FC. Checked
// against its closed form at constant volume (it adds to the normal and shear stress and leaves
// T alone), and the constant-volume state against the constant-pressure state at the pressure it
// finds (two solvers: bisection in ν at given p, and the explicit state at given ν).
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/calibration/steady_shear_model.hpp"
#include "continuum/model/closures.hpp"

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
      ModelFactors with;
      with.inertial_contact = 0.12, with.inertial_contact_power = m;
      const auto bare = steady_simple_shear_at_solid_fraction(s, {}, rate, phi);
      const auto st = steady_simple_shear_at_solid_fraction(s, with, rate, phi);
      ASSERT_TRUE(bare.ok && st.ok) << st.why;
      const double p_ic = rho * std::pow(0.12 * d * rate, 2) * std::pow(nu_c - phi, -m);
      // Same closed expressions on both sides: rounding only.
      EXPECT_NEAR(st.inertial_contact_normal_stress / p_ic, 1.0, 1e-14) << phi;
      EXPECT_NEAR(st.normal_stress / (bare.normal_stress + p_ic), 1.0, 1e-14) << phi;
      EXPECT_NEAR(st.shear_stress / (bare.shear_stress + mu_cs * p_ic), 1.0, 1e-14) << phi;
      EXPECT_EQ(st.granular_temperature, bare.granular_temperature) << phi;  // no production
    }
  // It scales as γ̇² like the collisions': the scaled pressure does not depend on the rate.
  ModelFactors with;
  with.inertial_contact = 0.12;
  const auto slow = steady_simple_shear_at_solid_fraction(s, with, 2.0, 0.56);
  const auto fast = steady_simple_shear_at_solid_fraction(s, with, 20.0, 0.56);
  EXPECT_NEAR(slow.scaled_pressure / fast.scaled_pressure, 1.0, 1e-12);
}

TEST(InertialContact, ConstantVolumeStateIsTheConstantPressureStateAtItsPressure) {
  ModelFactors f;
  f.inertial_contact = 0.12, f.friction_rise = 1.2, f.friction_rise_I0 = 2;
  for (const bool chains : {false, true}) {
    const auto s = spheres(chains);
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

}  // namespace
}  // namespace granflow::calibration
