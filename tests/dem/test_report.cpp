// `granflow report RUN_DIR` on DEM sweeps (analysis/report.cpp): the fits are re-derived from an
// existing result.h5 without LIGGGHTS, written to /fits and summary.json, and tabulated in
// report.md. The run directories are synthetic (a /steady table on known laws).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "analysis/report.hpp"
#include "core/kind_registry.hpp"
#include "core/result_file.hpp"
#include "core/run.hpp"
#include "dem_coupling/dem_kind.hpp"
#include "dem_coupling/kind/inertial_law_fit.hpp"
#include "dem_coupling/kind/mixed_number_law_fit.hpp"

namespace {

namespace fs = std::filesystem;
using namespace granflow;

fs::path fresh(const std::string& name) {
  const fs::path dir = fs::path(GRANFLOW_BINARY_DIR) / "test_dem_report" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  // The plot step is not under test here: a no-op interpreter keeps the test fast.
  setenv("GRANFLOW_PYTHON", "/bin/true", 1);
  return dir;
}

std::string read(const fs::path& file) {
  std::ifstream in(file);
  return {std::istreambuf_iterator<char>(in), {}};
}

// The registry `granflow report` uses, with the DEM kind (its report section re-derives fits).
const core::KindRegistry& dem_registry() {
  static const core::KindRegistry registry = [] {
    core::KindRegistry r;
    dem::register_dem_kinds(r);
    return r;
  }();
  return registry;
}

TEST(DemReport, DrySweepFitsAreRederivedFromResultH5) {
  const fs::path dir = fresh("dry");
  std::ofstream(dir / "case.yaml") << "kind: dem\nname: synthetic_dry\n";
  core::Summary before;
  before.set("sweep.count", 12);
  before.write(dir / "summary.json");
  {
    core::ResultFile h5(dir / "result.h5");
    std::vector<double> mp, I, Ie, mu, mue, phi, phie;
    for (double m : {0.5, 0.0})
      for (double i : {0.01, 0.02, 0.05, 0.1, 0.2, 0.3}) {
        mp.push_back(m);
        I.push_back(i);
        Ie.push_back(1e-3 * i);
        // Frictional: GDR MiDi; frictionless: Peyneau & Roux (the laws the fits choose).
        mu.push_back(m > 0 ? dem::inertial_friction_law(i, 0.37, 0.64, 0.28)
                           : 0.1 + 0.39 * std::pow(i, 0.42));
        mue.push_back(0.005);
        phi.push_back(m > 0 ? 0.587 - 0.25 * i : 0.639 - 0.15 * std::pow(i, 0.77));
        phie.push_back(0.001);
      }
    h5.write("/steady/particle_friction", mp, "1", "");
    h5.write("/steady/inertial_number", I, "1", "");
    h5.write("/steady/inertial_number_err", Ie, "1", "");
    h5.write("/steady/friction", mu, "1", "");
    h5.write("/steady/friction_err", mue, "1", "");
    h5.write("/steady/solid_fraction", phi, "1", "");
    h5.write("/steady/solid_fraction_err", phie, "1", "");
  }
  // Twice: the second run replaces /fits and the fit.* keys (idempotent).
  for (int pass = 0; pass < 2; ++pass) {
    const fs::path md = analysis::write_report(dir, dem_registry());
    const std::string text = read(md);
    EXPECT_NE(text.find("μ(I) and φ(I) fits"), std::string::npos) << text;
    EXPECT_NE(text.find("Chialvo"), std::string::npos) << text;
  }
  const auto s = core::Summary::read(dir / "summary.json");
  EXPECT_EQ(s.get("sweep.count"), 12);  // kept
  // Exact data: the fitted constants are those of the table (1e-6: LM tolerance, see
  // test_inertial_law_fit.cpp).
  EXPECT_NEAR(s.get("fit.mu_p_0p5.mu_s"), 0.37, 1e-6);
  EXPECT_NEAR(s.get("fit.frictionless.mu_0"), 0.10, 1e-6);
  EXPECT_NEAR(s.get("fit.frictionless.phi_rcp"), 0.639, 1e-6);
  EXPECT_EQ(s.get("fit.frictionless.phi_c"), s.get("fit.frictionless.phi_rcp"));  // I → 0 limit
  EXPECT_EQ(core::read_string_attribute(dir / "result.h5", "/fits/frictionless", "law"),
            "peyneau_roux");
  EXPECT_EQ(core::read_string_attribute(dir / "result.h5", "/fits/mu_p_0p5", "law"), "gdr_midi");
  EXPECT_NEAR(s.get("fit.mu_p_0p5.a"), 0.25, 1e-9);
  // /fits holds the same numbers as summary.json.
  EXPECT_EQ(core::read_number_attribute(dir / "result.h5", "/fits/mu_p_0p5", "mu_s"),
            s.get("fit.mu_p_0p5.mu_s"));
  EXPECT_EQ(core::read_dataset(dir / "result.h5", "/fits/frictionless/friction_residual").size(),
            6u);
  EXPECT_EQ(core::read_dataset(dir / "result.h5", "/steady/friction").size(), 12u);
}

TEST(DemReport, WetSweepWithoutTabulatedStressRatiosGetsThemFromTheSeries) {
  // A run written before /steady/friction_contact existed: the report takes τ_contact/σ_yy and
  // τ_lub/σ_yy from /conditions/N/series over the steady part (start_strain), and the earlier
  // Boyer-in-K α (fit.alpha with fit.alpha_rms) becomes fit.alpha_boyer.
  const fs::path dir = fresh("wet");
  std::ofstream(dir / "case.yaml") << "kind: dem\nname: synthetic_wet\n";
  core::Summary before;
  before.set("fit.alpha", 0.036);
  before.set("fit.alpha_rms", 0.148);
  before.set("fit.alpha_chi2_per_dof", 113);
  before.write(dir / "summary.json");
  const double law[4] = {0.38, 0.95, 0.02, 0.6};
  std::vector<double> mp, I, Ie, mu, mue, phi, phie, st, J, Je, contact_ratio;
  {
    core::ResultFile h5(dir / "result.h5");
    int n = 0;
    for (double i : {0.1, 0.05})
      for (double stokes : {0.1, 0.32, 1.0, 3.2, 10.0, 100.0}) {
        const double j = i * i / stokes, k = j + law[3] * i * i;
        mp.push_back(0.5), I.push_back(i), Ie.push_back(1e-4), st.push_back(stokes);
        J.push_back(j), Je.push_back(1e-3 * j);
        mu.push_back(dem::mixed_number_friction_law(k, law[0], law[1], law[2]));
        mue.push_back(0.01);
        phi.push_back(dem::mixed_number_solid_fraction_law(k, 0.585, 1.0));
        phie.push_back(0.001);
        // Series: before strain 1 a transient (ratio 2x), after it τ_contact = 0.9 μ σ_yy and
        // τ_lub = 0.1 μ σ_yy per sample, so the steady ratios are exactly 0.9 μ and 0.1 μ.
        std::vector<double> strain, sigma, tau_contact, tau_lub;
        for (int s = 0; s < 400; ++s) {
          strain.push_back(0.01 * s);
          sigma.push_back(100.0 + 5.0 * std::sin(0.37 * s));
          const double transient = strain.back() < 1.0 ? 2.0 : 1.0;
          tau_contact.push_back(transient * 0.9 * mu.back() * sigma.back());
          tau_lub.push_back(transient * 0.1 * mu.back() * sigma.back());
        }
        const std::string g = fmt::format("/conditions/{}", n++);
        h5.write(g + "/series/strain", strain, "1", "");
        h5.write(g + "/series/normal_stress", sigma, "Pa", "");
        h5.write(g + "/series/shear_stress_contact", tau_contact, "Pa", "");
        h5.write(g + "/series/shear_stress_lubrication", tau_lub, "Pa", "");
        h5.attribute(g + "/steady", "steady_start_strain", 1.0);
        contact_ratio.push_back(0.9 * mu.back());
      }
    for (const auto& [name, v] :
         {std::pair<const char*, const std::vector<double>*>{"particle_friction", &mp},
          {"inertial_number", &I},
          {"inertial_number_err", &Ie},
          {"friction", &mu},
          {"friction_err", &mue},
          {"solid_fraction", &phi},
          {"solid_fraction_err", &phie},
          {"stokes_number", &st},
          {"viscous_number", &J},
          {"viscous_number_err", &Je}})
      h5.write(std::string("/steady/") + name, *v, "1", "");
  }
  const std::string text = read(analysis::write_report(dir, dem_registry()));
  EXPECT_NE(text.find("Mixed number K = J + α I² (free fit)"), std::string::npos) << text;
  EXPECT_NE(text.find("contact and hydrodynamic parts"), std::string::npos) << text;
  const auto s = core::Summary::read(dir / "summary.json");
  EXPECT_EQ(s.get("fit.alpha_boyer"), 0.036);
  EXPECT_FALSE(s.contains("fit.alpha_rms"));
  // Exact data on the free law: α back to 1e-5 relative (LM tolerance).
  EXPECT_NEAR(s.get("fit.alpha"), law[3], 1e-5 * law[3]);
  for (int n = 0; n < 12; ++n)
    EXPECT_NEAR(s.get(fmt::format("boyer.mu_contact.{}", n)), contact_ratio[n],
                1e-12 * contact_ratio[n])
        << n;
  EXPECT_NEAR(core::read_number_attribute(dir / "result.h5", "/steady", "fitted_alpha"),
              s.get("fit.alpha"), 0.0);
}

TEST(DemReport, InterruptedSweepIsAnalysedFromItsFinishedConditions) {
  // A sweep killed before it wrote /steady and summary.json: the finished conditions' steady
  // attributes (/conditions/N/steady) are fitted; the one that stopped at strain 3 of 10 (killed
  // mid-run) is left out.
  const fs::path dir = fresh("interrupted");
  std::ofstream(dir / "case.yaml") << "kind: dem\nname: killed\nstrain:\n  total: 10\n";
  {
    core::ResultFile h5(dir / "result.h5");
    int n = 0;
    for (double i : {0.01, 0.02, 0.05, 0.1, 0.2, 0.3, 0.15}) {
      const std::string g = fmt::format("/conditions/{}", n++);
      h5.attribute(g, "particle_friction", 0.5);
      h5.attribute(g + "/steady", "inertial_number", i);
      h5.attribute(g + "/steady", "inertial_number_err", 1e-3 * i);
      h5.attribute(g + "/steady", "friction", dem::inertial_friction_law(i, 0.37, 0.64, 0.28));
      h5.attribute(g + "/steady", "friction_err", 0.005);
      h5.attribute(g + "/steady", "solid_fraction", 0.587 - 0.25 * i);
      h5.attribute(g + "/steady", "solid_fraction_err", 0.001);
      h5.attribute(g + "/steady", "steady_end_strain", i == 0.15 ? 3.0 : 10.0);
    }
  }
  const std::string text = read(analysis::write_report(dir, dem_registry()));
  EXPECT_NE(text.find("μ(I) and φ(I) fits"), std::string::npos) << text;
  const auto s = core::Summary::read(dir / "summary.json");
  EXPECT_EQ(s.get("fit.mu_p_0p5.points"), 6);
  EXPECT_NEAR(s.get("fit.mu_p_0p5.mu_s"), 0.37, 1e-6);             // exact data, LM tolerance
  EXPECT_EQ(s.get("fit.mu_p_0p5.mu_s_published_deviation"), 0.0);  // inside 0.35-0.38
}

TEST(DemReport, NotADemResultFileIsNamed) {
  const fs::path dir = fresh("not_dem");
  std::ofstream(dir / "case.yaml") << "kind: dem\nname: broken\n";
  core::Summary().write(dir / "summary.json");
  { core::ResultFile h5(dir / "result.h5"); }
  try {
    analysis::write_report(dir, dem_registry());
    FAIL() << "expected an error naming /steady/particle_friction";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("/steady/particle_friction"), std::string::npos)
        << e.what();
  }
}

}  // namespace
