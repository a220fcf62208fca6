// The shear stopped at constant volume (rev/shear_stop.hpp): after a steady simple shear the
// point cools by its energy balance alone. Checked against the closed forms of that balance, with
// the dissipation rates taken from the closures themselves (Γ, Λ of StressParts), not from the
// Riccati coefficients the update integrates:
//   (3/2) ρ_p ν dT/dt = -Γ - Λ,  Γ = Γ̂ T^{3/2},  Λ = Λ̂ T,  s = T^½:
//   ds/dt = -c s - b s²,  b = Γ / (3 ρ_p ν s³),  c = Λ / (3 ρ_p ν s²);
//   dry (c = 0): Haff's law T(t) = T0 / (1 + b s0 t)²;
//   immersed: s(t) = c s0 e^{-ct} / (c + b s0 (1 - e^{-ct})).
#include <gtest/gtest.h>

#include <cmath>

#include "continuum/rev/shear_stop.hpp"
#include "continuum/rev/simple_shear.hpp"

using namespace granflow;

namespace {

struct Stopped {
  rev::SimpleShearResult sheared;
  rev::SimpleShearSeries stop;
  double b = 0, c = 0, s0 = 0;
};

Stopped shear_then_stop(const continuum::MultiRegimeSettings& settings, double duration) {
  const continuum::MultiRegimePoint point(settings);
  Stopped out;
  rev::SimpleShearControl control;
  control.shear_rate = 20.0;
  control.void_ratio = 0.8;
  out.sheared = rev::run_simple_shear(point, control);
  const continuum::PointState& at_stop = out.sheared.final_state;
  const auto parts = point.evaluate(at_stop, Eigen::Matrix3d::Zero());
  const double rho_nu = settings.collisional_parameters.particle_density * at_stop.solid_fraction;
  out.s0 = std::sqrt(at_stop.granular_temperature);
  out.b = parts.collisional_dissipation / (3.0 * rho_nu * std::pow(out.s0, 3));
  out.c = parts.liquid_dissipation / (3.0 * rho_nu * out.s0 * out.s0);
  rev::ShearStopControl stop;
  stop.duration = duration;
  rev::run_shear_stop(point, at_stop, out.sheared.series.strain.back(), stop, out.stop);
  return out;
}

}  // namespace

TEST(ShearStop, DryPointCoolsAsHaffsLaw) {
  const continuum::MultiRegimeSettings dry;
  // 50 Haff times: T falls by 2600×.
  const auto probe = shear_then_stop(dry, 1e-9);
  const double haff_time = 1.0 / (probe.b * probe.s0);
  const auto r = shear_then_stop(dry, 50.0 * haff_time);
  ASSERT_TRUE(r.sheared.steady.reached);
  ASSERT_GT(r.stop.time.size(), 100u);
  EXPECT_NEAR(r.stop.time.back(), 50.0 * haff_time, 1e-12 * haff_time);
  const double T0 = r.s0 * r.s0;
  for (std::size_t i = 0; i < r.stop.time.size(); ++i) {
    const double haff = T0 / std::pow(1.0 + r.b * r.s0 * r.stop.time[i], 2);
    // exact Riccati steps with constant coefficients (ν fixed, L = d): round-off only
    EXPECT_NEAR(r.stop.granular_temperature[i] / haff, 1.0, 1e-10) << "step " << i;
    // at rest the volume is held and nothing shears: ν fixed, τ = 0, p = p_COL(ν, T)
    EXPECT_EQ(r.stop.solid_fraction[i], r.sheared.final_state.solid_fraction);
    EXPECT_EQ(r.stop.shear_stress[i], 0.0);
    EXPECT_DOUBLE_EQ(r.stop.pressure[i], r.stop.collisional_pressure[i]);
  }
  EXPECT_LT(r.stop.granular_temperature.back(), T0 / 2000.0);
}

TEST(ShearStop, ImmersedPointCoolsByCollisionsAndTheLiquid) {
  continuum::MultiRegimeSettings wet;
  wet.liquid = true;
  wet.fluctuation_dissipation = true;
  const auto probe = shear_then_stop(wet, 1e-9);
  ASSERT_GT(probe.c, 0.0);
  const double duration = 5.0 / probe.c;  // five viscous times
  const auto r = shear_then_stop(wet, duration);
  for (std::size_t i = 0; i < r.stop.time.size(); ++i) {
    const double decay = std::exp(-r.c * r.stop.time[i]);
    const double s = r.c * r.s0 * decay / (r.c + r.b * r.s0 * (1.0 - decay));
    EXPECT_NEAR(r.stop.granular_temperature[i] / (s * s), 1.0, 1e-9) << "step " << i;
  }
  // the liquid alone would leave e^{-10} of T0 after five viscous times; collisions take more
  EXPECT_LT(r.stop.granular_temperature.back(), std::exp(-10.0) * r.s0 * r.s0);
}
