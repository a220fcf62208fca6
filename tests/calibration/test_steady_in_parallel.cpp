// The in-parallel steady simple shear (analysis/calibration/steady_shear_model.hpp, force chains
// on their critical state + kinetic theory, docs/model/steady_state.md): its limits and its
// balances, each checked by an independent expression.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "analysis/calibration/steady_shear_model.hpp"
#include "continuum/model/force_chains/critical_state_lade_duncan.hpp"

namespace granflow::calibration {
namespace {

// Dry frictional DEM spheres (cases/rev/materials/dem_spheres_force_chains.yaml).
continuum::MultiRegimeSettings spheres(bool chains = true) {
  continuum::MultiRegimeSettings s;
  s.collisional = true;
  s.force_chains = chains;
  auto& col = s.collisional_parameters;
  col.diameter = 1e-3;
  col.particle_density = 2500;
  col.restitution = 0.7;
  col.particle_friction = 0.5;
  col.jamming_fraction = 0.60;
  auto& fc = s.force_chain_parameters;
  fc.M_c = 0.70;
  fc.e_Gamma = 0.695;
  fc.lambda_c = 0.01;
  fc.xi_c = 0.5;
  fc.atmospheric_pressure = 100;
  return s;
}

TEST(SteadyInParallel, CriticalFrictionIsTheLadeDuncanRatioAtZeroLodeAngle) {
  // Independent closed form: at cos3θ = 0, I1³/I3 = k_LD gives 1 - η²/3 = 27/k_LD, with
  // k_LD = 27/(1 - M_c²/3 + 2 M_c³/27) from the compression value.
  for (double M_c : {0.6, 0.7, 1.25}) {
    auto fc = spheres().force_chain_parameters;
    fc.M_c = M_c;
    const double one_minus = 1.0 - M_c * M_c / 3.0 + 2.0 / 27.0 * M_c * M_c * M_c;
    const double eta = std::sqrt(3.0 * (1.0 - one_minus));
    EXPECT_NEAR(critical_state_friction(fc), eta / std::sqrt(3.0), 1e-13) << M_c;
  }
  // The published value for M_c = 1.25 (φ_cs = 31.2°): μ_FC = 0.6133 in simple shear.
  auto fc = spheres().force_chain_parameters;
  fc.M_c = 1.25;
  EXPECT_NEAR(critical_state_friction(fc), 0.61332, 1e-5);
}

TEST(SteadyInParallel, SkeletonPressureInvertsTheCriticalStateLine) {
  const auto fc = spheres().force_chain_parameters;
  const model::force_chains::CriticalStateLadeDuncan line(fc);
  for (double p : {1.0, 10.0, 100.0, 1000.0}) {
    const double e = line.critical_void_ratio(p);
    EXPECT_NEAR(critical_state_pressure(fc, 1.0 / (1.0 + e)) / p, 1.0, 1e-10) << p;
  }
  EXPECT_EQ(critical_state_pressure(fc, 1.0 / (1.0 + fc.e_Gamma + 1e-9)), 0.0);  // looser: none
}

TEST(SteadyInParallel, SlowShearTendsToTheCriticalStateOfTheSkeleton) {
  // T -> 0 as γ̇ -> 0: p_COL vanishes, e -> e_cs(p), μ -> μ_FC (seed §3.1). The collisional share
  // falls as I² (p_COL ∝ T ∝ γ̇² at fixed ν), so at I = 1e-4 it is ~1e-7 of p.
  const auto s = spheres();
  const double p = 100, rho_p = 2500, d = 1e-3;
  const double gamma_dot = 1e-4 * std::sqrt(p / rho_p) / d;  // I = 1e-4
  const auto st = steady_simple_shear(s, {}, gamma_dot, p);
  ASSERT_TRUE(st.ok) << st.why;
  const model::force_chains::CriticalStateLadeDuncan line(s.force_chain_parameters);
  EXPECT_NEAR(1.0 / st.solid_fraction - 1.0, line.critical_void_ratio(p), 1e-6);
  EXPECT_NEAR(st.friction, critical_state_friction(s.force_chain_parameters), 1e-5);
  EXPECT_LT(st.collisional_pressure / p, 1e-5);
}

TEST(SteadyInParallel, NormalStressIsSharedAndTheEnergyBalanceHolds) {
  const auto s = spheres();
  const auto& col = s.collisional_parameters;
  for (double alpha : {0.0, 0.05}) {
    ModelFactors f;
    f.contact_production = alpha;
    for (double gamma_dot : {2.0, 10.0, 60.0}) {
      const auto st = steady_simple_shear(s, f, gamma_dot, 100.0);
      ASSERT_TRUE(st.ok) << st.why;
      // p_FC(ν) from the line, p_COL from T: their sum is the imposed σ_yy (ν to rounding).
      EXPECT_NEAR((st.force_chain_normal_stress + st.collisional_pressure) / 100.0, 1.0, 1e-9);
      EXPECT_NEAR(st.force_chain_normal_stress,
                  critical_state_pressure(s.force_chain_parameters, st.solid_fraction), 1e-9);
      // Production τ_COL γ̇ + α τ_FC γ̇ = Γ = ρ_p f3 T^{3/2}/d (L = d), written independently of
      // the solver's scaled form.
      const auto k = model::collisional_coefficients(col, st.solid_fraction);
      const double T = st.granular_temperature;
      const double production =
          (st.collisional_shear_stress + alpha * st.force_chain_shear_stress) * gamma_dot;
      const double dissipation = col.particle_density * k.f3 * std::pow(T, 1.5) / col.diameter;
      EXPECT_NEAR(production / dissipation, 1.0, 1e-9) << alpha << " " << gamma_dot;
      EXPECT_NEAR(st.shear_stress,
                  st.force_chain_shear_stress + st.collisional_shear_stress, 1e-12 * st.shear_stress);
    }
  }
}

TEST(SteadyInParallel, ContactProductionHeatsTheDenseRegime) {
  const auto s = spheres();
  ModelFactors f;
  const auto seed_model = steady_simple_shear(s, f, 4.0, 100.0);
  f.contact_production = 0.1;
  const auto heated = steady_simple_shear(s, f, 4.0, 100.0);
  ASSERT_TRUE(seed_model.ok && heated.ok);
  EXPECT_GT(heated.scaled_temperature, 1.5 * seed_model.scaled_temperature);
}

TEST(SteadyInParallel, LooseOfTheLineAtFastShearIsKineticTheoryAlone) {
  // At large I the collisions alone carry σ_yy at a ν looser than the line: p_FC = 0 and the
  // state is the kinetic-theory one (same ν, μ, T to rounding).
  const auto chains = spheres(true), alone = spheres(false);
  const auto a = steady_simple_shear(chains, {}, 400.0, 100.0);
  const auto b = steady_simple_shear(alone, {}, 400.0, 100.0);
  ASSERT_TRUE(a.ok && b.ok);
  EXPECT_EQ(a.force_chain_normal_stress, 0.0);
  EXPECT_LT(b.solid_fraction, 1.0 / (1.0 + chains.force_chain_parameters.e_Gamma));
  EXPECT_NEAR(a.solid_fraction, b.solid_fraction, 1e-14);
  EXPECT_NEAR(a.friction, b.friction, 1e-12);
}

TEST(SteadyInParallel, FrictionRisesFromTheCriticalStateToTheCollisionalValue) {
  // μ(I) runs from μ_FC at I -> 0 to the kinetic-theory μ = sqrt(f2 f3)/f1 once p_FC = 0, and
  // φ(I) falls from the critical state line: the shape of μ(I), φ(I) of DEM simple shear. Past
  // the point where p_FC vanishes μ is kinetic theory's, whose own slope may be either sign.
  const auto s = spheres();
  double last_mu = 0, last_phi = 1;
  for (double gamma_dot : {0.5, 2.0, 4.0, 10.0, 20.0, 40.0, 60.0}) {
    const auto st = steady_simple_shear(s, {}, gamma_dot, 100.0);
    ASSERT_TRUE(st.ok) << st.why;
    std::printf("γ̇ %5.1f I %.4f: μ %.4f φ %.4f T* %.4f  p_FC/p %.3f\n", gamma_dot,
                st.inertial_number, st.friction, st.solid_fraction, st.scaled_temperature,
                st.force_chain_normal_stress / 100.0);
    if (st.force_chain_normal_stress > 0) {
      EXPECT_GT(st.friction, last_mu) << gamma_dot;
    }
    EXPECT_LT(st.solid_fraction, last_phi) << gamma_dot;
    last_mu = st.friction, last_phi = st.solid_fraction;
  }
}

}  // namespace
}  // namespace granflow::calibration
