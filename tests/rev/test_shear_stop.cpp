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

#include "continuum/model/closures.hpp"
#include "continuum/rev/shear_stop.hpp"
#include "continuum/rev/simple_shear.hpp"
#include "tests/rev/dem_sphere_settings.hpp"

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

// The drained stop (rev/shear_stop.hpp run_drained_stop): an elastic skeleton at rest under
// σ_n = p0 (1 + δ) drains its liquid over H. Linearised about p0 (σ_yy = p0 + M ε_yy, M = K + 4G/3
// the constrained modulus of the skeleton at p0), Terzaghi's lumped consolidation
//   u = σ_n − σ_yy,  dε_yy/dt = k u,  k = κ(ν) / (η0 H²)
// gives u(t) = δ p0 e^{−k M t}. The update is backward Euler in u, u_{n+1} = u_n / (1 + k M Δt_n),
// checked step by step with the series' own steps; a run with steps 10× finer reaches u = 0.1 u0
// at ln(10)/(k M), the continuous closed form.
namespace {

struct Drained {
  rev::SimpleShearSeries stop;
  double k = 0, M = 0, p0 = 0, delta = 0;
};

Drained drained_elastic_point(double duration_in_consolidation_times, double step_factor) {
  continuum::MultiRegimeSettings s = granflow::testing::dem_sphere_settings();
  s.collisional = false;  // the skeleton alone carries σ_yy (no p_COL, no T)
  const continuum::MultiRegimePoint point(s);
  Drained out;
  out.p0 = 100.0;
  out.delta = 1e-3;
  // Overconsolidated 2×: the small reload stays inside the yield locus (elastic).
  const continuum::PointState start = point.initial_state(0.72, out.p0, 2.0, 0.0);
  const auto& elastic = point.force_chain_model()->elasticity();
  out.M = elastic.bulk_modulus(out.p0) + 4.0 / 3.0 * elastic.shear_modulus(out.p0);
  rev::DrainedStopControl control;
  control.normal_stress = out.p0 * (1.0 + out.delta);
  control.drainage_length = 0.01;
  const auto& liquid = s.liquid_parameters;
  out.k = model::permeability(liquid, s.collisional_parameters.diameter, start.solid_fraction) /
          (liquid.viscosity * control.drainage_length * control.drainage_length);
  control.stop.duration = duration_in_consolidation_times / (out.k * out.M);
  control.stop.time_step_factor = step_factor;
  control.relative_tolerance = 1e-7;  // u0 = 1e-3 σ_n: the root to 1e-4 u0
  rev::run_drained_stop(point, start, 0.0, control, out.stop);
  return out;
}

}  // namespace

TEST(DrainedStop, ElasticSkeletonConsolidatesAsTerzaghisLumpedLaw) {
  const Drained r = drained_elastic_point(5.0, 0.1);
  ASSERT_GT(r.stop.time.size(), 40u);
  const double u0 = r.delta * r.p0;
  double u = u0, time = 0.0;
  for (std::size_t i = 0; i < r.stop.time.size(); ++i) {
    const double dt = r.stop.time[i] - time;
    time = r.stop.time[i];
    u /= 1.0 + r.k * r.M * dt;  // backward Euler in u with this step
    const double u_point = r.p0 * (1.0 + r.delta) - r.stop.normal_stress[i];
    // linearisation: M varies by ~δ/2 over the reload (K ∝ p^½), k by ~10 Δν ≈ 1e-4, and the
    // point solves σ_yy + u = σ_n to 1e-7 σ_n = 1e-4 u0: 5e-3 u0 in all
    EXPECT_NEAR(u_point, u, 5e-3 * u0) << "step " << i;
    // the compaction rate is k u: Darcy's outflow through H
    EXPECT_NEAR(r.stop.vertical_strain_rate[i], r.k * u_point, 5e-3 * r.k * u0) << "step " << i;
  }
  EXPECT_LT(r.p0 * (1.0 + r.delta) - r.stop.normal_stress.back(), 0.02 * u0);
}

TEST(DrainedStop, ConsolidationTimeIsTheClosedForms) {
  const Drained r = drained_elastic_point(4.0, 0.01);
  const double target = r.p0 * (1.0 + r.delta) - 0.1 * r.delta * r.p0;  // u = 0.1 u0
  std::size_t i = 0;
  while (i < r.stop.normal_stress.size() && r.stop.normal_stress[i] < target) ++i;
  ASSERT_LT(i, r.stop.normal_stress.size());
  // backward Euler with k M Δt = 0.01 lags e^{-kMt} by ~0.5 % per consolidation time (2.3 here),
  // the sample spacing adds ≤ 1 %: 2 %
  EXPECT_NEAR(r.stop.time[i] * r.k * r.M, std::log(10.0), 0.02 * std::log(10.0));
}
