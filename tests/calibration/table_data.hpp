// Text tables for the calibration tests: the model of cases/calibrate/from_table.yaml, constant-
// volume rows it makes with Gaussian noise (the synthetic example table), and their CSV text.
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "analysis/calibration/calibrate_kind.hpp"
#include "analysis/calibration/calibration.hpp"

namespace granflow::calibration::testing {

inline std::filesystem::path example_case() {
  return std::filesystem::path(GRANFLOW_SOURCE_DIR) / "cases" / "calibrate" / "from_table.yaml";
}
// The fitted parameters of the example and the values the table was made with.
inline const std::vector<std::string> example_names = {
    "critical_void_ratio", "critical_state_slope", "critical_stress_ratio", "contact_production"};
inline const std::vector<double> example_truth = {0.80, 0.15, 0.748, 0.596};
inline const std::vector<Observable> example_observables = {
    Observable::friction, Observable::scaled_pressure, Observable::scaled_temperature};

// The example case's model (its start values) and the truth: the same with example_truth.
inline CalibratedModel example_start() {
  const auto schema = calibrate_schema();
  return read_case_model(core::Case::load(example_case(), {}, schema));
}
inline CalibratedModel example_truth_model() {
  return apply(example_start(), example_names,
               Eigen::Map<const Eigen::VectorXd>(example_truth.data(), 4));
}

// Noise of the synthetic rows: σ_μ = 0.005, σ_p/p = 2 %, σ_T*/T* = 4 % (T* has no error column:
// the case's floor). The stated errors are those fractions of the measured (noisy) values, as a
// DEM code's batch-means errors are estimated from its own samples.
constexpr double friction_sigma = 0.005, pressure_rel_sigma = 0.02, temperature_rel_sigma = 0.04;

// Constant-volume rows at γ̇ = d = ρ_p = 1: φ from 0.560 to 0.587 in `count` even steps, then
// `repeats` more draws at the 5th and 8th φ. value[1] is the imposed φ.
inline std::vector<DataPoint> constant_volume_rows(const CalibratedModel& truth, unsigned seed,
                                                   int count, int repeats = 0) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> phis;
  for (int i = 0; i < count; ++i) phis.push_back(0.560 + 0.027 * i / (count - 1));
  for (int i = 0; i < repeats; ++i) phis.push_back(phis[static_cast<std::size_t>(i % 2 ? 7 : 4)]);
  std::vector<DataPoint> out;
  for (std::size_t i = 0; i < phis.size(); ++i) {
    DataPoint p;
    p.protocol = Protocol::constant_volume;
    p.shear_rate = 1.0;
    p.particle_friction = NAN;
    p.value[1] = phis[i];
    const auto s = predict(truth, p);
    const double mu = s.friction + friction_sigma * normal(rng);
    const double pressure = s.scaled_pressure * (1 + pressure_rel_sigma * normal(rng));
    const double T = s.scaled_temperature * (1 + temperature_rel_sigma * normal(rng));
    p.value[0] = mu, p.error[0] = friction_sigma;
    p.value[2] = T, p.error[2] = 0.0, p.floor[2] = temperature_rel_sigma;
    p.value[3] = pressure, p.error[3] = pressure_rel_sigma * pressure;
    p.normal_stress = pressure;
    p.inertial_number = 1.0 / std::sqrt(pressure);
    p.row = static_cast<int>(i);
    out.push_back(p);
  }
  return out;
}

// The rows as the example's CSV (columns phi, p, p_err, mu, mu_err, T), values rounded as printed.
inline std::string constant_volume_csv(const std::vector<DataPoint>& rows, unsigned seed) {
  std::string out = fmt::format(
      "# SYNTHETIC constant-volume steady simple shear, dimensionless (d = rho_p = shear rate = 1),\n"
      "# made by granflow's forward model (steady_simple_shear_at_solid_fraction) with the truth of\n"
      "# cases/calibrate/from_table.yaml and Gaussian noise (seed {}): sigma_mu = {}, sigma_p/p = {},\n"
      "# sigma_T/T = {} (no T error column). Written by tests/calibration/test_table_protocols.cpp.\n"
      "# protocol: constant_volume\n"
      "# units: dimensionless\n"
      "phi,p,p_err,mu,mu_err,T\n",
      seed, friction_sigma, pressure_rel_sigma, temperature_rel_sigma);
  for (const auto& p : rows)
    out += fmt::format("{:.4f},{:.6g},{:.3g},{:.5f},{:.3g},{:.5g}\n", p.value[1], p.value[3],
                       p.error[3], p.value[0], p.error[0], p.value[2]);
  return out;
}

}  // namespace granflow::calibration::testing
