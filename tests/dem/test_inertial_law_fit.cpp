// The rheology fits of DEM sweeps (dem_coupling/kind/): weighted least squares
// (statistics/least_squares.hpp), μ(I) and φ(I) with the law chosen per friction (GDR MiDi for
// frictional, Peyneau & Roux for frictionless spheres), the free mixed-number law μ(K)
// with α and Boyer's contact/hydrodynamic split. Synthetic data with known parameters
// and Gaussian noise of known σ.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "statistics/least_squares.hpp"
#include "dem_coupling/kind/dem_fits.hpp"
#include "dem_coupling/kind/inertial_law_fit.hpp"
#include "dem_coupling/kind/mixed_number_law_fit.hpp"

namespace {

using namespace granflow::dem;
using granflow::statistics::weighted_least_squares;
using granflow::statistics::weighted_line;

// The dry sweep's inertial numbers (cases/dem/dry_sweep.yaml) plus two.
const std::vector<double> sweep_inertial = {0.01, 0.02, 0.05, 0.1, 0.2, 0.3, 0.03, 0.15};

TEST(DemWeightedLeastSquares, StraightLineByLevenbergMarquardtEqualsTheClosedForm) {
  // φ(I) = φ_c − a I: the closed form (Numerical Recipes §15.2) and the general LM fit of the
  // same linear model minimise the same quadratic χ²; estimates and (Jᵀ W J)⁻¹ standard errors
  // agree to the LM tolerance (1e-12 relative steps) and the 1e-5 finite-difference Jacobian
  // (exact for a linear model up to round-off): 1e-7 relative.
  const std::vector<double> phi = {0.585, 0.581, 0.574, 0.561, 0.535, 0.512, 0.579, 0.548};
  const std::vector<double> err = {0.0004, 0.0006, 0.0005, 0.0008, 0.001, 0.0012, 0.0005, 0.0009};
  const LineFit line = weighted_line(sweep_inertial, phi, err);
  Eigen::VectorXd start(2);
  start << 0.5, 0.0;
  const LeastSquaresFit lm = weighted_least_squares(
      [&](std::size_t i, const Eigen::VectorXd& t) { return t[0] + t[1] * sweep_inertial[i]; }, phi,
      err, start);
  ASSERT_TRUE(lm.converged);
  EXPECT_NEAR(lm.estimate[0], line.intercept, 1e-7 * std::abs(line.intercept));
  EXPECT_NEAR(lm.estimate[1], line.slope, 1e-7 * std::abs(line.slope));
  EXPECT_NEAR(lm.standard_error[0], line.intercept_err, 1e-7 * line.intercept_err);
  EXPECT_NEAR(lm.standard_error[1], line.slope_err, 1e-7 * line.slope_err);
  EXPECT_NEAR(lm.covariance(0, 1), line.covariance, 1e-7 * std::abs(line.covariance));
  EXPECT_NEAR(lm.chi2, line.chi2, 1e-7 * line.chi2);
  EXPECT_EQ(line.dof, 6);
  // Unweighted check of the closed form itself on three collinear points: exact line, χ² = 0.
  const LineFit exact = weighted_line({0.0, 1.0, 2.0}, {1.0, 0.5, 0.0}, {1.0, 1.0, 1.0});
  EXPECT_NEAR(exact.intercept, 1.0, 1e-15);
  EXPECT_NEAR(exact.slope, -0.5, 1e-15);
  EXPECT_NEAR(exact.chi2, 0.0, 1e-28);
  // var(intercept) = S_xx/Δ = 5/(3·5 − 9) = 5/6, var(slope) = S/Δ = 3/6.
  EXPECT_NEAR(exact.intercept_err, std::sqrt(5.0 / 6.0), 1e-15);
  EXPECT_NEAR(exact.slope_err, std::sqrt(0.5), 1e-15);
}

TEST(DemInertialLawFit, ExactDataGiveTheParametersBack) {
  const double mu_s = 0.36, mu_2 = 0.66, i_0 = 0.25, phi_c = 0.587, a = 0.25;
  std::vector<double> mu, mue, phi, phie;
  for (double I : sweep_inertial) {
    mu.push_back(inertial_friction_law(I, mu_s, mu_2, i_0));
    mue.push_back(0.005);
    phi.push_back(phi_c - a * I);
    phie.push_back(0.001);
  }
  const InertialLawFit f = fit_inertial_law(0.5, sweep_inertial, mu, mue, phi, phie);
  // Noise-free data: the LM minimum is χ² = 0 to its tolerances; 1e-6 relative is far above them.
  EXPECT_NEAR(f.mu_s(), mu_s, 1e-6);
  EXPECT_NEAR(f.mu_2(), mu_2, 1e-6);
  EXPECT_NEAR(f.i_0(), i_0, 1e-6);
  EXPECT_NEAR(f.phi_c(), phi_c, 1e-12);
  EXPECT_NEAR(f.a(), a, 1e-10);
  EXPECT_LT(f.mu.chi2, 1e-12);
  EXPECT_EQ(f.mu.dof, 5);
  // μ_s = 0.36 lies in Chialvo et al.'s 0.35-0.38 and φ_c on their 0.587: zero deviations
  // (φ_c exact to round-off over its SE of ~1e-3).
  EXPECT_EQ(f.mu_s_published_deviation(), 0.0);
  EXPECT_NEAR(f.phi_c_published_deviation(), 0.0, 1e-9);
  // The same data labelled frictionless (fitted with the same law): μ_s = 0.36 is far above
  // Peyneau & Roux's 0.10.
  const InertialLawFit g =
      fit_inertial_law(0.0, DryLaw::gdr_midi, sweep_inertial, mu, mue, phi, phie);
  EXPECT_NEAR(g.mu_s_published_deviation(), (0.36 - 0.10) / g.mu_s_err(), 1e-6 / g.mu_s_err());
  // 0.587 vs 0.639's rounding interval [0.6385, 0.6395]: (0.587 - 0.6385)/SE.
  EXPECT_NEAR(g.phi_c_published_deviation(), (0.587 - 0.6385) / g.phi_c_err(), 1e-9);
  EXPECT_LT(g.phi_c_published_deviation(), -10.0);  // SE ~1e-3
  // The quoted 0.587 stands for [0.5865, 0.5875]: 0.5877 ± 0.0002 is 1 SE above it, 0.5874
  // inside (zero), 0.5860 ± 0.0002 2.5 SE below.
  for (const auto& [shift, deviation] :
       std::vector<std::pair<double, double>>{{0.0007, 1.0}, {0.0004, 0.0}, {-0.0010, -2.5}}) {
    std::vector<double> shifted(phi), narrow(phie.size(), 0.0);
    for (double& v : shifted) v += shift;
    // error bars that give SE(φ_c) = 0.0002 exactly: scale the 0.001 ones by 0.0002/SE
    const double scale = 0.0002 / f.phi_c_err();
    for (std::size_t k = 0; k < phie.size(); ++k) narrow[k] = phie[k] * scale;
    const InertialLawFit h = fit_inertial_law(0.5, sweep_inertial, mu, mue, shifted, narrow);
    EXPECT_NEAR(h.phi_c_err(), 0.0002, 1e-9);
    EXPECT_NEAR(h.phi_c_published_deviation(), deviation, 1e-6) << "shift " << shift;
  }
  EXPECT_EQ(friction_label(0.5), "mu_p_0p5");
  EXPECT_EQ(friction_label(0.0), "frictionless");
}

TEST(DemInertialLawFit, NoisyDataRecoverTheParametersWithin2StandardErrors) {
  // 400 synthetic sweeps with Gaussian noise of the stated σ (μ: 0.006, φ: 0.0008, the sizes of
  // the DEM error bars): each parameter must lie within 2 SE of the truth in about 95 % of them
  // (Gaussian coverage of a nearly linear model). Binomial spread of a 95 % rate over 400 trials
  // is 1.1 %, and the μ(I) law is non-linear in I_0: accept 90-99 %. The mean χ²_red is 1 with a
  // spread sqrt(2/dof/400) = 0.03 (μ, 5 dof) and 0.029 (φ, 6 dof): accept ±0.15.
  const double truth_mu[] = {0.37, 0.64, 0.28};
  const double phi_c = 0.587, a = 0.26;
  std::mt19937 rng(20261122);
  std::normal_distribution<double> gauss(0.0, 1.0);
  int inside_mu[3] = {0, 0, 0}, inside_phi[2] = {0, 0};
  double chi2_mu = 0, chi2_phi = 0;
  const int trials = 400;
  for (int trial = 0; trial < trials; ++trial) {
    std::vector<double> mu, mue, phi, phie;
    for (double I : sweep_inertial) {
      mu.push_back(inertial_friction_law(I, truth_mu[0], truth_mu[1], truth_mu[2]) +
                   0.006 * gauss(rng));
      mue.push_back(0.006);
      phi.push_back(phi_c - a * I + 0.0008 * gauss(rng));
      phie.push_back(0.0008);
    }
    const InertialLawFit f = fit_inertial_law(0.5, sweep_inertial, mu, mue, phi, phie);
    ASSERT_TRUE(f.mu.identifiable) << trial;
    for (int j = 0; j < 3; ++j)
      inside_mu[j] += std::abs(f.mu.estimate[j] - truth_mu[j]) <= 2 * f.mu.standard_error[j];
    inside_phi[0] += std::abs(f.phi_c() - phi_c) <= 2 * f.phi_c_err();
    inside_phi[1] += std::abs(f.a() - a) <= 2 * f.a_err();
    chi2_mu += f.mu.chi2_red / trials;
    chi2_phi += f.phi.chi2_red / trials;
  }
  for (int j = 0; j < 3; ++j) {
    EXPECT_GE(inside_mu[j], 0.90 * trials) << "μ parameter " << j;
    EXPECT_LE(inside_mu[j], 0.99 * trials) << "μ parameter " << j;
  }
  for (int j = 0; j < 2; ++j) {
    EXPECT_GE(inside_phi[j], 0.90 * trials) << "φ parameter " << j;
    EXPECT_LE(inside_phi[j], 0.99 * trials) << "φ parameter " << j;
  }
  EXPECT_NEAR(chi2_mu, 1.0, 0.15);
  EXPECT_NEAR(chi2_phi, 1.0, 0.15);
}

TEST(DemInertialLawFit, FailedPointsAreSkippedAndGroupsSplitByFriction) {
  // A sweep table with two frictions and one failed (NaN) row: one fit per μ_p, the NaN row left
  // out, and the frictional group compared with Chialvo et al.'s published values.
  DemSteadyTable t;
  for (double mp : {0.5, 0.0})
    for (double I : {0.01, 0.02, 0.05, 0.1, 0.2, 0.3}) {
      t.particle_friction.push_back(mp);
      t.inertial.push_back(I);
      t.inertial_err.push_back(0.001 * I);
      t.friction.push_back(mp > 0 ? inertial_friction_law(I, 0.37, 0.64, 0.3)
                                  : 0.10 + 0.39 * std::pow(I, 0.42));
      t.friction_err.push_back(0.005);
      t.solid_fraction.push_back(mp > 0 ? 0.587 - 0.2 * I : 0.639 - 0.15 * std::pow(I, 0.77));
      t.solid_fraction_err.push_back(0.001);
    }
  t.friction[3] = NAN;  // failed condition: μ_p = 0.5, I = 0.1
  const DemFits f = compute_dem_fits(t);
  ASSERT_EQ(f.dry.size(), 2u);
  // std::set order: 0 first.
  EXPECT_EQ(f.dry[0].particle_friction, 0.0);
  EXPECT_EQ(f.dry[0].inertial.size(), 6u);
  EXPECT_EQ(f.dry[1].inertial.size(), 5u);
  EXPECT_NEAR(f.dry[1].mu_s(), 0.37, 1e-6);  // exact data (tolerance as above)
  // The law by friction: Peyneau & Roux for μ_p = 0, GDR MiDi for μ_p = 0.5.
  EXPECT_EQ(f.dry[0].law, DryLaw::peyneau_roux);
  EXPECT_EQ(f.dry[1].law, DryLaw::gdr_midi);
  EXPECT_NEAR(f.dry[0].mu_s(), 0.10, 1e-6);    // μ_0, exact data (LM tolerance)
  EXPECT_NEAR(f.dry[0].phi_c(), 0.639, 1e-6);  // φ_RCP
  const auto summary = dem_fit_summary(f, t);
  EXPECT_NEAR(summary.at("fit.mu_p_0p5.mu_s"), 0.37, 1e-6);
  EXPECT_EQ(summary.at("fit.frictionless.points"), 6);
  EXPECT_EQ(summary.at("fit.frictionless.law_peyneau_roux"), 1.0);
  EXPECT_EQ(summary.at("fit.mu_p_0p5.law_peyneau_roux"), 0.0);
  EXPECT_NEAR(summary.at("fit.frictionless.alpha"), 0.42, 1e-5);
  EXPECT_NEAR(summary.at("fit.frictionless.beta"), 0.77, 1e-5);
  EXPECT_EQ(summary.at("fit.frictionless.mu_0"), summary.at("fit.frictionless.mu_s"));
  EXPECT_EQ(summary.count("fit.frictionless.I_0"), 0u);
  // The log line names the law and its parameters.
  const std::string line = dry_fit_log_line(f.dry[0]);
  EXPECT_NE(line.find("peyneau_roux"), std::string::npos) << line;
  EXPECT_NE(line.find("phi_rcp = 0.639"), std::string::npos) << line;
  ASSERT_TRUE(published_dem_law(0.5).has_value());
  EXPECT_EQ(published_dem_law(0.5)->phi_c, 0.587);
  EXPECT_FALSE(published_dem_law(0.3).has_value());
}

TEST(DemDryLaw, SelectedByNameAndByFriction) {
  EXPECT_EQ(dry_law_from_name("gdr_midi"), DryLaw::gdr_midi);
  EXPECT_EQ(dry_law_from_name("peyneau_roux"), DryLaw::peyneau_roux);
  EXPECT_STREQ(dry_law_name(DryLaw::peyneau_roux), "peyneau_roux");
  EXPECT_THROW(dry_law_from_name("midi"), std::invalid_argument);
  EXPECT_EQ(dry_law_for_friction(0.0), DryLaw::peyneau_roux);
  EXPECT_EQ(dry_law_for_friction(0.1), DryLaw::gdr_midi);
  EXPECT_EQ(dry_law_for_friction(0.5), DryLaw::gdr_midi);
  // The closed forms at I = 0.25: μ_0 + c I^α = 0.1 + 0.4 · 0.5 (α = 0.5); φ_RCP − b I = 0.6 −
  // 0.05.
  EXPECT_NEAR(PeyneauRouxLaw::friction(0.25, Eigen::Vector3d(0.1, 0.4, 0.5)), 0.3, 1e-15);
  EXPECT_NEAR(PeyneauRouxLaw::solid_fraction(0.25, Eigen::Vector3d(0.6, 0.2, 1.0)), 0.55, 1e-15);
}

// Frictionless sweep points (the dry sweep's I) on the Peyneau & Roux law with the constants the
// full dry sweep gave (docs/dem_dataset.md): μ = 0.10 + 0.39 I^0.43, φ = 0.639 − 0.154 I^0.78.
constexpr double pr_mu[3] = {0.10, 0.39, 0.43}, pr_phi[3] = {0.639, 0.154, 0.78};

TEST(DemPeyneauRouxFit, ExactDataGiveTheParametersBack) {
  std::vector<double> mu, mue, phi, phie;
  for (double I : sweep_inertial) {
    mu.push_back(pr_mu[0] + pr_mu[1] * std::pow(I, pr_mu[2]));
    mue.push_back(0.002);
    phi.push_back(pr_phi[0] - pr_phi[1] * std::pow(I, pr_phi[2]));
    phie.push_back(0.0003);
  }
  const InertialLawFit f = fit_inertial_law(0.0, sweep_inertial, mu, mue, phi, phie);
  ASSERT_EQ(f.law, DryLaw::peyneau_roux);
  ASSERT_TRUE(f.mu.converged && f.phi.converged);
  // Noise-free data: χ² = 0 at the truth; 1e-6 relative is far above the LM tolerances (1e-12).
  for (int j = 0; j < 3; ++j) {
    EXPECT_NEAR(f.mu_value(j), pr_mu[j], 1e-6 * pr_mu[j]) << j;
    EXPECT_NEAR(f.phi_value(j), pr_phi[j], 1e-6 * pr_phi[j]) << j;
  }
  EXPECT_EQ(f.mu.dof, 5);
  EXPECT_FALSE(f.mu.at_bound || f.phi.at_bound);
  // μ_0 = 0.10 and φ_RCP = 0.639 are the published values: zero deviations (both to 1e-6 over
  // SEs of ~1e-3 and ~5e-4 is < 0.01 SE).
  EXPECT_NEAR(f.mu_s_published_deviation(), 0.0, 0.01);
  EXPECT_NEAR(f.phi_c_published_deviation(), 0.0, 0.01);
  // GDR MiDi-only accessors are NaN for this law.
  EXPECT_TRUE(std::isnan(f.i_0()) && std::isnan(f.a()));
  // The fitted curves pass through the points.
  EXPECT_NEAR(f.friction_at(0.1), mu[3], 1e-9);
  EXPECT_NEAR(f.solid_fraction_at(0.1), phi[3], 1e-9);
}

TEST(DemPeyneauRouxFit, NoisyDataRecoverTheParametersWithin2StandardErrors) {
  // 300 synthetic frictionless sweeps with Gaussian noise of the DEM error bars' size (μ: 0.002,
  // φ: 0.0003, as the full dry sweep): each parameter within 2 SE of the truth in about 95 % of
  // them. Binomial spread of 95 % over 300 trials is 1.3 %; the power laws are non-linear in α
  // and β (so the Gaussian interval is approximate): accept 88-99 %. Mean χ²_red = 1 with a
  // spread sqrt(2/5/300) = 0.037: accept ±0.15.
  std::mt19937 rng(894);
  std::normal_distribution<double> gauss(0.0, 1.0);
  int inside_mu[3] = {0, 0, 0}, inside_phi[3] = {0, 0, 0};
  double chi2_mu = 0, chi2_phi = 0;
  const int trials = 300;
  for (int trial = 0; trial < trials; ++trial) {
    std::vector<double> mu, mue, phi, phie;
    for (double I : sweep_inertial) {
      mu.push_back(pr_mu[0] + pr_mu[1] * std::pow(I, pr_mu[2]) + 0.002 * gauss(rng));
      mue.push_back(0.002);
      phi.push_back(pr_phi[0] - pr_phi[1] * std::pow(I, pr_phi[2]) + 0.0003 * gauss(rng));
      phie.push_back(0.0003);
    }
    const InertialLawFit f = fit_inertial_law(0.0, sweep_inertial, mu, mue, phi, phie);
    ASSERT_TRUE(f.mu.identifiable && f.phi.identifiable) << trial;
    for (int j = 0; j < 3; ++j) {
      inside_mu[j] += std::abs(f.mu_value(j) - pr_mu[j]) <= 2 * f.mu_error(j);
      inside_phi[j] += std::abs(f.phi_value(j) - pr_phi[j]) <= 2 * f.phi_error(j);
    }
    chi2_mu += f.mu.chi2_red / trials;
    chi2_phi += f.phi.chi2_red / trials;
  }
  for (int j = 0; j < 3; ++j) {
    EXPECT_GE(inside_mu[j], 0.88 * trials) << "μ parameter " << j;
    EXPECT_LE(inside_mu[j], 0.99 * trials) << "μ parameter " << j;
    EXPECT_GE(inside_phi[j], 0.88 * trials) << "φ parameter " << j;
    EXPECT_LE(inside_phi[j], 0.99 * trials) << "φ parameter " << j;
  }
  EXPECT_NEAR(chi2_mu, 1.0, 0.15);
  EXPECT_NEAR(chi2_phi, 1.0, 0.15);
}

TEST(DemPeyneauRouxFit, GdrMidiFormMissesPowerLawDataThatPeyneauRouxFits) {
  // The reason for the per-friction choice: on noise-free power-law data with the DEM error bars,
  // the GDR MiDi form (regular at I = 0) leaves χ²_red far above 1 (the real sweep: 8 and 52),
  // the Peyneau & Roux form fits exactly. 5: far outside the χ²_red spread of 5 dof (0.63).
  std::vector<double> mu, mue, phi, phie;
  for (double I : sweep_inertial) {
    mu.push_back(pr_mu[0] + pr_mu[1] * std::pow(I, pr_mu[2]));
    mue.push_back(0.002);
    phi.push_back(pr_phi[0] - pr_phi[1] * std::pow(I, pr_phi[2]));
    phie.push_back(0.0003);
  }
  const InertialLawFit midi =
      fit_inertial_law(0.0, DryLaw::gdr_midi, sweep_inertial, mu, mue, phi, phie);
  EXPECT_GT(midi.phi.chi2_red, 5.0);
  const InertialLawFit pr = fit_inertial_law(0.0, sweep_inertial, mu, mue, phi, phie);
  EXPECT_LT(pr.mu.chi2_red, 1e-6);
  EXPECT_LT(pr.phi.chi2_red, 1e-6);
}

// 12 conditions as cases/dem/wet_sweep.yaml: I = 0.1 and 0.05, St = 0.1 ... 100, J = I²/St.
struct WetSweep {
  std::vector<double> j, i, mu, mue, phi, phie;
};
WetSweep synthetic_wet_sweep(const double law[4], double phi_m, double b, double noise_mu,
                             double noise_phi, std::mt19937* rng) {
  WetSweep w;
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (double I : {0.1, 0.05})
    for (double st : {0.1, 0.32, 1.0, 3.2, 10.0, 100.0}) {
      const double j = I * I / st, k = j + law[3] * I * I;
      w.j.push_back(j);
      w.i.push_back(I);
      w.mu.push_back(mixed_number_friction_law(k, law[0], law[1], law[2]) +
                     (rng ? noise_mu * gauss(*rng) : 0.0));
      w.mue.push_back(noise_mu);
      w.phi.push_back(mixed_number_solid_fraction_law(k, phi_m, b) +
                      (rng ? noise_phi * gauss(*rng) : 0.0));
      w.phie.push_back(noise_phi);
    }
  return w;
}

TEST(DemMixedNumberLawFit, ExactDataGiveMu1Mu2K0AndAlphaBack) {
  const double law[4] = {0.38, 0.95, 0.02, 0.6};
  const WetSweep w = synthetic_wet_sweep(law, 0.585, 1.0, 0.01, 0.001, nullptr);
  const MixedNumberLawFit f = fit_mixed_number_law(w.j, w.i, w.mu, w.mue, w.phi, w.phie);
  ASSERT_EQ(f.viscous.size(), 12u);
  // Noise-free data: the minimum is χ² = 0; 1e-5 relative is far above the LM tolerances.
  for (int j = 0; j < 4; ++j) EXPECT_NEAR(f.value(j), law[j], 1e-5 * law[j]) << j;
  ASSERT_EQ(f.phi.estimate.size(), 2);
  EXPECT_NEAR(f.phi.estimate[0], 0.585, 1e-6);
  EXPECT_NEAR(f.phi.estimate[1], 1.0, 1e-5);
  EXPECT_EQ(f.mu.dof, 8);
}

TEST(DemMixedNumberLawFit, NoisyDataRecoverAlphaWithin2StandardErrors) {
  // 200 synthetic wet sweeps, μ noise 0.01 (the DEM error bars of the viscous points): α and μ_1
  // within 2 SE in about 95 % of them. Binomial spread over 200 trials is 1.5 %; the law is
  // non-linear in α and K_0: accept 88-99 %.
  const double law[4] = {0.38, 0.95, 0.02, 0.6};
  std::mt19937 rng(5);
  int inside_alpha = 0, inside_mu_1 = 0;
  const int trials = 200;
  for (int trial = 0; trial < trials; ++trial) {
    const WetSweep w = synthetic_wet_sweep(law, 0.585, 1.0, 0.01, 0.001, &rng);
    const MixedNumberLawFit f = fit_mixed_number_law(w.j, w.i, w.mu, w.mue, w.phi, w.phie);
    ASSERT_TRUE(f.mu.identifiable) << trial;
    inside_alpha += std::abs(f.alpha() - law[3]) <= 2 * f.alpha_err();
    inside_mu_1 += std::abs(f.value(0) - law[0]) <= 2 * f.error(0);
  }
  EXPECT_GE(inside_alpha, 0.88 * trials);
  EXPECT_LE(inside_alpha, 0.99 * trials);
  EXPECT_GE(inside_mu_1, 0.88 * trials);
  EXPECT_LE(inside_mu_1, 0.99 * trials);
}

TEST(DemBoyerSplit, ContactPartOnBoyersLawHasZeroResidualAndTheLubricationShareIsItsRatio) {
  // A wet table whose τ_contact/σ_yy is exactly μ_c(J) and whose τ_lub/σ_yy is half of μ_h(J):
  // residuals 0, Σ res²/n = 0 over the St <= 1 points, lubrication share 0.5.
  DemSteadyTable t;
  t.wet = true;
  for (double st : {0.1, 0.32, 1.0, 3.2, 10.0, 100.0}) {
    const double I = 0.1, j = I * I / st;
    t.particle_friction.push_back(0.5);
    t.inertial.push_back(I);
    t.inertial_err.push_back(1e-4);
    t.stokes.push_back(st);
    t.viscous.push_back(j);
    t.viscous_err.push_back(0.0);
    t.friction_contact.push_back(boyer2011::contact_friction(j));
    t.friction_contact_err.push_back(0.01);
    t.friction_lubrication.push_back(0.5 * boyer2011::hydrodynamic_friction(j));
    t.friction_lubrication_err.push_back(0.001);
    t.friction.push_back(t.friction_contact.back() + t.friction_lubrication.back());
    t.friction_err.push_back(0.01);
    t.solid_fraction.push_back(boyer2011::solid_fraction(j));
    t.solid_fraction_err.push_back(0.001);
  }
  const DemFits f = compute_dem_fits(t);
  EXPECT_EQ(f.split.viscous_points, 3);  // St = 0.1, 0.32, 1
  EXPECT_NEAR(f.split.contact_chi2_per_point, 0.0, 1e-20);
  EXPECT_NEAR(f.split.lubrication_share_of_hydrodynamic, 0.5, 1e-14);
  // Boyer's law at J0: μ_c = μ1 + (μ2 − μ1)/2 (closed form).
  EXPECT_NEAR(boyer2011::contact_friction(0.005), 0.32 + 0.19, 1e-15);
  const auto summary = dem_fit_summary(f, t);
  EXPECT_NEAR(summary.at("boyer.mu_c.0"), boyer2011::contact_friction(0.1), 1e-15);
  EXPECT_NEAR(summary.at("boyer.contact_residual.2"), 0.0, 1e-12);
}

TEST(DemStressRatio, RatioOfMeansAndDeltaMethodError) {
  // part = 0.4 σ exactly per sample: ratio 0.4, residual part − 0.4 σ ≡ 0, so zero error.
  std::vector<double> sigma, part;
  for (int i = 0; i < 400; ++i) {
    sigma.push_back(100.0 + 10.0 * std::sin(0.1 * i));
    part.push_back(0.4 * sigma.back());
  }
  const StressRatio r = stress_ratio_of_series(part, sigma, 100);
  EXPECT_NEAR(r.value, 0.4, 1e-14);
  EXPECT_NEAR(r.error, 0.0, 1e-14);
}

}  // namespace
