// Yield locus (di Prisco et al. 1993) and Lade-Duncan critical state: analytic gradients against
// finite differences, closed-form points of the locus and of the Lade-Duncan surface, and the
// consistency of the stress update (stress on the locus after plastic steps).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "continuum/model/force_chains/force_chain_model.hpp"
#include "tests/force_chains/strain_drivers.hpp"

namespace fc = granflow::model::force_chains;
using fc::testing::diag;

namespace {
Eigen::Matrix3d symmetric(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::Matrix3d a;
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) a(i, j) = a(j, i) = scale * u(rng);
  return a;
}
}  // namespace

TEST(ForceChainsYield, GradientsMatchCentralDifferences) {
  const fc::ForceChainParameters par;
  const fc::YieldFunctionDiPrisco f(par);
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::Matrix3d sigma = 80e3 * Eigen::Matrix3d::Identity() + symmetric(rng, 20e3);
    Eigen::Matrix3d chi = Eigen::Matrix3d::Identity() / std::sqrt(3.0) + symmetric(rng, 0.1);
    chi /= chi.norm();
    const double rc = 2e5;
    const auto g = f.gradients(sigma, chi, rc);
    EXPECT_DOUBLE_EQ(g.value, f.value(sigma, chi, rc));
    // central differences with symmetric perturbations E_ij + E_ji (h = 1e-3 Pa, resp. 1e-6):
    // truncation O(h²) and round-off ~1e-16/h relative; 1e-5 relative leaves margin for both
    for (int i = 0; i < 3; ++i)
      for (int j = i; j < 3; ++j) {
        Eigen::Matrix3d e = Eigen::Matrix3d::Zero();
        e(i, j) += 0.5;
        e(j, i) += 0.5;
        const double h = 1e-3;
        const double fd =
            (f.value(sigma + h * e, chi, rc) - f.value(sigma - h * e, chi, rc)) / (2 * h);
        const double an = fc::double_contraction(g.d_stress, e);
        EXPECT_NEAR(an, fd, 1e-5 * g.d_stress.norm()) << i << j;
        const double hc = 1e-6;
        const double fdc =
            (f.value(sigma, chi + hc * e, rc) - f.value(sigma, chi - hc * e, rc)) / (2 * hc);
        EXPECT_NEAR(fc::double_contraction(g.d_axis, e), fdc, 1e-5 * g.d_axis.norm()) << i << j;
      }
    const double fdr =
        (f.value(sigma, chi, rc * (1 + 1e-6)) - f.value(sigma, chi, rc * (1 - 1e-6))) / (2e-6 * rc);
    EXPECT_NEAR(g.d_size, fdr, 1e-6 * std::abs(g.d_size));
  }
}

TEST(ForceChainsYield, LocusCrossesAxisAtRcAndIsClosedInCompression) {
  const fc::ForceChainParameters par;
  const fc::YieldFunctionDiPrisco f(par);
  const Eigen::Matrix3d chi = Eigen::Matrix3d::Identity() / std::sqrt(3.0);
  const double rc = 1e5, p_c = rc / std::sqrt(3.0);
  EXPECT_NEAR(f.value(p_c * Eigen::Matrix3d::Identity(), chi, rc), 0.0, 1e-14);
  // triaxial compression, isotropic axis: J2η = (2/3)η², J3η = (2/9)η³ (η = q/p), so the locus
  // is at ln(r/r_c) = -[(3/2)(γ-1)η² - (2/9)γη³] / (3β_f(γ-3)) (closed form)
  for (double eta : {0.3, 0.8, 1.25, 2.0}) {
    const double lhs = 1.5 * (par.gamma - 1) * eta * eta - 2.0 / 9.0 * par.gamma * eta * eta * eta;
    const double p = p_c * std::exp(-lhs / f.log_coefficient());
    const Eigen::Matrix3d s = diag(p + 2 * eta * p / 3, p - eta * p / 3, p - eta * p / 3);
    EXPECT_NEAR(f.value(s, chi, rc), 0.0, 1e-12) << eta;
  }
}

TEST(ForceChainsYield, LadeDuncanRatioAtEveryLodeAngle) {
  fc::ForceChainParameters par;
  par.M_c = 1.25;
  const fc::CriticalStateLadeDuncan cs(par);
  EXPECT_NEAR(cs.stress_ratio(1.0), 1.25, 1e-12);
  // at any Lode angle the computed M(θ) puts the stress on I1³/I3 = k_LD (independent check
  // through the principal stresses)
  for (double theta : {0.0, 0.3, 0.6, 0.9, M_PI / 3}) {
    const double m = cs.stress_ratio(std::cos(3 * theta));
    const double p = 1.0, q = m * p;
    double s1 = p + 2.0 / 3.0 * q * std::cos(theta),
           s2 = p + 2.0 / 3.0 * q * std::cos(theta - 2 * M_PI / 3),
           s3 = p + 2.0 / 3.0 * q * std::cos(theta + 2 * M_PI / 3);
    const double i1 = s1 + s2 + s3, i3 = s1 * s2 * s3;
    EXPECT_NEAR(i1 * i1 * i1 / i3, cs.lade_duncan_constant(), 1e-9) << theta;
    // and the invariant helper recovers cos3θ from the tensor
    EXPECT_NEAR(fc::lode_cos3theta(fc::deviator(diag(s1, s2, s3))), std::cos(3 * theta), 1e-12);
  }
  // extension is weaker than compression (Lade-Duncan: M_e/M_c ≈ 0.77 at M_c = 1.25; Mohr-
  // Coulomb would give 0.72, Drucker-Prager 1)
  const double ratio = cs.stress_ratio(-1.0) / 1.25;
  EXPECT_GT(ratio, 0.72);
  EXPECT_LT(ratio, 0.85);
}

TEST(ForceChainsYield, StressOnLocusAfterPlasticSteps) {
  const fc::ForceChainModel model{fc::ForceChainParameters{}};
  std::mt19937 rng(11);
  // random strain paths from a normally consolidated state; every plastic update must end on
  // the locus: |f| <= 1e-6. (f is dimensionless, O(1-10) across the locus; FTOL = 1e-8 is the
  // drift-correction target; 1e-6 leaves room for the last sub-step when the correction stops
  // improving.)
  int plastic = 0;
  for (int path = 0; path < 20; ++path) {
    auto s = model.isotropic_state(50e3 + 10e3 * path, 0.6 + 0.005 * path);
    Eigen::Matrix3d direction = symmetric(rng, 1.0);
    direction += 0.5 * Eigen::Matrix3d::Identity();  // mostly compressive: stays solid
    for (int i = 0; i < 50; ++i) {
      const auto info = model.update(s, 2e-4 * direction / direction.norm(), 1e-3, 0.0);
      if (s.fluidized) break;
      if (info.plastic) {
        ++plastic;
        EXPECT_LE(std::abs(info.yield_value), 1e-6) << "path " << path << " step " << i;
        EXPECT_NEAR(info.yield_value, model.yield_value(s), 1e-15);
      } else {
        EXPECT_LE(info.yield_value, model.parameters().yield_tolerance);
      }
    }
  }
  EXPECT_GT(plastic, 300);  // the paths do load the locus
}

TEST(ForceChainsYield, NoTensionTestAgreesWithPrincipalStresses) {
  // is_compressive (principal minors) against the smallest principal stress from the Lode
  // angle (two independent routes), on random symmetric tensors around the boundary σ_3 = 0
  std::mt19937 rng(5);
  int agree = 0, tested = 0;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Matrix3d s = 50.0 * Eigen::Matrix3d::Identity() + symmetric(rng, 60.0);
    const double smin = fc::minimum_principal_stress(s);
    if (std::abs(smin) < 1e-6 * s.norm()) continue;  // too close to call either way
    ++tested;
    agree += fc::is_compressive(s, 1e-12) == (smin > 0.0);
  }
  EXPECT_EQ(agree, tested);
  EXPECT_GT(tested, 1900);
  // and the σ_3 formula on a known case: triaxial compression p = 10, q = 30 gives σ_3 = 0
  EXPECT_NEAR(fc::minimum_principal_stress(diag(30, 0, 0)), 0.0, 1e-12);
  EXPECT_NEAR(fc::minimum_principal_stress(diag(3, 7, 5)), 3.0, 1e-12);
}
