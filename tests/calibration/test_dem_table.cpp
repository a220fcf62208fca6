// DEM tables from any code (analysis/calibration/dem_table.hpp): a granflow DEM result.h5 written
// out as CSV calibrates exactly as the result.h5 itself; columns named otherwise, derived
// quantities and the error floor; every bad table is one line and exit 2 from the CLI.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "analysis/calibration/calibrate_kind.hpp"
#include "analysis/calibration/calibration.hpp"
#include "analysis/calibration/dem_table.hpp"
#include "core/result_file.hpp"
#include "tests/cli/granflow_child.hpp"

namespace granflow::calibration {
namespace {

namespace fs = std::filesystem;
const fs::path work = fs::path(GRANFLOW_BINARY_DIR) / "test_calibration_table";

// The in-parallel model of cases/calibrate/dry_mu_I.yaml with the shipped calibration's values
// (docs/calibration.md), as case text and as a model.
const char* model_sections =
    "material: {diameter: 1.0e-3, particle_density: 2500, restitution: 0.7, "
    "particle_friction: 0.5}\n"
    "collisional: {jamming_fraction: 0.59, radial_distribution: torquato}\n"
    "force_chains: {M_c: 0.75, e_Gamma: 1.07, lambda_c: 0.43, xi_c: 1.0, "
    "atmospheric_pressure: 100}\n"
    "steady: {contact_production: 0.59, friction_rise: 1.5, friction_rise_I0: 2}\n";

CalibratedModel sweep_truth() {
  CalibratedModel m;
  m.settings.collisional = m.settings.force_chains = true;
  auto& col = m.settings.collisional_parameters;
  col.diameter = 1e-3, col.particle_density = 2500, col.restitution = 0.7;
  col.particle_friction = 0.5, col.jamming_fraction = 0.5901;
  col.radial_distribution = model::RadialDistributionKind::torquato;
  auto& fc = m.settings.force_chain_parameters;
  fc.M_c = 0.748, fc.e_Gamma = 1.067, fc.lambda_c = 0.431, fc.xi_c = 1, fc.atmospheric_pressure = 100;
  m.factors.contact_production = 0.596, m.factors.friction_rise = 1.55;
  m.factors.friction_rise_I0 = 2;
  return m;
}

// A stand-in for the dry sweep's result.h5 (cases/dem/dry_sweep.yaml: μ_p = 0.5 and 0, γ̇ = 2 ...
// 60 1/s, σ_yy = 100 Pa with the servo's scatter) with every /steady column the DEM kind writes
// (dem_coupling/dem_kind.cpp), values from the forward model with DEM-sized noise. The repository
// ships no DEM run (runs/ is made by `granflow run`), so the test writes its own.
const std::vector<std::string> steady_columns = {
    "friction",           "friction_err",      "solid_fraction",        "solid_fraction_err",
    "void_ratio",         "void_ratio_err",    "granular_temperature",  "granular_temperature_err",
    "scaled_temperature", "normal_stress",     "normal_stress_err",     "mean_stress",
    "mean_stress_err",    "shear_stress",      "shear_stress_err",      "inertial_number",
    "inertial_number_err", "coordination_number", "coordination_number_err", "steady_start_strain",
    "steady_reached",     "drift_max",         "profile_deviation",     "shear_rate",
    "particle_friction",  "normal_stress_target", "time_step",          "wall_time"};

fs::path write_sweep_result(const fs::path& file) {
  fs::create_directories(file.parent_path());
  std::mt19937 rng(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::map<std::string, std::vector<double>> col;
  const double d = 1e-3, rho = 2500;
  for (double mu_p : {0.5, 0.0})
    for (double rate : {2.0, 4.0, 10.0, 20.0, 40.0, 60.0}) {
      CalibratedModel m = sweep_truth();
      m.settings.collisional_parameters.particle_friction = mu_p;
      DataPoint at;
      at.shear_rate = rate, at.normal_stress = 100 * (1 + 0.03 * normal(rng));
      const auto s = predict(m, at);
      const double mu = s.friction + 0.004 * normal(rng), phi = s.solid_fraction + 3e-4 * normal(rng);
      const double T = s.granular_temperature * (1 + 0.05 * normal(rng));
      const double p = at.normal_stress, I = rate * d / std::sqrt(p / rho);
      const std::map<std::string, double> row = {
          {"friction", mu}, {"friction_err", 0.004}, {"solid_fraction", phi},
          {"solid_fraction_err", 3e-4}, {"void_ratio", 1 / phi - 1},
          {"void_ratio_err", 3e-4 / (phi * phi)}, {"granular_temperature", T},
          {"granular_temperature_err", 0.05 * T}, {"scaled_temperature", T / std::pow(d * rate, 2)},
          {"normal_stress", p}, {"normal_stress_err", 0.01 * p}, {"mean_stress", 0.97 * p},
          {"mean_stress_err", 0.01 * p}, {"shear_stress", mu * p}, {"shear_stress_err", 0.004 * p},
          {"inertial_number", I}, {"inertial_number_err", 0.005 * I}, {"coordination_number", 3.5},
          {"coordination_number_err", 0.02}, {"steady_start_strain", 1.2}, {"steady_reached", 1},
          {"drift_max", 1.4}, {"profile_deviation", 0.01}, {"shear_rate", rate},
          {"particle_friction", mu_p}, {"normal_stress_target", 100}, {"time_step", 4e-6}, {"wall_time", 90}};
      for (const auto& [name, value] : row) col[name].push_back(value);
    }
  core::ResultFile f(file);
  for (const auto& name : steady_columns) f.write("/steady/" + name, col[name], "", name);
  f.attribute("/steady", "diameter", d);
  f.attribute("/steady", "particle_density", rho);
  f.attribute("/steady", "restitution", 0.7);
  f.attribute("/steady", "control", std::string("constant_pressure"));
  f.flush();
  return file;
}

// /steady of a granflow result.h5 as CSV, every column under its own name, 17 digits (the doubles
// round-trip exactly), the protocol and units as the table's comment lines.
fs::path export_csv(const fs::path& result, const fs::path& csv) {
  std::vector<std::vector<double>> columns;
  for (const auto& name : steady_columns) columns.push_back(core::read_dataset(result, "/steady/" + name));
  std::ofstream out(csv);
  out << "# /steady of " << result.filename().string() << "\n# protocol: "
      << core::read_string_attribute(result, "/steady", "control") << "\n# units: si\n";
  for (std::size_t j = 0; j < steady_columns.size(); ++j) out << (j ? "," : "") << steady_columns[j];
  out << "\n";
  for (std::size_t r = 0; r < columns.front().size(); ++r) {
    for (std::size_t j = 0; j < columns.size(); ++j)
      out << (j ? "," : "") << fmt::format("{:.17g}", columns[j][r]);
    out << "\n";
  }
  return csv;
}

// What run_calibrate_case does with a case (read_case_data, fit on the training rows, held-out
// errors), without its plots: the fit and the held-out relative errors.
const std::vector<std::string> fitted = {"jamming_fraction",      "critical_void_ratio",
                                         "critical_stress_ratio", "critical_state_slope",
                                         "contact_production",    "friction_rise"};
const std::vector<Observable> observables = {Observable::friction, Observable::solid_fraction,
                                             Observable::scaled_temperature};

struct Calibration {
  FitResult fit;
  std::vector<double> holdout;
  std::size_t rows = 0;
};

Calibration calibrate(const std::string& data_section, const std::string& name) {
  const auto schema = calibrate_schema();
  const std::string text = "kind: calibrate\nname: " + name + "\n" + model_sections +
                           "data: " + data_section +
                           "\nfit: {parameters: 'jamming_fraction critical_void_ratio "
                           "critical_stress_ratio critical_state_slope contact_production "
                           "friction_rise', starts: 2}\n";
  const auto c = core::Case::parse(text, (work / (name + ".yaml")).string(), {}, schema);
  check_calibrate_case(c);
  check_calibrate_data(c);
  const auto data = read_case_data(c);
  const auto start = read_case_model(c);
  Calibration out;
  out.fit = fit(start, fitted, data.training, observables, 4000, 2);
  const auto calibrated = apply(start, fitted, out.fit.estimate);
  for (const auto o : observables)
    out.holdout.push_back(mean_relative_error(calibrated, data.holdout, o));
  out.rows = data.used.size();
  return out;
}

TEST(DemTable, ResultFileWrittenAsCsvCalibratesExactlyAsTheResultFile) {
  const auto h5 = write_sweep_result(work / "sweep" / "result.h5");
  const auto csv = export_csv(h5, work / "sweep.csv");
  const std::string section = ", particle_friction: 0.5, observables: friction solid_fraction "
                              "scaled_temperature}";
  const auto a = calibrate("{files: '" + h5.string() + "'" + section, "from_h5");
  const auto b = calibrate("{table: '" + csv.string() + "'" + section, "from_csv");
  ASSERT_EQ(a.rows, 6u);  // the μ_p = 0.5 rows
  ASSERT_EQ(b.rows, 6u);
  double largest = 0;
  for (std::size_t j = 0; j < fitted.size(); ++j) {
    const auto i = static_cast<Eigen::Index>(j);
    EXPECT_NEAR(a.fit.estimate[i], b.fit.estimate[i], 1e-9) << fitted[j];
    EXPECT_NEAR(a.fit.standard_error[i], b.fit.standard_error[i], 1e-9) << fitted[j];
    largest = std::max({largest, std::abs(a.fit.estimate[i] - b.fit.estimate[i]),
                        std::abs(a.fit.standard_error[i] - b.fit.standard_error[i])});
  }
  EXPECT_NEAR(a.fit.chi2, b.fit.chi2, 1e-9 * a.fit.chi2);
  for (std::size_t k = 0; k < observables.size(); ++k)
    EXPECT_NEAR(a.holdout[k], b.holdout[k], 1e-12) << k;
  EXPECT_TRUE(a.fit.inside_domain);
  std::printf("result.h5 vs CSV: largest difference of estimates and errors %.3g; χ²_red %.3g\n",
              largest, a.fit.chi2_red);
  for (std::size_t j = 0; j < fitted.size(); ++j)
    std::printf("  %s = %.5g ± %.3g\n", fitted[j].c_str(), a.fit.estimate[static_cast<Eigen::Index>(j)],
                a.fit.standard_error[static_cast<Eigen::Index>(j)]);
}

// Columns named otherwise (data.columns), errors named otherwise (data.errors), and the
// quantities derived from the others: γ̇ from I and σ_yy, σ_yy from `pressure`, μ = τ/σ_yy.
TEST(DemTable, ColumnsMappedAndQuantitiesDerived) {
  fs::create_directories(work);
  const auto file = work / "derived.txt";
  std::ofstream(file) << "# a whitespace-separated table from another code\n"
                         "I   P     tau   dtau  phi    T\n"
                         "0.02  100   38.5  0.4   0.585  2.0e-6\n"
                         "0.2   100   47.0  0.5   0.555  4.0e-5\n";
  TableSpec spec;
  spec.file = file;
  spec.protocol = "constant_pressure";
  spec.columns = {{"inertial_number", "I"}, {"pressure", "P"}, {"shear_stress", "tau"},
                  {"solid_fraction", "phi"}, {"granular_temperature", "T"}};
  spec.errors = {{"shear_stress", "dtau"}};
  spec.diameter = 1e-3, spec.particle_density = 2500;
  const auto t = read_dem_table(spec);
  ASSERT_EQ(t.set.points.size(), 2u);
  const auto& p = t.set.points[1];
  EXPECT_NEAR(p.shear_rate, 0.2 * std::sqrt(100.0 / 2500) / 1e-3, 1e-9);  // 40 1/s
  EXPECT_EQ(p.normal_stress, 100);
  EXPECT_NEAR(p.value[0], 0.47, 1e-15);
  EXPECT_NEAR(p.error[0], 0.005, 1e-15);  // τ's relative error alone: P has none
  EXPECT_NEAR(p.value[2], 4e-5 / std::pow(1e-3 * 40, 2), 1e-12);
  EXPECT_EQ(p.error[1], 0.0);  // no φ error column
  EXPECT_EQ(p.line, 4);
  std::string derived;
  for (const auto& s : t.derived) derived += s + "; ";
  for (const char* what : {"shear_rate = inertial_number", "normal_stress = pressure",
                           "friction = shear_stress/normal_stress",
                           "scaled_temperature = granular_temperature"})
    EXPECT_NE(derived.find(what), std::string::npos) << derived;
}

// A table without error bars is refused unless data.error_floor gives the observables one; the
// floor adds in quadrature and the report states χ²_red both ways.
TEST(DemTable, TableWithoutErrorsNeedsAFloor) {
  const auto truth = sweep_truth();
  fs::create_directories(work);
  const auto file = work / "no_errors.csv";
  {
    std::ofstream out(file);
    out << "shear_rate,normal_stress,friction,solid_fraction,friction_err\n";
    for (double rate : {2.0, 4.0, 10.0, 20.0, 40.0, 60.0}) {
      DataPoint at;
      at.shear_rate = rate, at.normal_stress = 100;
      const auto s = predict(truth, at);
      out << fmt::format("{},100,{:.6f},{:.6f},0.004\n", rate, s.friction, s.solid_fraction);
    }
  }
  const auto schema = calibrate_schema();
  const std::string base = std::string("kind: calibrate\n") + model_sections +
                           "fit: {parameters: critical_void_ratio}\n"
                           "data: {table: '" + file.string() +
                           "', protocol: constant_pressure, observables: friction solid_fraction";
  const auto bare = core::Case::parse(base + "}\n", (work / "bare.yaml").string(), {}, schema);
  try {
    check_calibrate_data(bare);
    FAIL() << "a table without φ errors was accepted without a floor";
  } catch (const core::CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("data.error_floor.solid_fraction"), std::string::npos)
        << e.what();
  }
  const auto floored = core::Case::parse(
      base + ", error_floor: {solid_fraction: 0.002, friction: 0.01}}\n",
      (work / "floored.yaml").string(), {}, schema);
  const auto data = read_case_data(floored);
  const auto& p = data.used.front();
  EXPECT_NEAR(fit_error(p, Observable::friction),
              std::hypot(0.004, 0.01 * p.value[0]), 1e-15);
  EXPECT_NEAR(fit_error(p, Observable::solid_fraction), 0.002 * p.value[1], 1e-15);
  const auto own = chi2_at(read_case_model(floored), data.training,
                           {Observable::friction, Observable::solid_fraction}, true);
  EXPECT_EQ(own.residuals, 3);  // μ only has an error of its own (3 training rows)
}

}  // namespace
}  // namespace granflow::calibration
