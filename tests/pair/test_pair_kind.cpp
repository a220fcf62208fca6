// kind: pair end to end: a tiny dry DEM (200 spheres, 2 strain units, 1 rank) and the continuum
// at the same two conditions; table, summary keys of issue 6, report.
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
    // model.md §7) and the continuum gives a finite μ at the same (γ̇, σ_yy).
    EXPECT_GT(s.get(k + "mu_dem"), 0.2);
    EXPECT_LT(s.get(k + "mu_dem"), 0.8);
    EXPECT_TRUE(std::isfinite(s.get(k + "mu_cont")));
    EXPECT_NEAR(s.get(k + "rel_err_mu"), s.get(k + "mu_cont") / s.get(k + "mu_dem") - 1, 1e-12);
  }
  // The DEM's σ_yy is the continuum's imposed p: the two I agree up to the DEM's σ_yy error.
  const auto I_dem = core::read_dataset(dir / "result.h5", "/pair/I_dem");
  const auto I_cont = core::read_dataset(dir / "result.h5", "/pair/I_cont");
  for (std::size_t i = 0; i < I_dem.size(); ++i)
    EXPECT_NEAR(I_cont[i] / I_dem[i], 1.0, 1e-6);  // same γ̇, d, ρ_p and p: rounding of the solve
  EXPECT_TRUE(std::filesystem::exists(dir / "dem" / "result.h5"));
  // The continuum side by two paths (algebraic steady state, time-stepped REV): the REV stops at
  // 1e-10 relative change per unit strain, so they agree far below 1e-6.
  EXPECT_LT(s.get("pair.rev_vs_algebraic_max_rel_diff"), 1e-6);
  const auto report = analysis::write_report(dir);
  std::ifstream in(report);
  std::stringstream md;
  md << in.rdbuf();
  EXPECT_NE(md.str().find("DEM and continuum, point by point"), std::string::npos);
}

TEST(PairKind, WetPairIsRefusedUntilTheImmersedDemIsPaired) {
  const auto schema = pair_schema();
  const auto c = core::Case::parse(std::string(tiny_case) + "liquid: {enabled: true}\n",
                                   "wet_pair.yaml", {}, schema);
  EXPECT_THROW(check_pair_case(c), core::CaseError);
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
}

}  // namespace
}  // namespace granflow::pair
