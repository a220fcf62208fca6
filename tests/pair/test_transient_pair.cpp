// kind: transient_pair end to end: a 250-sphere loose packing prepared at p0 = 100 Pa with the
// shearing friction (kind: dem_prepare), then sheared undrained from rest in the DEM and in the
// REV from the same φ0, p0 and γ̇ (I0 = 0.01) over 0.3 strain (~20-40 s in all).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "analysis/calibration/steady_shear_model.hpp"
#include "analysis/transient_pair/continuum_transient.hpp"
#include "analysis/transient_pair/transient_pair_kind.hpp"
#include "continuum/sections/model_sections.hpp"
#include "core/kind_registry.hpp"
#include "core/process.hpp"
#include "core/result_file.hpp"
#include "dem_coupling/dem_kind.hpp"
#include "dem_coupling/kind/rate_step_metrics.hpp"

namespace granflow::transient_pair {
namespace {

const char* preparation = R"(kind: dem_prepare
name: prep
material:
  diameter: 1.0e-3
  particle_density: 2500
  restitution: 0.7
  youngs_modulus: 1.0e7
  poisson_ratio: 0.3
dem:
  particles: 250
preparation:
  pressure: 100
  friction: 0.5
)";

// The critical state line of cases/rev/materials/dem_spheres_force_chains.yaml (the steady
// calibration's, as are the elastic and fluidization keys below): e_cs(p) = e_Γ − λ_c (p/p_ref)^ξ_c
// with ξ_c = 1.
constexpr double e_gamma = 1.07, lambda_c = 0.43, p_ref = 100.0;

std::string pair_case(const std::filesystem::path& prepared) {
  return fmt::format(R"(kind: transient_pair
name: tiny
material:
  diameter: 1.0e-3
  particle_density: 2500
  restitution: 0.7
  particle_friction: 0.5
  youngs_modulus: 1.0e7
  poisson_ratio: 0.3
collisional:
  jamming_fraction: 0.59
  radial_distribution: torquato
force_chains:
  bulk_modulus_ref: 2.0e5
  reference_pressure: 100.0
  elastic_exponent: 0.333333
  M_c: 0.75
  e_Gamma: {}
  lambda_c: {}
  xi_c: 1.0
  atmospheric_pressure: {}
  e_min: 0.45
  e_max: 1.2
  pressure_floor: 1.0
  fluidization_size: 2.0
  resolidification_size: 4.0
  regrowth_modulus: 4.0e3
  regrowth_temperature: 1.0e-6
start:
  preparation: {}
control:
  mode: constant_volume
shear_rate: 2
strain:
  total: 0.3
  sample: 0.002
stop:
  duration: 0.01
)",
                     e_gamma, lambda_c, p_ref, prepared.string());
}

// Checks and runs the pair case `c` into `run` (exit 0 expected; a failure is a test failure) and
// returns its summary.
core::Summary run_pair(const core::Case& c, const std::filesystem::path& run) {
  check_transient_pair_case(c);
  int code = -1;
  {
    core::RunContext ctx(c, run, true, true);
    code = run_transient_pair_case(ctx);
    ctx.finish();
  }
  EXPECT_EQ(code, core::exit_ok);
  return core::Summary::read(run / "summary.json");
}

// The Python reader (tests/cli/check_results_reader.py) opens each run of `runs` (directory,
// kind) and checks that every dataset is listed with its unit in docs/results.md.
void expect_documented_results(
    const std::filesystem::path& dir,
    const std::vector<std::pair<std::filesystem::path, std::string>>& runs) {
  core::ProcessOptions options;
  options.output = dir / "reader.log";
  const std::filesystem::path source = GRANFLOW_SOURCE_DIR;
  std::vector<std::string> command{"/usr/bin/python3",
                                   (source / "tests/cli/check_results_reader.py").string()};
  for (const auto& [run, kind] : runs) command.insert(command.end(), {run.string(), kind});
  const auto r = core::run_process(command, options);
  std::ifstream log(dir / "reader.log");
  const std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  EXPECT_EQ(r.status, 0) << text;
}

// The 250-sphere loose packing of `preparation` in DIR (a kind: dem_prepare run).
void prepare_packing(const std::filesystem::path& dir) {
  core::KindRegistry registry;
  dem::register_dem_kinds(registry);
  const auto& prepare = registry.find("dem_prepare", "", "prep.yaml");
  const auto c = core::Case::parse(preparation, "prep.yaml", {}, prepare.schema);
  core::RunContext ctx(c, dir, true, true);
  ASSERT_EQ(prepare.run(ctx), core::exit_ok);
  ctx.finish();
}

TEST(TransientPair, LoosePackingInTheDemAndTheContinuum) {
  const auto dir = std::filesystem::path(GRANFLOW_BINARY_DIR) / "test_transient_pair";
  std::filesystem::remove_all(dir);
  ASSERT_NO_FATAL_FAILURE(prepare_packing(dir / "prep"));
  const auto schema = transient_pair_schema();
  const auto c = core::Case::parse(pair_case(dir / "prep"), "tiny.yaml", {}, schema);
  const auto s = run_pair(c, dir / "run");
  const auto prep = core::Summary::read(dir / "prep" / "summary.json");
  // Both sides start from the prepared state.
  EXPECT_DOUBLE_EQ(s.get("transient.phi0"), prep.get("prepared.phi"));
  EXPECT_DOUBLE_EQ(s.get("transient.p0"), prep.get("prepared.p"));
  const auto h5 = dir / "run" / "result.h5";
  const auto p = core::read_dataset(h5, "/transient_pair/group_0/mean_stress");
  const auto tau = core::read_dataset(h5, "/transient_pair/group_0/shear_stress");
  const auto sigma_yy = core::read_dataset(h5, "/transient_pair/group_0/normal_stress");
  const auto strain = core::read_dataset(h5, "/transient_pair/group_0/strain");
  ASSERT_GT(p.size(), 100u);
  EXPECT_NEAR(strain.back(), 0.3, 1e-3);  // run through the DEM's strain, no steady stop
  // At constant volume the skeleton ends on its critical state at the imposed void ratio e0:
  // p' = p_ref (e_Γ − e0)/λ_c (the closed form of the line) and τ/σ_yy = μ_FC, the Lade-Duncan
  // critical stress ratio in simple shear (calibration::critical_state_friction). Within 1 %:
  // p also holds p_COL, which at the REV's T (~1e-6 m²/s²) is < 0.5 % of p' here, and the
  // exponential approach (decay strain ~0.05 at this ψ) is complete to < 1e-3 by γ = 0.3.
  const double e0 = 1.0 / s.get("transient.phi0") - 1.0;
  const double p_cs = p_ref * (e_gamma - e0) / lambda_c;
  EXPECT_NEAR(p.back() / p_cs, 1.0, 0.01) << "p_cs(e0) = " << p_cs;
  const auto settings = continuum::read_multi_regime_settings(c);
  EXPECT_NEAR(tau.back() / sigma_yy.back() /
                  calibration::critical_state_friction(settings.force_chain_parameters),
              1.0, 0.01);
  // The continuum liquefies only if its critical state at e0 lies below 5 % of p0.
  EXPECT_EQ(s.get("transient.cont.liquefied"), p_cs < 0.05 * s.get("transient.p0"));
  // The DEM's loose packing (φ0 ≈ 0.57 < φ_c ≈ 0.585 at μ_p = 0.5) does liquefy, and the pair
  // reports the DEM run's own verdict.
  const auto dem = core::Summary::read(dir / "run" / "dem" / "summary.json");
  EXPECT_EQ(s.get("transient.dem.liquefied"), dem.get("transient.liquefied"));
  EXPECT_EQ(s.get("transient.dem.liquefied"), 1.0);
  EXPECT_DOUBLE_EQ(s.get("transient.dem.peak_tau"), dem.get("transient.peak_tau"));
  EXPECT_TRUE(std::filesystem::exists(dir / "run" / "transient_pair.png"));
  // The DEM's band is in the pair's own file, the same numbers as the DEM run's.
  EXPECT_EQ(
      core::read_dataset(h5, "/transient_pair/group_0/dem/mean_stress_mean"),
      core::read_dataset(dir / "run" / "dem" / "result.h5", "/transient/group_0/mean_stress_mean"));

  // The shear stopped: both sides' stopped series, the DEM's band the DEM run's own, and the
  // cooling compared by one function on both (T falls on both: nothing drives either).
  EXPECT_EQ(core::read_dataset(h5, "/transient_pair/group_0/dem/stop/granular_temperature_mean"),
            core::read_dataset(dir / "run" / "dem" / "result.h5",
                               "/transient/group_0/stop/granular_temperature_mean"));
  const auto stop_time = core::read_dataset(h5, "/transient_pair/group_0/stop/time");
  const auto stop_T = core::read_dataset(h5, "/transient_pair/group_0/stop/granular_temperature");
  ASSERT_FALSE(stop_time.empty());
  EXPECT_NEAR(stop_time.back(), 0.01, 1e-12);
  EXPECT_LT(stop_T.back(), stop_T.front());
  EXPECT_DOUBLE_EQ(s.get("transient.dem.flowing_T"), dem.get("transient.flowing_T"));
  EXPECT_LT(s.get("transient.dem.stop_T_over_flowing_T"), 1.0);
  EXPECT_LT(s.get("transient.cont.stop_T_over_flowing_T"), 1.0);

  // The same pair from the finished DEM run (dem_run): the DEM is not run again and every
  // number is the same (the continuum is deterministic).
  const auto again = core::Case::parse(pair_case(dir / "prep"), "tiny.yaml",
                                       {"dem_run=" + (dir / "run" / "dem").string()}, schema);
  check_transient_pair_case(again);
  check_transient_pair_inputs(again);
  {
    core::RunContext ctx(again, dir / "again", true, true);
    ASSERT_EQ(run_transient_pair_case(ctx), core::exit_ok);
    ctx.finish();
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "again" / "dem"));
  const auto t = core::Summary::read(dir / "again" / "summary.json");
  for (const char* key : {"transient.dem.peak_tau", "transient.dem.residual_tau",
                          "transient.cont.peak_tau", "transient.cont.residual_p", "transient.phi0"})
    EXPECT_EQ(t.get(key), s.get(key)) << key;
  // The Python reader opens the three runs (the preparation, the DEM from it, the pair) and every
  // dataset is listed with its unit in docs/results.md (tests/cli/check_results_reader.py).
  expect_documented_results(dir, {{dir / "prep", "dem_prepare"},
                                  {dir / "run" / "dem", "dem"},
                                  {dir / "run", "transient_pair"}});
  // A dem_run that is no DEM run (the preparation) is one case error naming the key.
  const auto wrong = core::Case::parse(pair_case(dir / "prep"), "tiny.yaml",
                                       {"dem_run=" + (dir / "prep").string()}, schema);
  try {
    check_transient_pair_inputs(wrong);
    ADD_FAILURE() << "a dem_prepare run accepted as dem_run";
  } catch (const core::CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("dem_run"), std::string::npos) << e.what();
  }
}

// The drained stop on both sides: the loose packing sheared in water, then 30 ms under σ_n = p0
// draining over 1 cm (the DEM's fix drainage, the REV's run_drained_stop, the same lumped Darcy
// law with the liquid's permeability closure). η(ν) diverges at the case's ν_c here, not at
// Boyer's 0.585, which the DEM passes (docs/transient_pairs.md).
TEST(TransientPair, DrainedStopReconsolidatesBothSides) {
  const auto dir = std::filesystem::path(GRANFLOW_BINARY_DIR) / "test_transient_pair_drained";
  std::filesystem::remove_all(dir);
  ASSERT_NO_FATAL_FAILURE(prepare_packing(dir / "prep"));
  const auto schema = transient_pair_schema();
  const auto c = core::Case::parse(
      pair_case(dir / "prep"), "tiny.yaml",
      {"liquid.enabled=true", "liquid.viscosity=1e-3", "liquid.maximum_packing=0.59",
       "stop.duration=0.03", "stop.drainage_length=0.01"},
      schema);
  const auto s = run_pair(c, dir / "run");
  const auto h5 = dir / "run" / "result.h5";
  const double p0 = s.get("transient.p0");
  // Both sides compact (φ up) and carry σ_n = p0 again; the DEM measured at 250 spheres: φ up
  // 0.0085, 0.9 σ_n after 17.6 ms (tests/dem/test_prepare.cpp).
  for (const char* side : {"dem", "cont"}) {
    const std::string key = std::string("transient.") + side + ".";
    EXPECT_GT(s.get(key + "stop_phi_change"), 0.002) << side;
    EXPECT_GT(s.get(key + "reconsolidation_time"), 0.0) << side;
    EXPECT_LT(s.get(key + "reconsolidation_time"), 0.03) << side;
  }
  EXPECT_TRUE(s.contains("transient.rel_err.reconsolidation_time"));
  const auto phi = core::read_dataset(h5, "/transient_pair/group_0/stop/solid_fraction");
  const auto sigma = core::read_dataset(h5, "/transient_pair/group_0/stop/normal_stress");
  ASSERT_FALSE(phi.empty());
  EXPECT_GT(phi.back(), s.get("transient.phi0"));
  // the continuum solves σ_yy + u = σ_n with u = ε̇_yy/k the excess pore pressure, which drains
  // away: at the end σ_yy is past the 0.9 σ_n of the metric and not above σ_n (measured 0.92)
  EXPECT_GE(sigma.back(), 0.9 * p0);
  EXPECT_LE(sigma.back(), p0 * (1.0 + 1e-3));
  // the DEM's stop band is the DEM run's own, φ included
  EXPECT_EQ(core::read_dataset(h5, "/transient_pair/group_0/dem/stop/solid_fraction_mean"),
            core::read_dataset(dir / "run" / "dem" / "result.h5",
                               "/transient/group_0/stop/solid_fraction_mean"));
  // every dataset of the drained pair is documented (tests/cli/check_results_reader.py)
  expect_documented_results(dir, {{dir / "run" / "dem", "dem"}, {dir / "run", "transient_pair"}});
}

// A drained shear in water with a step in the shear rate, both sides: σ_n = p0 held while the
// water drains over 1 cm, γ̇ 2 -> 20 1/s at γ = 0.15. The loose packing compacts while sheared
// slowly and dilates after the step on both sides (DEM at 1000 spheres: φ 0.587 -> 0.575, the
// continuum 0.588 -> 0.575; docs/transient_pairs.md), μ and T rise. The quasi-static critical
// state line (e_cs(100 Pa) = 0.70: φ 0.588) keeps the compaction below the poles at 0.62.
TEST(TransientPair, DrainedShearWithARateStepOnBothSides) {
  const auto dir = std::filesystem::path(GRANFLOW_BINARY_DIR) / "test_transient_pair_rate_step";
  std::filesystem::remove_all(dir);
  ASSERT_NO_FATAL_FAILURE(prepare_packing(dir / "prep"));
  const auto schema = transient_pair_schema();
  const auto c = core::Case::parse(
      pair_case(dir / "prep"), "tiny.yaml",
      {"liquid.enabled=true", "liquid.viscosity=1e-3", "liquid.maximum_packing=0.62",
       "force_chains.e_Gamma=0.71", "force_chains.lambda_c=0.01",
       "collisional.jamming_fraction=0.62", "control.mode=drained", "control.drainage_length=0.01",
       "rate_step.strain=0.15", "rate_step.shear_rate=20"},
      schema);
  const auto s = run_pair(c, dir / "run");
  // Both sides compact while sheared slowly, and μ and T rise with the rate (the DEM's T 25x; the
  // continuum's kinetic theory alone, without the dense-branch closures, far more from 1e-9).
  for (const char* side : {"dem", "cont"}) {
    const std::string key = std::string("transient.") + side + ".";
    EXPECT_GT(s.get(key + "phi_before_step"), s.get("transient.phi0") + 0.003) << side;
    EXPECT_GT(s.get(key + "dilation_strain"), 0.0) << side;
    EXPECT_GT(s.get(key + "mu_after_step"), s.get(key + "mu_before_step")) << side;
    EXPECT_GT(s.get(key + "T_after_step"), 5.0 * s.get(key + "T_before_step")) << side;
  }
  // The DEM dilates after the step (250 spheres, 0.15 strain after it: measured -0.0019; 1000
  // spheres over 0.3: -0.0115). This continuum has no dense-branch stress to take over σ_n from
  // its skeleton, which goes on compacting to its critical state (measured +0.002): the shipped
  // case's dense-branch closures dilate it (docs/transient_pairs.md).
  EXPECT_LT(s.get("transient.dem.dilation"), -0.001);
  for (const char* name : {"mu_after_step", "dilation", "dilation_strain"})
    EXPECT_TRUE(s.contains(std::string("transient.rel_err.") + name)) << name;
  // The metrics are one function of the series (dem::rate_step_metrics): the continuum's from
  // its own datasets again.
  const auto h5 = dir / "run" / "result.h5";
  const std::string g = "/transient_pair/group_0/";
  const auto strain = core::read_dataset(h5, g + "strain");
  const auto m = dem::rate_step_metrics(
      strain, core::read_dataset(h5, g + "shear_stress"),
      core::read_dataset(h5, g + "normal_stress"), core::read_dataset(h5, g + "solid_fraction"),
      core::read_dataset(h5, g + "granular_temperature"), 0.15, 0.2);
  EXPECT_DOUBLE_EQ(m.dilation, s.get("transient.cont.dilation"));
  EXPECT_DOUBLE_EQ(m.mu_after, s.get("transient.cont.mu_after_step"));
  // every dataset of the pair is documented (tests/cli/check_results_reader.py)
  expect_documented_results(dir, {{dir / "run" / "dem", "dem"}, {dir / "run", "transient_pair"}});
}

// The known continuum result behind the pair: constant-volume simple shear liquefies a loose
// sample and not a dense one. With the quasi-static line e_cs = e_Γ − λ_c p/p_ref (e_Γ 0.71,
// λ_c 0.01) the skeleton at constant e0 heads for its critical pressure p_cs(e0) = p_ref (e_Γ −
// e0)/λ_c: none for the loose e0 = 0.741 (φ0 0.5745, above e_Γ: p' -> 0, liquefaction), 433 Pa for
// e0 = 0.667 (φ0 0.600, below the line at p0: dilative, p' rises from p0 = 100 Pa).
TEST(TransientPair, ContinuumLiquefiesALooseSampleNotADenseOne) {
  const auto schema = transient_pair_schema();
  const auto c = core::Case::parse(pair_case("unused"), "tiny.yaml",
                                   {"force_chains.e_Gamma=0.71", "force_chains.lambda_c=0.01",
                                    "collisional.jamming_fraction=0.62", "strain.total=1"},
                                   schema);
  const double p0 = 100.0;
  rev::SimpleShearResult loose, dense;
  continuum_transient(c, 0.5745, p0, loose);
  continuum_transient(c, 0.600, p0, dense);
  const auto& pl = loose.series.pressure;
  const auto& pd = dense.series.pressure;
  // Loose: p' falls below 5 % of p0 (the liquefaction threshold) and stays there; what is left is
  // kinetic theory's p_COL at the REV's T (measured ~0.1 Pa).
  EXPECT_LT(pl.back(), 0.05 * p0);
  EXPECT_LT(*std::max_element(pl.end() - 50, pl.end()), 0.05 * p0);
  // Dense: a brief contraction first (the skeleton starts on its yield locus; measured minimum
  // 0.74 p0 at γ = 0.004), far from the threshold, then dilation against the fixed volume to its
  // critical state: p_cs(e0) within 1 % by γ = 1 (the collisional share at this T is < 0.5 %;
  // measured 0.93 p_cs at γ = 0.3 and 1.0002 p_cs at γ = 1).
  EXPECT_GT(*std::min_element(pd.begin(), pd.end()), 0.5 * p0);
  EXPECT_GT(pd.back(), 4.0 * p0);
  const double e0 = 1.0 / 0.600 - 1.0, p_cs = p_ref * (0.71 - e0) / 0.01;
  EXPECT_NEAR(pd.back() / p_cs, 1.0, 0.01) << "p_cs(e0) = " << p_cs;
  const auto low = std::min_element(pd.begin(), pd.end());
  std::printf("dense: min p' %.4g Pa at γ %.4g, end %.4g Pa = %.4f p_cs; loose: end %.3g Pa\n",
              *low, dense.series.strain[std::size_t(low - pd.begin())], pd.back(), pd.back() / p_cs,
              pl.back());
}

// The REV's own transient at φ0 0.5745, p0 100 Pa as a "DEM" for the fit: p'(γ), τ(γ) sampled every
// 0.005 up to `total`, with a zero band (σ = the 1 % p0 floor).
DemTransient transient_as_dem(const core::Case& c, double total, rev::SimpleShearResult& truth) {
  DemTransient dem;
  dem.phi0 = 0.5745, dem.p0 = 100.0;
  continuum_transient(c, dem.phi0, dem.p0, truth);
  for (double g = 0.005; g <= total + 1e-12; g += 0.005) {
    dem.strain.push_back(g);
    dem.p_mean.push_back(interpolate(truth.series.strain, truth.series.pressure, g));
    dem.tau_mean.push_back(interpolate(truth.series.strain, truth.series.shear_stress, g));
  }
  dem.p_min = dem.p_max = dem.p_mean;
  dem.tau_min = dem.tau_max = dem.tau_mean;
  return dem;
}

// The fit recovers a force-chain parameter from a transient the continuum itself made (two paths:
// the forward run at ξ_ψ = 8, the fit from the case's ξ_ψ = 12). The "DEM" here is the REV's
// own p'(γ), τ(γ) on a loose packing with the quasi-static line (e_Γ 0.71, λ_c 0.01), which
// liquefies, sampled every 0.005, with a zero band (σ = the 1 % p0 floor).
TEST(TransientPair, FitRecoversTheParameterThatMadeTheTransient) {
  const auto schema = transient_pair_schema();
  const auto c = core::Case::parse(pair_case("unused"), "tiny.yaml",
                                   {"force_chains.e_Gamma=0.71", "force_chains.lambda_c=0.01",
                                    "force_chains.xi_psi=12", "strain.total=0.15"},
                                   schema);
  rev::SimpleShearResult truth;
  const DemTransient dem =
      transient_as_dem(with_force_chain_values(c, schema, {"xi_psi"}, {8.0}), 0.15, truth);
  const auto fit = fit_force_chains(c, schema, {"xi_psi"}, dem);
  ASSERT_EQ(fit.estimate.size(), 1u);
  EXPECT_DOUBLE_EQ(fit.start[0], 12.0);
  // The same model at the same strains: the optimum is exact up to the stress integration's
  // tolerance (1e-5 relative per sub-step) and the 1 % difference steps of the fit, so 1 %.
  EXPECT_NEAR(fit.estimate[0], 8.0, 0.08) << "after " << fit.evaluations << " REV runs";
  std::printf("xi_psi %.6g after %d REV runs, chi2_red %.3g (start %.3g)\n", fit.estimate[0],
              fit.evaluations, fit.chi2_red, fit.chi2_initial);
  EXPECT_LT(fit.chi2_red, 1e-2);
  EXPECT_GT(fit.chi2_initial, 100 * fit.chi2_red * (fit.points - 1));  // it did move

  // calibrate.range bounds the search: within a factor 1.25 of 12 the truth (8) is out of reach,
  // the fit ends on the bound 12/1.25 = 9.6 and says so.
  const auto narrow =
      core::Case::parse(pair_case("unused"), "tiny.yaml",
                        {"force_chains.e_Gamma=0.71", "force_chains.lambda_c=0.01",
                         "force_chains.xi_psi=12", "strain.total=0.15", "calibrate.range=1.25"},
                        schema);
  const auto bounded = fit_force_chains(narrow, schema, {"xi_psi"}, dem);
  EXPECT_NEAR(bounded.estimate[0], 9.6, 1e-6);
  EXPECT_TRUE(bounded.at_bound[0]);
}

// A parameter outside force_chains, given by its key path: the contacts' viscous scale b_v
// (liquid.viscous_contact) of an immersed loose packing, recovered from a transient the REV made
// at b_v = 0.4 (started at 0.6). After the collapse b_v η0 γ̇ (ν_c − ν)^-m carries p' and τ, so
// the residual fixes it.
TEST(TransientPair, FitRecoversAKeyPathParameter) {
  const auto schema = transient_pair_schema();
  const auto c =
      core::Case::parse(pair_case("unused"), "tiny.yaml",
                        {"force_chains.e_Gamma=0.71", "force_chains.lambda_c=0.01",
                         "strain.total=0.15", "liquid.enabled=true", "liquid.viscosity=1e-3",
                         "liquid.viscous_contact=0.6", "collisional.inertial_contact_power=2.2"},
                        schema);
  EXPECT_EQ(fitted_key("liquid.viscous_contact"), "liquid.viscous_contact");
  EXPECT_EQ(fitted_key("xi_psi"), "force_chains.xi_psi");
  rev::SimpleShearResult truth;
  const DemTransient dem = transient_as_dem(
      with_force_chain_values(c, schema, {"liquid.viscous_contact"}, {0.4}), 0.15, truth);
  // the viscous share is what the liquefied packing carries: well above kinetic theory's here
  EXPECT_GT(truth.series.inertial_contact_pressure.back(), 0.5 * truth.series.pressure.back());
  const auto fit = fit_force_chains(c, schema, {"liquid.viscous_contact"}, dem);
  EXPECT_DOUBLE_EQ(fit.start[0], 0.6);
  // the same model at the same strains: exact up to the stress integration (1e-5) and the 1 %
  // difference steps: 1 %
  EXPECT_NEAR(fit.estimate[0], 0.4, 0.004) << "after " << fit.evaluations << " REV runs";
}

TEST(TransientPair, NeedsAPreparationAndConstantVolume) {
  const auto schema = transient_pair_schema();
  auto text = pair_case("somewhere");
  const auto c = core::Case::parse(text, "tiny.yaml", {"control.mode=constant_pressure"}, schema);
  try {
    check_transient_pair_case(c);
    FAIL() << "constant_pressure accepted";
  } catch (const core::CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("control.mode"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace granflow::transient_pair
