// End to end: `granflow study convergence` of a `kind: dem` case (analysis/dem_study.py; the
// ladder of docs/speed-accuracy.md, section DEM). A 2-rung particle ladder (200 and 300 spheres of
// cases/dem/dry_point.yaml at I = 0.3, 2 strain, one rank: ~5 s per rung) writes study.csv with the
// documented columns, study.md, study.json and pareto.png, and compares the small rung with the
// reference (the larger); an unknown --vary name is exit 2 with one line and makes no directory.
// With --seeds 2 a one-rung study (the base, 200 spheres, 2 seeds: ~8 s) reports the mean of the
// seeds' μ, φ with the between-seed standard error and the steps of both runs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/process.hpp"
#include "core/run.hpp"
#include "tests/dem/scratch_dir.hpp"

namespace {

namespace fs = std::filesystem;
using granflow::dem::testing::fresh_directory;

std::string read(const fs::path& file) {
  std::ifstream in(file);
  return {std::istreambuf_iterator<char>(in), {}};
}

// `granflow study convergence` of the tiny dry point with `extra` arguments, in `dir` (no shell);
// its output in dir/cli.txt; the exit status.
int study(const fs::path& dir, const std::vector<std::string>& extra) {
  std::vector<std::string> args{
      GRANFLOW_CLI_PATH, "study",
      "convergence",     std::string(GRANFLOW_SOURCE_DIR) + "/cases/dem/dry_point.yaml",
      "--out",           "study"};
  for (const char* set : {"dem.particles=300", "dem.ranks=1", "strain.total=2"})
    args.insert(args.end(), {"--set", set});
  args.insert(args.end(), extra.begin(), extra.end());
  granflow::core::ProcessOptions options;
  options.directory = dir;
  options.output = dir / "cli.txt";
  return granflow::core::run_process(args, options).status;
}

std::vector<std::string> split(const std::string& line, char by) {
  std::vector<std::string> out;
  std::stringstream in(line);
  for (std::string item; std::getline(in, item, by);) out.push_back(item);
  if (!line.empty() && line.back() == by) out.emplace_back();
  return out;
}

TEST(DemStudy, TwoRungParticleLadderWritesTheDocumentedColumns) {
  const fs::path dir = fresh_directory("dem_study_ladder");
  ASSERT_EQ(
      study(dir, {"--vary", "particles", "--ladder", "particles=200,300", "--inertial", "0.3"}), 0)
      << read(dir / "cli.txt");
  const fs::path out = dir / "study";
  for (const char* file : {"study.csv", "study.md", "study.json", "pareto.png", "case.yaml"})
    EXPECT_TRUE(fs::exists(out / file)) << file;
  std::istringstream csv(read(out / "study.csv"));
  std::string header;
  std::getline(csv, header);
  // The columns of docs/speed-accuracy.md, section DEM, in this order.
  EXPECT_EQ(header,
            "row,n,inertial_target,ladder,label,reference,base,particles,strain,safety,stiffness,"
            "sample,shear_rate,inertial_number,steady,mu,mu_err,phi,phi_err,T,T_err,dmu_se,"
            "dphi_se,dT_se,mu_error,phi_error,wall_s,steps,particle_steps,time_step,failed,"
            "seeds,mu_scatter_ratio");
  const std::vector<std::string> names = split(header, ',');
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(csv, line);) rows.push_back(split(line, ','));
  ASSERT_EQ(rows.size(), 2u) << read(out / "study.csv");
  auto value = [&](std::size_t row, const std::string& name) {
    for (std::size_t k = 0; k < names.size(); ++k)
      if (names[k] == name) return rows[row].at(k);
    ADD_FAILURE() << "no column " << name;
    return std::string();
  };
  // Sorted by the ladder's value: 200 spheres, then the base and reference, 300.
  EXPECT_EQ(value(0, "particles"), "200");
  EXPECT_EQ(value(1, "particles"), "300");
  EXPECT_EQ(value(0, "reference"), "0");
  EXPECT_EQ(value(1, "reference"), "1");
  EXPECT_EQ(value(1, "base"), "1");
  for (std::size_t r = 0; r < 2; ++r) {
    EXPECT_EQ(value(r, "failed"), "0");
    const double mu = std::stod(value(r, "mu")), err = std::stod(value(r, "mu_err"));
    EXPECT_GT(mu, 0.2);
    EXPECT_LT(mu, 0.8);
    EXPECT_GT(err, 0.0);
    EXPECT_GT(std::stod(value(r, "phi")), 0.5);
    EXPECT_NEAR(std::stod(value(r, "inertial_target")), 0.3, 1e-12);
    EXPECT_NEAR(std::stod(value(r, "shear_rate")), 60.0, 1e-9);  // 0.3 √(100/2500) / 1 mm
    EXPECT_GT(std::stod(value(r, "wall_s")), 0.0);
    // particle-steps = particles × steps (compression included)
    EXPECT_DOUBLE_EQ(std::stod(value(r, "particle_steps")),
                     std::stod(value(r, "particles")) * std::stod(value(r, "steps")));
  }
  // The reference compared with itself: no difference; its μ error is its own se(μ)/μ.
  EXPECT_EQ(std::stod(value(1, "dmu_se")), 0.0);
  EXPECT_NEAR(std::stod(value(1, "mu_error")),
              std::stod(value(1, "mu_err")) / std::stod(value(1, "mu")), 1e-9);
  EXPECT_GE(std::stod(value(0, "mu_error")),
            std::stod(value(0, "mu_err")) / std::stod(value(1, "mu")) - 1e-12);
  EXPECT_NE(read(out / "study.md").find("particles 300 (base) *"), std::string::npos)
      << read(out / "study.md");
  EXPECT_NE(read(out / "study.json").find("\"study.0.mu_error\""), std::string::npos);
  EXPECT_EQ(value(0, "seeds"), "1");
}

TEST(DemStudy, SeedsAreAveragedWithTheBetweenSeedError) {
  const fs::path dir = fresh_directory("dem_study_seeds");
  ASSERT_EQ(study(dir, {"--vary", "particles", "--ladder", "particles=200", "--inertial", "0.3",
                        "--set", "dem.particles=200", "--seeds", "2"}),
            0)
      << read(dir / "cli.txt");
  std::istringstream csv(read(dir / "study" / "study.csv"));
  std::string header, line;
  std::getline(csv, header);
  std::getline(csv, line);
  const std::vector<std::string> names = split(header, ','), row = split(line, ',');
  auto value = [&](const std::string& name) {
    for (std::size_t k = 0; k < names.size(); ++k)
      if (names[k] == name) return std::stod(row.at(k));
    ADD_FAILURE() << "no column " << name;
    return 0.0;
  };
  // The rung's run: seeds 1 and 2 as its points 0 and 1.
  const auto s = granflow::core::Summary::read(dir / "study" / "run_0" / "summary.json");
  const double mu0 = s.get("steady.mu.0"), mu1 = s.get("steady.mu.1");
  EXPECT_EQ(value("seeds"), 2.0);
  EXPECT_NEAR(value("mu"), 0.5 * (mu0 + mu1), 1e-9);
  EXPECT_NEAR(value("mu_err"), 0.5 * std::abs(mu0 - mu1), 1e-9);  // s/√2 of two values
  EXPECT_NEAR(value("phi"), 0.5 * (s.get("steady.phi.0") + s.get("steady.phi.1")), 1e-9);
  EXPECT_DOUBLE_EQ(value("steps"), s.get("cost.steps.0") + s.get("cost.steps.1"));
  EXPECT_DOUBLE_EQ(value("particle_steps"), 200.0 * value("steps"));
  EXPECT_EQ(value("dmu_se"), 0.0);  // the only rung is the reference
  EXPECT_NE(read(dir / "study" / "study.md").find("mean over 2 seeds"), std::string::npos);
}

TEST(DemStudy, UnknownVaryNameIsOneLineExitTwo) {
  const fs::path dir = fresh_directory("dem_study_bad_vary");
  EXPECT_EQ(study(dir, {"--vary", "particles,mesh"}), 2);
  const std::string text = read(dir / "cli.txt");
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
  EXPECT_NE(text.find("--vary"), std::string::npos) << text;
  EXPECT_NE(text.find("mesh"), std::string::npos) << text;
  EXPECT_FALSE(fs::exists(dir / "study"));  // checked before the study directory is made
}

}  // namespace
