// `granflow run/check` on kind: dem cases, end to end (the CLI launches granflow-dem).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/run.hpp"
#include "dem_coupling/kind/series_table.hpp"
#include "tests/dem/driver_runner.hpp"

namespace {

using granflow::dem::testing::fresh_directory;

// 200 frictional spheres at constant volume, 1 strain unit at 50 1/s (~5000 steps): seconds.
const char* small_case = R"(kind: dem
name: small
material:
  diameter: 1.0e-3
  particle_density: 2500
  restitution: 0.7
  particle_friction: 0.5
dem:
  particles: 200
  compression_steps: 2000
control:
  mode: constant_volume
  solid_fraction: 0.55
shear_rate: 50
strain:
  total: 1.5
  sample: 0.01
)";

// `driver`: a granflow-dem replacement (GRANFLOW_DEM_DRIVER) or empty for the built one.
int run_cli(const std::string& args, const std::filesystem::path& dir,
            const std::filesystem::path& driver = {}) {
  const std::string env =
      driver.empty() ? std::string() : fmt::format("GRANFLOW_DEM_DRIVER='{}' ", driver.string());
  const std::string cmd = fmt::format("cd '{}' && {}'{}' {} > cli.txt 2>&1", dir.string(), env,
                                      GRANFLOW_CLI_PATH, args);
  const int raw = std::system(cmd.c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : 128;
}

std::string read(const std::filesystem::path& file) {
  std::ifstream in(file);
  return {std::istreambuf_iterator<char>(in), {}};
}

TEST(DemCli, ImpossibleCaseIsRefusedBeforeLiggghtsStarts) {
  const auto dir = fresh_directory("cli_refused");
  std::ofstream(dir / "case.yaml") << small_case;
  // Solid fraction beyond what soft spheres compressed above random close packing reach (0.70,
  // max_solid_fraction; 0.64 before constant volume above jamming): exit 2 naming the key,
  // nothing launched.
  EXPECT_EQ(run_cli("run case.yaml --out run --set control.solid_fraction=0.72", dir),
            granflow::core::exit_bad_input);
  const std::string out = read(dir / "cli.txt");
  EXPECT_NE(out.find("control.solid_fraction"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "run" / "in.granflow"));
  // Too few particles for the periodic box.
  EXPECT_EQ(run_cli("check case.yaml --set dem.particles=10", dir), granflow::core::exit_bad_input);
  EXPECT_NE(read(dir / "cli.txt").find("dem.particles"), std::string::npos);
}

TEST(DemCli, SmallCaseRunsEndToEndAndWritesTheIssueKeys) {
  const auto dir = fresh_directory("cli_run");
  std::ofstream(dir / "case.yaml") << small_case;
  ASSERT_EQ(run_cli("run case.yaml --out run", dir), 0) << read(dir / "cli.txt");
  const auto run = dir / "run";
  EXPECT_TRUE(std::filesystem::exists(run / "in.granflow"));
  EXPECT_TRUE(std::filesystem::exists(run / "result.h5"));
  const auto summary = granflow::core::Summary::read(run / "summary.json");
  for (const char* key : {"steady.mu", "steady.mu_err", "steady.phi", "steady.phi_err", "steady.e",
                          "steady.T", "steady.T_err", "steady.p", "steady.p_err", "steady.tau",
                          "steady.I", "steady.Z", "steady.start_strain", "cost.wall_s",
                          "cost.particle_steps_per_s", "dem.particles", "dem.dt"})
    EXPECT_TRUE(summary.contains(key)) << key;
  // Constant volume: phi is imposed exactly; mu = tau / p by definition of the summary values.
  EXPECT_NEAR(summary.get("steady.phi"), 0.55, 1e-9);
  EXPECT_NEAR(summary.get("steady.mu"), summary.get("steady.tau") / summary.get("steady.p"), 1e-12);
  EXPECT_EQ(summary.get("dem.particles"), 200);
  // The rerun command is in the log, and the deck reproduces the run by hand.
  EXPECT_NE(read(run / "log.txt").find("granflow-dem in.granflow"), std::string::npos);
}

// The same case immersed: η0 = 0.01 Pa s, St = ρ_p d² γ̇/η0 = 12.5, drag + rotational
// drag + lubrication (fix fluid/le); Δt set by the contact (lubrication τ_n = 5e-5 s ≫ Δt).
std::string wet_case() {
  return std::string(small_case) + R"(liquid:
  enabled: true
  viscosity: 0.01
  trulsson_alpha: 0.6
dem_liquid:
  maximum_gap: 0.05
  minimum_gap: 0.001
)";
}

TEST(DemCli, WetCaseRunsEndToEndAndItsStressPartsSumToTheShearStress) {
  const auto dir = fresh_directory("cli_wet");
  std::ofstream(dir / "case.yaml") << wet_case();
  ASSERT_EQ(run_cli("run case.yaml --out run", dir), 0) << read(dir / "cli.txt");
  const auto run = dir / "run";
  const std::string deck = read(run / "in.granflow");
  EXPECT_NE(deck.find("fix gf_fluid all fluid/le viscosity 0.01"), std::string::npos) << deck;
  const auto summary = granflow::core::Summary::read(run / "summary.json");
  for (const char* key : {"steady.J", "steady.K", "steady.St", "steady.tau_contact",
                          "steady.tau_lub", "steady.tau_drag", "steady.tau_kin", "steady.J_err",
                          "steady.tau_contact_err", "steady.tau_lub_err", "dem.dt", "dem.dt_limit"})
    EXPECT_TRUE(summary.contains(key)) << key;
  // Definitions: St = ρ_p d² γ̇/η0 (d = 1 mm: the number mean of the bidisperse sizes, to
  // round-off), J = η0 γ̇/σ_yy, K = J + α I².
  EXPECT_NEAR(summary.get("steady.St"), 2500 * 1e-6 * 50 / 0.01, 1e-9);
  const double sigma = summary.get("steady.p"), inertial = summary.get("steady.I");
  EXPECT_NEAR(summary.get("steady.J"), 0.01 * 50 / sigma, 1e-12);
  EXPECT_NEAR(summary.get("steady.K"), summary.get("steady.J") + 0.6 * inertial * inertial, 1e-12);
  EXPECT_EQ(summary.get("dem.dt_limit"), 0);  // contact: 0.1 t_R = 3.9e-6 s < 0.2 τ_n = 1e-5 s
  // Lubrication resists the shear: its steady shear stress is positive.
  EXPECT_GT(summary.get("steady.tau_lub"), 0.0);
  // The parts sum to τ: exactly by construction per sample (τ_contact is the contact virial minus
  // the fix's lubrication and drag virials), so to the round-off of the series file (τ is written
  // with 10 significant digits, the parts with 17): 1e-9 of the largest part.
  const auto series = granflow::dem::read_series_table(run / "series.tsv");
  ASSERT_GT(series.rows(), 100u);
  const auto& tau = series.at("tau");
  for (std::size_t i = 0; i < series.rows(); ++i) {
    const double parts[] = {series.at("tau_contact")[i], series.at("tau_lub")[i],
                            series.at("tau_drag")[i], series.at("tau_kin")[i]};
    double sum = 0, scale = 0;
    for (double part : parts) {
      sum += part;
      scale = std::max(scale, std::abs(part));
    }
    ASSERT_NEAR(sum, tau[i], 1e-9 * scale) << "sample " << i;
  }
  // The steady means are linear in the series (same start, same batches): they sum too.
  const double steady_sum = summary.get("steady.tau_contact") + summary.get("steady.tau_lub") +
                            summary.get("steady.tau_drag") + summary.get("steady.tau_kin");
  EXPECT_NEAR(steady_sum, summary.get("steady.tau"), 1e-8 * std::abs(summary.get("steady.tau")));
}

TEST(DemCli, WetCaseWithTooWideLubricationGapIsRefused) {
  const auto dir = fresh_directory("cli_wet_refused");
  std::ofstream(dir / "case.yaml") << wet_case();
  // h_max = 0.5 d exceeds the smallest radius d_small/2 = 0.45 d (bidisperse 0.9/1.1 mm).
  EXPECT_EQ(run_cli("check case.yaml --set dem_liquid.maximum_gap=0.5", dir),
            granflow::core::exit_bad_input);
  EXPECT_NE(read(dir / "cli.txt").find("dem_liquid.maximum_gap"), std::string::npos)
      << read(dir / "cli.txt");
}

TEST(DemCli, LiggghtsErrorIsSurfacedWithExitCode4AndTheRunDirectoryIsKept) {
  // A driver wrapper appends a command LIGGGHTS rejects to the generated deck, then runs the real
  // driver: granflow must report LIGGGHTS' own message, exit 4 and keep the run directory.
  const auto dir = fresh_directory("cli_liggghts_error");
  std::ofstream(dir / "case.yaml") << small_case;
  const auto wrapper = dir / "broken-driver.sh";
  std::ofstream(wrapper) << fmt::format(
      "#!/bin/sh\necho 'fix broken all no/such/fix/style' >> in.granflow\nexec '{}' \"$@\"\n",
      GRANFLOW_DEM_DRIVER_PATH);
  std::filesystem::permissions(wrapper, std::filesystem::perms::owner_all);
  EXPECT_EQ(run_cli("run case.yaml --out run", dir, wrapper), granflow::core::exit_external);
  const std::string log = read(dir / "run" / "log.txt");
  EXPECT_NE(log.find("ERROR"), std::string::npos) << log;
  EXPECT_NE(log.find("no/such/fix/style"), std::string::npos) << log;
  EXPECT_TRUE(std::filesystem::exists(dir / "run" / "result.h5"));
  EXPECT_TRUE(std::filesystem::exists(dir / "run" / "summary.json"));
}

TEST(DemCli, SweepContinuesAfterAFailedPointAndFlagsIt) {
  // A two-point sweep whose first point fails in LIGGGHTS (a wrapper breaks the deck of
  // point_0 only). The second point still runs; the failed row of /steady is NaN, the other is
  // finite; summary.json flags the failure (sweep.failed.0, sweep.failed_points) and has no
  // steady.*.0 keys; the exit code is 4 (external program failed).
  const auto dir = fresh_directory("cli_sweep_failed_point");
  std::ofstream(dir / "case.yaml") << small_case << "sweep:\n  shear_rate: [50, 60]\n";
  const auto wrapper = dir / "break-point-0.sh";
  std::ofstream(wrapper) << fmt::format(
      "#!/bin/sh\ncase \"$(pwd)\" in */point_0) echo 'fix broken all no/such/fix/style' >> "
      "in.granflow;; esac\nexec '{}' \"$@\"\n",
      GRANFLOW_DEM_DRIVER_PATH);
  std::filesystem::permissions(wrapper, std::filesystem::perms::owner_all);
  EXPECT_EQ(run_cli("run case.yaml --out run", dir, wrapper), granflow::core::exit_external)
      << read(dir / "cli.txt");
  const auto run = dir / "run";
  const auto mu = granflow::core::read_dataset(run / "result.h5", "/steady/friction");
  ASSERT_EQ(mu.size(), 2u);
  EXPECT_TRUE(std::isnan(mu[0]));
  EXPECT_TRUE(std::isfinite(mu[1]));
  EXPECT_TRUE(
      std::isnan(granflow::core::read_dataset(run / "result.h5", "/steady/solid_fraction")[0]));
  const auto summary = granflow::core::Summary::read(run / "summary.json");
  EXPECT_EQ(summary.get("sweep.count"), 2);
  EXPECT_EQ(summary.get("sweep.failed_points"), 1);
  EXPECT_EQ(summary.get("sweep.failed.0"), 1);
  EXPECT_FALSE(summary.contains("sweep.failed.1"));
  EXPECT_FALSE(summary.contains("steady.mu.0"));
  EXPECT_TRUE(summary.contains("steady.mu.1"));
  // The failed point's LIGGGHTS message is in the log, and point 1's samples are in result.h5.
  EXPECT_NE(read(run / "log.txt").find("no/such/fix/style"), std::string::npos);
  EXPECT_GT(granflow::core::read_dataset(run / "result.h5", "/conditions/1/series/friction").size(),
            100u);
}

}  // namespace
