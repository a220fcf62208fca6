// Elastic response inside the locus: closed forms of the pressure-dependent hypo-elasticity
// (K = K_ref (p/p_ref)^n, constant ν) against the model's update, and the exact ("finite")
// update against many small tangent steps (two independent integration paths).
#include <gtest/gtest.h>

#include <cmath>

#include "continuum/model/force_chains/force_chain_model.hpp"
#include "tests/force_chains/strain_drivers.hpp"

namespace fc = granflow::model::force_chains;
using fc::testing::diag;

namespace {
fc::ForceChainParameters params() { return fc::ForceChainParameters{}; }

// Closed form of dp/dε_v = K_ref (p/p_ref)^n above the floor.
double isotropic_pressure(const fc::ForceChainParameters& p, double p0, double ev) {
  const double n = p.elastic_exponent;
  return std::pow(
      std::pow(p0, 1 - n) + (1 - n) * p.bulk_modulus_ref * std::pow(p.reference_pressure, -n) * ev,
      1 / (1 - n));
}
}  // namespace

TEST(ForceChainsElastic, IsotropicUnloadingFollowsPowerLaw) {
  // n = 0.5 (default, sqrt fast path), a generic exponent, and n = 0 (linear)
  for (double n : {0.5, 0.6, 0.0}) {
    auto par = params();
    par.elastic_exponent = n;
    const fc::ForceChainModel model(par);
    // overconsolidated: r_c = 4 √3 p, so isotropic unloading stays inside the locus
    auto s = model.isotropic_state(80e3, 0.7, 4.0);
    double ev = 0;
    for (int i = 0; i < 200; ++i) {  // unload: ε_v = -6e-4 in 200 increments
      const auto info = model.update(s, diag(-1e-6, -1e-6, -1e-6), 1e-3, 0.0);
      ev -= 3e-6;
      ASSERT_FALSE(info.plastic) << "step " << i;
    }
    const double expected = isotropic_pressure(par, 80e3, ev);
    // the finite update is exact along straight paths; 1e-10 relative is round-off of the
    // 200 compositions
    EXPECT_NEAR(fc::testing::p_of(s), expected, 1e-10 * expected) << n;
    EXPECT_LT(expected, 0.9 * 80e3);  // the path did unload substantially
    EXPECT_NEAR(fc::testing::q_of(s), 0.0, 1e-9 * expected);
    // void ratio: 1+e ∝ exp(-ε_v) (exact Lagrangian volume change)
    EXPECT_NEAR(s.void_ratio, 1.7 * std::exp(-ev) - 1.0, 1e-12);
  }
}

TEST(ForceChainsElastic, DeviatoricStrainAtConstantPressureGivesThreeG) {
  const auto par = params();
  const fc::ForceChainModel model(par);
  auto s = model.isotropic_state(60e3, 0.7, 4.0);
  const double a = 2e-4;  // isochoric: ε_q = a, p constant, q = 3 G(p) ε_q
  const auto info = model.update(s, diag(a, -a / 2, -a / 2), 1e-3, 0.0);
  ASSERT_FALSE(info.plastic);
  const double g = model.elasticity().shear_modulus(60e3);
  EXPECT_NEAR(fc::testing::p_of(s), 60e3, 1e-9 * 60e3);  // round-off only
  EXPECT_NEAR(fc::testing::q_of(s), 3 * g * a, 1e-9 * 3 * g * a);
  // G/K from the Poisson ratio: G = 3K(1-2ν)/(2(1+ν))
  const double nu = par.poisson_ratio;
  EXPECT_NEAR(g / model.elasticity().bulk_modulus(60e3), 1.5 * (1 - 2 * nu) / (1 + nu), 1e-14);
}

TEST(ForceChainsElastic, FiniteUpdateMatchesManyTangentSteps) {
  const auto par = params();
  const fc::PressureDependentElasticity el(par);
  // general strain increment (volumetric + shear, crossing nothing)
  Eigen::Matrix3d de;
  de << 1.2e-3, 2e-4, -1e-4, 2e-4, -3e-4, 5e-5, -1e-4, 5e-5, 4e-4;
  Eigen::Matrix3d s0 = diag(70e3, 50e3, 40e3);
  s0(0, 1) = s0(1, 0) = 3e3;
  const Eigen::Matrix3d finite = el.finite_update(s0, de);
  // forward-Euler tangent integration, N steps: error O(1/N)
  auto tangent = [&](int n) {
    Eigen::Matrix3d s = s0;
    for (int i = 0; i < n; ++i) s += el.apply(s.trace() / 3, de / n);
    return s;
  };
  const double e1 = (tangent(1000) - finite).norm(), e2 = (tangent(2000) - finite).norm();
  // first-order convergence of the tangent path to the finite one: halving h halves the error
  // (ratio 2 ± 5 %), and the finite form is within the O(1/N) error of N = 2000 steps
  EXPECT_NEAR(e1 / e2, 2.0, 0.1);
  EXPECT_LT(e2, 1e-4 * finite.norm());
}

TEST(ForceChainsElastic, FloorKeepsStiffnessPositiveAndLinearBelowIt) {
  const auto par = params();
  const fc::PressureDependentElasticity el(par);
  const double k_floor =
      par.bulk_modulus_ref *
      std::pow(par.pressure_floor / par.reference_pressure, par.elastic_exponent);
  EXPECT_DOUBLE_EQ(el.bulk_modulus(0.0), k_floor);
  EXPECT_DOUBLE_EQ(el.bulk_modulus(-5.0), k_floor);
  // from zero stress, compaction below the floor is linear with K(p_floor)
  const double ev = 0.5 * par.pressure_floor / k_floor;
  EXPECT_NEAR(el.pressure_after(0.0, ev), k_floor * ev, 1e-12 * par.pressure_floor);
  // crossing the floor upward then back downward returns to the start (piecewise closed form)
  const double p1 = el.pressure_after(10.0, 1e-3);
  EXPECT_NEAR(el.pressure_after(p1, -1e-3), 10.0, 1e-9 * p1);
  // compliance inverts stiffness
  Eigen::Matrix3d de = diag(1e-4, -2e-5, 3e-5);
  de(0, 2) = de(2, 0) = 7e-5;
  EXPECT_NEAR((el.apply_inverse(5e3, el.apply(5e3, de)) - de).norm(), 0.0, 1e-18);
}
