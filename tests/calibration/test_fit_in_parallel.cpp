// Calibration of the in-parallel steady model (force chains on the critical state + kinetic
// theory, docs/model/steady_state.md) on synthetic data it generated with known Gaussian noise:
// noiseless recovery, 2-standard-error coverage of the critical-state parameters over seeds,
// χ²_red ≈ 1, and the cost of one fit.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "analysis/calibration/calibration.hpp"
#include "tests/calibration/synthetic_data.hpp"

namespace granflow::calibration {
namespace {

// Dry frictional spheres with a critical state line about 100 Pa.
CalibratedModel spheres(double restitution, double e_gamma, double m_c, double lambda_c) {
  CalibratedModel m = testing::dry_model(restitution, 0.60);
  m.settings.force_chains = true;
  auto& fc = m.settings.force_chain_parameters;
  fc.e_Gamma = e_gamma;
  fc.M_c = m_c;
  fc.lambda_c = lambda_c;
  fc.xi_c = 0.5;
  fc.atmospheric_pressure = 100;
  return m;
}

const std::vector<std::string> names = {"restitution", "critical_void_ratio",
                                        "critical_stress_ratio", "critical_state_slope"};
const std::vector<Observable> observables = {Observable::friction, Observable::solid_fraction,
                                             Observable::scaled_temperature};
const double truth_values[4] = {0.8, 0.70, 0.72, 0.02};

CalibratedModel truth() { return spheres(0.8, 0.70, 0.72, 0.02); }
CalibratedModel start() { return spheres(0.7, 0.69, 0.68, 0.01); }

TEST(CalibrationFitInParallel, NoiselessDataGiveTheTruth) {
  auto data = testing::synthetic_points(truth(), 1);
  for (auto& p : data) {
    const auto s = predict(truth(), p);
    p.value[0] = s.friction, p.value[1] = s.solid_fraction, p.value[2] = s.scaled_temperature;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const auto r = fit(start(), names, data, observables);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("4 parameters, 12 points: %.3f s, %d evaluations\n", seconds, r.evaluations);
  // LM tolerance 1e-12 relative and ν solved to rounding: the optimum is the truth to 1e-6.
  for (int j = 0; j < 4; ++j) EXPECT_NEAR(r.estimate[j] / truth_values[j], 1.0, 1e-6) << names[j];
  EXPECT_LT(r.chi2, 1e-8);
  EXPECT_TRUE(r.identifiable);
  EXPECT_LT(seconds, 5.0);  // the cost target of a 5-parameter, 12-point calibration
}

TEST(CalibrationFitInParallel, CriticalStateParametersCoveredWithinTwoStandardErrors) {
  constexpr int seeds = 16;
  int covered[4] = {0, 0, 0, 0};
  double chi2_red = 0;
  for (int seed = 1; seed <= seeds; ++seed) {
    const auto data = testing::synthetic_points(truth(), 2000u + unsigned(seed));
    const auto r = fit(start(), names, data, observables);
    ASSERT_TRUE(r.identifiable) << seed;
    for (int j = 0; j < 4; ++j)
      covered[j] += std::abs(r.estimate[j] - truth_values[j]) < 2 * r.standard_error[j];
    chi2_red += r.chi2_red / seeds;
  }
  // 2σ coverage is 95.4 % for a linear-Gaussian problem: out of 16, P(covered < 13) ≈ 0.7 %.
  for (int j = 0; j < 4; ++j) EXPECT_GE(covered[j], 13) << names[j];
  // Mean χ²_red over 16 draws of 32 dof: sd of the mean 0.25/4; within 1 ± 0.25 (4σ).
  EXPECT_NEAR(chi2_red, 1.0, 0.25);
}

}  // namespace
}  // namespace granflow::calibration

namespace granflow::calibration {
namespace {

TEST(CalibrationFitInParallel, NamedExtensionsCoveredWithinTwoStandardErrors) {
  // The two named extensions (contact production α_FC, friction rise Δμ_FC) with the critical
  // state: truth α_FC = 0.5, Δμ_FC = 0.3, e_Γ = 0.9, M_c = 0.75 (λ_c = 0.3, ξ_c = 1 fixed).
  const auto model = [](double e_gamma, double m_c, double alpha, double rise) {
    CalibratedModel m = spheres(0.7, e_gamma, m_c, 0.3);
    m.settings.force_chain_parameters.xi_c = 1.0;
    m.factors.contact_production = alpha;
    m.factors.friction_rise = rise;
    return m;
  };
  const std::vector<std::string> extension_names = {"critical_void_ratio", "critical_stress_ratio",
                                                    "contact_production", "friction_rise"};
  const double truth[4] = {0.9, 0.75, 0.5, 0.3};
  constexpr int seeds = 16;
  int covered[4] = {0, 0, 0, 0};
  for (int seed = 1; seed <= seeds; ++seed) {
    const auto data = testing::synthetic_points(model(0.9, 0.75, 0.5, 0.3), 3000u + unsigned(seed));
    const auto r = fit(model(0.85, 0.7, 0.3, 0.2), extension_names, data, observables);
    ASSERT_TRUE(r.identifiable) << seed;
    for (int j = 0; j < 4; ++j)
      covered[j] += std::abs(r.estimate[j] - truth[j]) < 2 * r.standard_error[j];
  }
  // As above: P(covered < 13 of 16) ≈ 0.7 % for a linear-Gaussian problem.
  for (int j = 0; j < 4; ++j) EXPECT_GE(covered[j], 13) << extension_names[j];
}

}  // namespace
}  // namespace granflow::calibration
