// Fluidization (r_c -> 0, σ_FC = 0, χ frozen), regrowth (compaction with small T), the
// undrained liquefaction of the default loose sand, and stability at the extremes.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

#include "continuum/model/force_chains/force_chain_model.hpp"
#include "tests/force_chains/strain_drivers.hpp"

namespace fc = granflow::model::force_chains;
using fc::testing::diag;
using fc::testing::p_of;
using fc::testing::q_of;

namespace {
// Shear the sample first so that χ has rotated away from the isotropic axis.
fc::ForceChainState sheared_state(const fc::ForceChainModel& model) {
  auto s = model.isotropic_state(100e3, 0.60);
  for (int i = 0; i < 100; ++i) fc::testing::drained_triaxial_step(model, s, 1e-3, 100e3);
  return s;
}

void expect_sane(const fc::ForceChainModel& model, const fc::ForceChainState& s,
                 const fc::UpdateInfo& info, const char* what) {
  ASSERT_TRUE(s.stress.allFinite()) << what;
  ASSERT_TRUE(std::isfinite(s.r_c) && std::isfinite(s.void_ratio)) << what;
  ASSERT_GE(s.r_c, 0.0) << what;
  ASSERT_NEAR(s.chi.norm(), 1.0, 1e-12) << what;  // the axis stays a unit tensor
  if (s.fluidized) {
    ASSERT_EQ(s.stress.norm(), 0.0) << what;
  } else {
    // on or inside the locus (same 1e-6 as the consistency test)
    ASSERT_LE(info.yield_value, 1e-6) << what;
    ASSERT_GE(p_of(s), -1e-9 * s.r_c) << what;  // no tension beyond round-off
  }
  (void)model;
}
}  // namespace

TEST(ForceChainsFluidization, DilativePathFluidizesAndFreezesTheAxis) {
  const fc::ForceChainModel model{fc::ForceChainParameters{}};
  auto s = sheared_state(model);
  const Eigen::Matrix3d chi_sheared = s.chi;
  ASSERT_GT((chi_sheared - Eigen::Matrix3d::Identity() / std::sqrt(3.0)).norm(), 1e-3);
  // volumetric extension: unloading to the stress-free apex, then dilative plastic flow,
  // dr_c = (r_c/b_p) dε^p_v < 0 until r_c < fluidization_size
  bool fluid = false;
  double rc_prev = s.r_c;
  for (int i = 0; i < 400 && !fluid; ++i) {
    const auto info = model.update(s, diag(-1e-3, -1e-3, -1e-3), 1e-3, 0.0);
    expect_sane(model, s, info, "dilation");
    EXPECT_LE(s.r_c, rc_prev * (1 + 1e-12));  // dilation never hardens
    rc_prev = s.r_c;
    fluid = s.fluidized;
  }
  ASSERT_TRUE(fluid);
  EXPECT_EQ(s.r_c, 0.0);
  EXPECT_EQ(s.stress.norm(), 0.0);
  const Eigen::Matrix3d chi_fluid = s.chi;
  // shearing the fluidized material at high T changes nothing in the skeleton
  for (int i = 0; i < 100; ++i) {
    Eigen::Matrix3d shear = Eigen::Matrix3d::Zero();
    shear(0, 1) = shear(1, 0) = 5e-3;
    const auto info = model.update(s, shear + diag(1e-4, -1e-4, 0), 1e-3, 1.0);
    expect_sane(model, s, info, "fluid shear");
    EXPECT_TRUE(s.fluidized);
  }
  EXPECT_EQ((s.chi - chi_fluid).norm(), 0.0);  // χ frozen exactly
  // compaction at large T (collisional regime): no regrowth
  for (int i = 0; i < 50; ++i) model.update(s, diag(1e-3, 1e-3, 1e-3), 1e-3, 1.0);
  EXPECT_TRUE(s.fluidized);
  EXPECT_EQ(s.r_c, 0.0);
}

TEST(ForceChainsFluidization, RegrowthUnderCompactionWithSmallTemperature) {
  const fc::ForceChainParameters par;
  const fc::ForceChainModel model(par);
  fc::ForceChainState s;
  s.fluidized = true;
  s.r_c = 0.0;
  s.void_ratio = 0.75;
  const Eigen::Matrix3d chi0 = s.chi;
  // shearing without compaction at T = 0: no regrowth (the rule needs compaction)
  Eigen::Matrix3d shear = Eigen::Matrix3d::Zero();
  shear(0, 2) = shear(2, 0) = 1e-3;
  for (int i = 0; i < 20; ++i) model.update(s, shear, 1e-3, 0.0);
  EXPECT_EQ(s.r_c, 0.0);
  // compaction at T = T_r/2: dr_c = (1 - T/T_r) K_r dε_v exactly
  const double dev = 3e-5;
  model.update(s, diag(dev / 3, dev / 3, dev / 3), 1e-3, 0.5 * par.regrowth_temperature);
  EXPECT_NEAR(s.r_c, 0.5 * par.regrowth_modulus * dev, 1e-9 * par.regrowth_modulus * dev);
  EXPECT_TRUE(s.fluidized);
  EXPECT_EQ(s.stress.norm(), 0.0);
  // keep compacting with T = 0: the skeleton re-forms, then carries load again
  bool resolidified = false;
  for (int i = 0; i < 200 && !resolidified; ++i)
    resolidified = model.update(s, diag(1e-5, 1e-5, 1e-5), 1e-3, 0.0).resolidified;
  ASSERT_TRUE(resolidified);
  EXPECT_FALSE(s.fluidized);
  EXPECT_GE(s.r_c, par.resolidification_size);
  EXPECT_EQ((s.chi - chi0).norm(), 0.0);  // the axis was kept through the fluid phase
  for (int i = 0; i < 300; ++i) {
    const auto info = model.update(s, diag(1e-4, 1e-4, 1e-4), 1e-3, 0.0);
    expect_sane(model, s, info, "reconsolidation");
  }
  // isotropic reconsolidation by ε_v = 0.09: p is back in the kPa-MPa range and the locus has
  // grown with the plastic compaction (r_c ∝ exp(ε^p_v/b_p))
  EXPECT_GT(p_of(s), 10e3);
  EXPECT_GT(s.r_c, 10 * par.resolidification_size);
}

TEST(ForceChainsFluidization, UndrainedLooseSandLiquefiesNearFivePercent) {
  // seed §4: e0 = 0.70, p'0 = 50 kPa, isochoric triaxial compression
  const fc::ForceChainModel model{fc::ForceChainParameters{}};
  auto s = model.isotropic_state(50e3, 0.70);
  double eps = 0.0, q_peak = 0.0, eps_liq = -1.0;
  const double d = 5e-5;
  for (int i = 0; i < 4000; ++i) {
    const auto info = fc::testing::undrained_triaxial_step(model, s, d);
    expect_sane(model, s, info, "undrained");
    eps += d;
    q_peak = std::max(q_peak, q_of(s));
    if (s.fluidized) {
      eps_liq = eps;
      break;
    }
  }
  std::printf("undrained: q_peak = %.0f Pa, sigma_FC = 0 from eps_d = %.4f\n", q_peak, eps_liq);
  // liquefaction (σ_FC = 0) between 3 % and 7 % deviatoric strain (seed Fig. 1: "for ε_d > 0.05")
  EXPECT_GT(eps_liq, 0.03);
  EXPECT_LT(eps_liq, 0.07);
  EXPECT_GT(q_peak, 10e3);  // a solid-like peak first (static liquefaction of a loose sand)
  EXPECT_NEAR(s.void_ratio, 0.70, 1e-12);  // isochoric: e unchanged
}

TEST(ForceChainsFluidization, StableAtTheExtremes) {
  const fc::ForceChainModel model{fc::ForceChainParameters{}};
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  // strain increments from 1e-12 (a tiny MPM step) to 5e-2 (the largest a case allows: a
  // fraction of the stable explicit step times 100 s⁻¹ is far below this)
  const double sizes[] = {1e-12, 1e-8, 1e-5, 1e-3, 1e-2, 5e-2};
  struct Start {
    double p, e, ocr;
  };
  const Start starts[] = {{50e3, 0.70, 1}, {1e5, 0.45, 1}, {1e5, 1.0, 1}, {200.0, 0.7, 1},
                          {2e3, 0.3, 1},   {2e3, 1.5, 3},  {1e7, 0.6, 1}};
  int fluidized = 0, updates = 0, refused = 0;
  for (const auto& st : starts)
    for (double h : sizes)
      for (int path = 0; path < 4; ++path) {
        auto s = model.isotropic_state(st.p, st.e, st.ocr);
        Eigen::Matrix3d dir;
        for (int i = 0; i < 3; ++i)
          for (int j = i; j < 3; ++j) dir(i, j) = dir(j, i) = u(rng);
        dir /= dir.norm();
        for (int i = 0; i < 40; ++i) {
          // alternate the path now and then: loading, unloading, reversal
          const Eigen::Matrix3d de = (i % 13 == 12 ? -1.0 : 1.0) * h * dir;
          if (de.trace() >= std::log1p(s.void_ratio)) {
            // compaction beyond e = 0 is refused with a message, not integrated
            EXPECT_THROW(model.update(s, de, 1e-4, 0.0), std::invalid_argument);
            ++refused;
            break;
          }
          const auto info = model.update(s, de, 1e-4, i % 2 ? 0.0 : 1e-2);
          ++updates;
          expect_sane(model, s, info, "extremes");
        }
        fluidized += s.fluidized;
      }
  std::printf("extremes: %d updates, %d paths ended fluidized, %d refused (e < 0)\n", updates,
              fluidized, refused);
  // absurd increments (30 % and 100 % strain in one update): finite, or refused, never NaN; the
  // sub-step budget bounds the cost
  for (double h : {0.3, 1.0})
    for (int path = 0; path < 6; ++path) {
      auto s = model.isotropic_state(1e3 + 4e4 * path, 0.5 + 0.05 * path);
      Eigen::Matrix3d dir;
      for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j) dir(i, j) = dir(j, i) = u(rng);
      dir /= dir.norm();
      for (int i = 0; i < 4; ++i) {
        const Eigen::Matrix3d de = (i == 2 ? -h : h) * dir;
        if (de.trace() >= std::log1p(s.void_ratio)) break;
        const auto info = model.update(s, de, 1e-4, 0.0);
        expect_sane(model, s, info, "absurd increment");
      }
    }
  EXPECT_GT(fluidized, 0);  // the set does include fluidizing paths
  // p' -> 0 under a pure tension increment from 1 Pa: stress-free, not NaN
  auto s = model.isotropic_state(1e5, 0.7);
  s.stress = 1.0 * Eigen::Matrix3d::Identity();
  const auto info = model.update(s, diag(-1e-2, -1e-2, -1e-2), 1e-4, 0.0);
  expect_sane(model, s, info, "p -> 0");
  EXPECT_TRUE(info.contact_loss);
  // a NaN strain is refused with a message before it can reach the state
  auto t = model.isotropic_state(1e5, 0.7);
  EXPECT_THROW(model.update(t, diag(std::nan(""), 0, 0), 1e-4, 0.0), std::invalid_argument);
  EXPECT_EQ(fc::testing::p_of(t), 1e5);
}

TEST(ForceChainsFluidization, MaterialFileMatchesTheDefaults) {
  // cases/rev/materials/sand_force_chains.yaml and ForceChainParameters{} must say the same
  const YAML::Node root = YAML::LoadFile(std::string(GRANFLOW_SOURCE_DIR) +
                                         "/cases/rev/materials/sand_force_chains.yaml");
  const YAML::Node n = root["force_chains"];
  ASSERT_TRUE(n.IsMap());
  const fc::ForceChainParameters d;
  const std::pair<const char*, double> expected[] = {
      {"bulk_modulus_ref", d.bulk_modulus_ref},
      {"reference_pressure", d.reference_pressure},
      {"elastic_exponent", d.elastic_exponent},
      {"poisson_ratio", d.poisson_ratio},
      {"pressure_floor", d.pressure_floor},
      {"beta_f", d.beta_f},
      {"gamma", d.gamma},
      {"b_p", d.b_p},
      {"xi_psi", d.xi_psi},
      {"xi_psi_dense", d.xi_psi_dense},
      {"c_p", d.c_p},
      {"theta_hat_c", d.theta_hat_c},
      {"theta_hat_e", d.theta_hat_e},
      {"M_c", d.M_c},
      {"e_Gamma", d.e_Gamma},
      {"lambda_c", d.lambda_c},
      {"xi_c", d.xi_c},
      {"atmospheric_pressure", d.atmospheric_pressure},
      {"e_min", d.e_min},
      {"e_max", d.e_max},
      {"d_0", d.d_0},
      {"n_d", d.n_d},
      {"fluidization_size", d.fluidization_size},
      {"resolidification_size", d.resolidification_size},
      {"regrowth_modulus", d.regrowth_modulus},
      {"regrowth_temperature", d.regrowth_temperature}};
  for (const auto& [key, value] : expected) {
    ASSERT_TRUE(n[key]) << key;
    EXPECT_DOUBLE_EQ(n[key].as<double>(), value) << key;
  }
}

TEST(ForceChainsFluidization, RateIndependentFromSlowToFastSteps) {
  // the same strain increments taken over dt = 1e-9 s ... 1 s (ε̇ from ~1e-6 to 1e3 s⁻¹ and
  // beyond) give bit-identical states: the force-chain part is rate independent (seed §3.1)
  const fc::ForceChainModel model{fc::ForceChainParameters{}};
  auto a = model.isotropic_state(50e3, 0.70), b = a;
  for (int i = 0; i < 300; ++i) {
    model.update(a, diag(1e-4, -5e-5, -5e-5), 1e-9, 0.0);
    model.update(b, diag(1e-4, -5e-5, -5e-5), 1.0, 0.0);
  }
  EXPECT_EQ((a.stress - b.stress).norm(), 0.0);
  EXPECT_EQ(a.r_c, b.r_c);
}
