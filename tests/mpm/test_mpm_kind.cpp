// The `mpm` case kind end to end: the case files of cases/mpm/ validate, run into a run directory
// and report the summary keys with the accuracy of the solver tests; bad input names
// the key.
#include <H5Cpp.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "continuum/mpm/mpm_kind.hpp"
#include "core/case.hpp"
#include "core/kind_registry.hpp"
#include "core/run.hpp"

using namespace granflow;

namespace {
// Runs cases/mpm/FILE into test_scratch/kind_FILE<tag> (tests that ctest may run at once on one
// case give different tags).
core::Summary run_case(const std::string& file, const std::vector<std::string>& overrides = {},
                       const std::string& tag = "") {
  core::KindRegistry registry;
  mpm::register_mpm_kinds(registry);
  const auto path = std::filesystem::path(GRANFLOW_SOURCE_DIR) / "cases" / "mpm" / file;
  const auto [kind, test] = core::peek_kind(path);
  const auto& entry = registry.find(kind, test, path.string());
  std::vector<std::string> all = overrides;
  all.push_back("numerics.threads=1");
  const core::Case c = core::Case::load(path, all, entry.schema);
  entry.check(c);
  const auto dir =
      std::filesystem::path(GRANFLOW_BINARY_DIR) / "test_scratch" / ("kind_" + file + tag);
  core::RunContext ctx(c, dir, /*force=*/true, /*quiet=*/true);
  EXPECT_EQ(entry.run(ctx), core::exit_ok);
  ctx.finish();
  EXPECT_TRUE(std::filesystem::exists(dir / "fields" / "solid.xmf"));
  return core::Summary::read(dir / "summary.json");
}

void expect_common_keys(const core::Summary& s) {
  for (const char* key :
       {"cost.wall_s", "cost.steps", "cost.particle_updates_per_s", "mpm.particles_solid",
        "mpm.particles_liquid", "mpm.dt", "mass.solid_rel_change", "mass.liquid_rel_change"}) {
    EXPECT_TRUE(s.contains(key)) << key;
  }
  // Point masses never change: exactly zero.
  EXPECT_EQ(s.get("mass.solid_rel_change"), 0.0);
  EXPECT_EQ(s.get("mass.liquid_rel_change"), 0.0);
}
}  // namespace

TEST(MpmKind, TerzaghiCaseRunsAndMatchesTheSeries) {
  const core::Summary s = run_case("terzaghi.yaml");
  expect_common_keys(s);
  EXPECT_EQ(s.get("mpm.particles_solid"), 40);  // 1 x 10 cells x 2 x 2
  EXPECT_EQ(s.get("mpm.particles_liquid"), 40);
  // Same bounds as test_mpm_terzaghi (h = H/10): measured 3.5e-2 and 1.4e-3.
  EXPECT_LT(s.get("terzaghi.l2_err_pressure"), 0.05);
  EXPECT_LT(s.get("terzaghi.settlement_err"), 0.005);
}

TEST(MpmKind, CouetteAndColumnCasesRun) {
  const core::Summary c = run_case("couette.yaml");
  expect_common_keys(c);
  EXPECT_LT(c.get("couette.l2_err_velocity"), 5e-3);  // as test_mpm_couette (measured 6.6e-4)
  const core::Summary e = run_case("elastic_column.yaml");
  expect_common_keys(e);
  EXPECT_LT(e.get("column.l2_err_stress"), 0.02);  // as test_mpm_elastic_column (1.4e-2)
}

TEST(MpmKind, BadGeometryNamesTheKey) {
  core::KindRegistry registry;
  mpm::register_mpm_kinds(registry);
  const auto path = std::filesystem::path(GRANFLOW_SOURCE_DIR) / "cases/mpm/terzaghi.yaml";
  const auto& entry = registry.find("mpm", "terzaghi", path.string());
  const core::Case c = core::Case::load(path, {"geometry.cell=0.3"}, entry.schema);
  try {
    entry.check(c);
    FAIL() << "a cell size that does not divide the height was accepted";
  } catch (const core::CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("geometry.cell"), std::string::npos) << e.what();
  }
}

TEST(MpmKind, FlipAndPicRelaxationTimeAreExclusive) {
  core::KindRegistry registry;
  mpm::register_mpm_kinds(registry);
  // elastic_column.yaml gives neither key (terzaghi.yaml gives flip: 1.0).
  const auto path = std::filesystem::path(GRANFLOW_SOURCE_DIR) / "cases/mpm/elastic_column.yaml";
  const auto& entry = registry.find("mpm", "elastic_column", path.string());
  const core::Case ok = core::Case::load(path, {"numerics.pic_relaxation_time=1e-3"}, entry.schema);
  EXPECT_NO_THROW(entry.check(ok));
  const core::Case both = core::Case::load(
      path, {"numerics.flip=0.99", "numerics.pic_relaxation_time=1e-3"}, entry.schema);
  try {
    entry.check(both);
    FAIL() << "a per-step flip and a PIC relaxation time were both accepted";
  } catch (const core::CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("numerics.pic_relaxation_time"), std::string::npos)
        << e.what();
  }
}

TEST(MpmKind, TerzaghiFieldFramesSpanTheWholeRunFromTimeZero) {
  // Three isochrones (T_v 0.05, 0.2, 0.5) run as three segments; the 10 frames are spaced on the
  // last isochrone's time t_end over the whole run, plus t = 0. (They were written in the last
  // segment only: no t = 0 frame, none before 0.2 t_end, and frames one step apart at its start.)
  run_case("terzaghi.yaml", {"output.frames=10"}, "_frames");
  const auto dir = std::filesystem::path(GRANFLOW_BINARY_DIR) / "test_scratch" /
                   "kind_terzaghi.yaml_frames" / "fields";
  std::vector<double> times;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".h5") continue;
    H5::H5File file(entry.path().string(), H5F_ACC_RDONLY);
    double t = 0;
    file.openGroup("/").openAttribute("time").read(H5::PredType::NATIVE_DOUBLE, &t);
    times.push_back(t);
  }
  std::sort(times.begin(), times.end());
  ASSERT_EQ(times.size(), 11u);
  EXPECT_EQ(times.front(), 0.0);
  const double t_end = times.back();
  for (std::size_t k = 1; k < times.size(); ++k)  // each within a time step of k t_end / 10
    EXPECT_NEAR(times[k], t_end * static_cast<double>(k) / 10, 0.02 * t_end) << k;
}
