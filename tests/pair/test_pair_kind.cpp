// kind: pair end to end: a tiny dry DEM (200 spheres, 2 strain units, 1 rank) and the continuum
// at the same two conditions; table, summary keys, report.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "analysis/pair/pair_kind.hpp"
#include "analysis/report.hpp"
#include "core/result_file.hpp"

namespace granflow::pair {
namespace {

const char* tiny_case = R"(kind: pair
name: pair_tiny
material:
  diameter: 1.0e-3
  particle_density: 2500
  restitution: 0.7
  particle_friction: 0.5
collisional:
  jamming_fraction: 0.587
dem:
  particles: 200
  compression_steps: 2000
control:
  mode: constant_pressure
  normal_stress: 100
  solid_fraction: 0.57
shear_rate: 20
strain:
  total: 2
  sample: 0.01
sweep:
  shear_rate: [20, 40]
)";

TEST(PairKind, TinyPairRunsEndToEnd) {
  const auto schema = pair_schema();
  const auto c = core::Case::parse(tiny_case, "tiny_pair.yaml", {}, schema);
  check_pair_case(c);
  const auto dir = std::filesystem::path(GRANFLOW_BINARY_DIR) / "test_pair" / "run";
  {
    core::RunContext ctx(c, dir, true, true);
    ASSERT_EQ(run_pair_case(ctx), core::exit_ok);
    ctx.finish();
  }
  const auto s = core::Summary::read(dir / "summary.json");
  const int count = static_cast<int>(s.get("pair.count"));
  // Both conditions reach a steady part with error bars in 2 strain units at 200 spheres.
  ASSERT_EQ(count, 2);
  for (int n = 0; n < count; ++n) {
    const std::string k = "pair." + std::to_string(n) + ".";
    for (const char* key :
         {"mu_dem", "mu_dem_err", "mu_cont", "T_dem", "T_cont", "e_dem", "e_cont", "rel_err_mu"})
      EXPECT_TRUE(s.contains(k + key)) << k + key;
    // The DEM's μ lies in the range of dense frictional flows (0.3 - 0.7 at I = 0.1 - 0.2,
    // docs/dem_dataset.md) and the continuum gives a finite μ at the same (γ̇, σ_yy).
    EXPECT_GT(s.get(k + "mu_dem"), 0.2);
    EXPECT_LT(s.get(k + "mu_dem"), 0.8);
    EXPECT_TRUE(std::isfinite(s.get(k + "mu_cont")));
    EXPECT_NEAR(s.get(k + "rel_err_mu"), s.get(k + "mu_cont") / s.get(k + "mu_dem") - 1, 1e-12);
  }
  // The DEM's σ_yy is the continuum's imposed p: the two I agree up to the DEM's σ_yy error.
  const auto I_dem = core::read_dataset(dir / "result.h5", "/pair/inertial_number_dem");
  const auto I_cont = core::read_dataset(dir / "result.h5", "/pair/inertial_number_cont");
  for (std::size_t i = 0; i < I_dem.size(); ++i)
    EXPECT_NEAR(I_cont[i] / I_dem[i], 1.0, 1e-6);  // same γ̇, d, ρ_p and p: rounding of the solve
  EXPECT_TRUE(std::filesystem::exists(dir / "dem" / "result.h5"));
  // The continuum side by two paths (algebraic steady state, time-stepped REV): the REV stops at
  // 1e-10 relative change per unit strain, so they agree far below 1e-6.
  EXPECT_LT(s.get("pair.rev_vs_algebraic_max_rel_diff"), 1e-6);
  core::KindRegistry registry;
  register_pair_kinds(registry);
  const auto report = analysis::write_report(dir, registry);
  std::ifstream in(report);
  std::stringstream md;
  md << in.rdbuf();
  EXPECT_NE(md.str().find("DEM and continuum, point by point"), std::string::npos);
}

// An immersed pair: the DEM with fix fluid/le and the continuum with its liquid terms, each at
// the condition's own η0 (the sweep varies it). St = ρ_p d² γ̇ / η0 = 0.2 and 20.
TEST(PairKind, TinyWetPairRunsEndToEnd) {
  // The viscous point (St 0.2) at 100 Pa flows near φ = 0.55, far below the dry start at 0.57:
  // with the default 0.002 height change per servo update its σ_yy would still be ~10x the target
  // after 2 strain, so the servo may move 1 % per update here (the comparison needs σ_yy ≈ 100 Pa).
  std::string head = std::string(tiny_case).substr(0, std::string(tiny_case).find("sweep:"));
  const std::string start = "  solid_fraction: 0.57\n";
  head.replace(head.find(start), start.size(),
               "  solid_fraction: 0.57\n  servo_max_strain: 0.01\n");
  const std::string wet_case = head +
                               R"(liquid:
  enabled: true
  viscosity: 0.25
  maximum_packing: 0.62
dem_liquid:
  minimum_gap: 0.01
sweep:
  liquid.viscosity: [0.25, 0.0025]
)";
  const auto schema = pair_schema();
  const auto c = core::Case::parse(wet_case, "tiny_wet_pair.yaml", {}, schema);
  check_pair_case(c);
  const auto dir = std::filesystem::path(GRANFLOW_BINARY_DIR) / "test_pair" / "wet";
  {
    core::RunContext ctx(c, dir, true, true);
    ASSERT_EQ(run_pair_case(ctx), core::exit_ok);
    ctx.finish();
  }
  const auto s = core::Summary::read(dir / "summary.json");
  ASSERT_EQ(static_cast<int>(s.get("pair.count")), 2);
  const auto J_dem = core::read_dataset(dir / "result.h5", "/pair/viscous_number_dem");
  const auto J_cont = core::read_dataset(dir / "result.h5", "/pair/viscous_number_cont");
  const auto sigma = core::read_dataset(dir / "result.h5", "/pair/normal_stress");
  const auto regime = core::read_dataset(dir / "result.h5", "/pair/regime");
  const double eta[2] = {0.25, 0.0025};
  for (int n = 0; n < 2; ++n) {
    // J = η0 γ̇ / σ_yy at the DEM's measured σ_yy, and the continuum is driven at that σ_yy with
    // the same η0: the two J agree to the rounding of the ν solve.
    EXPECT_NEAR(J_dem[n], eta[n] * 20.0 / sigma[n], 1e-12 * J_dem[n]);
    EXPECT_NEAR(J_cont[n] / J_dem[n], 1.0, 1e-6);
  }
  EXPECT_EQ(regime[0], 3.0);  // St = 0.2: viscous
  EXPECT_NE(regime[1], 3.0);  // St = 20: by I
  // Viscous stresses raise μ at fixed σ_yy in both the continuum (σ_L = η(ν) γ̇) and the DEM
  // (lubrication, drag; Boyer's μ(J) at J ≈ 0.05 is ~1 vs μ(I = 0.2) ≈ 0.5 dry): a factor 100 in
  // η0 must show in both, far beyond the ±0.05 scatter of a 200-sphere, 2-strain μ.
  EXPECT_GT(s.get("pair.0.mu_cont"), s.get("pair.1.mu_cont"));
  EXPECT_GT(s.get("pair.0.mu_dem"), s.get("pair.1.mu_dem") + 0.1);
  EXPECT_TRUE(s.contains("pair.0.J_dem"));
}

}  // namespace
}  // namespace granflow::pair

namespace granflow::pair {
namespace {

TEST(PairKind, ShippedCaseFilesValidate) {
  const auto schema = pair_schema();
  const auto dir = std::filesystem::path(GRANFLOW_SOURCE_DIR) / "cases" / "pair";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".yaml") continue;
    EXPECT_NO_THROW(check_pair_case(core::Case::load(entry.path(), {}, schema))) << entry.path();
    ++count;
  }
  EXPECT_GE(count, 1);
}

TEST(PairKind, RegimesByInertialNumber) {
  EXPECT_STREQ(regime_name(dry_regime(1e-4)), "quasi-static");
  EXPECT_STREQ(regime_name(dry_regime(0.01)), "dense inertial");
  EXPECT_STREQ(regime_name(dry_regime(0.2)), "collisional");
  EXPECT_STREQ(regime_name(flow_regime(0.1, 0.05)), "viscous");      // St = I²/J = 0.2
  EXPECT_STREQ(regime_name(flow_regime(0.1, 1e-4)), "collisional");  // St = 100: by I
  EXPECT_STREQ(regime_name(flow_regime(0.1, 0.0)), "collisional");   // dry
}

}  // namespace
}  // namespace granflow::pair
