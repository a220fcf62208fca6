// Output and restart: the field files hold the point and grid arrays the solver has, the XDMF
// names them, and a run restored from a checkpoint continues bit for bit like the uninterrupted
// run (two-phase Terzaghi column, MUSL, semi-implicit drag).
#include <H5Cpp.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "continuum/mpm/checkpoint.hpp"
#include "continuum/mpm/field_writer.hpp"
#include "continuum/mpm/problems.hpp"

using namespace granflow::mpm;

namespace {
std::filesystem::path scratch(const std::string& name) {
  auto p = std::filesystem::path(GRANFLOW_BINARY_DIR) / "test_scratch" / name;
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p;
}
}  // namespace

TEST(MpmOutput, FieldFilesHoldThePointArrays) {
  TerzaghiSpec t;
  t.options.threads = 1;
  auto s = make_terzaghi(t);
  s->run_steps(20);
  const auto dir = scratch("mpm_fields");
  FieldWriter w(dir);
  const auto h5 = w.write(*s);
  s->run_steps(5);
  w.write(*s);
  H5::H5File f(h5.string(), H5F_ACC_RDONLY);
  H5::DataSet d = f.openDataSet("/liquid/pressure");
  hsize_t dims[1];
  d.getSpace().getSimpleExtentDims(dims);
  ASSERT_EQ(dims[0], s->liquid().size());
  H5::DataSet xy = f.openDataSet("/solid/xy");
  hsize_t d2[2];
  xy.getSpace().getSimpleExtentDims(d2);
  EXPECT_EQ(d2[0], s->solid().size());
  EXPECT_EQ(d2[1], 2u);
  std::ifstream collection(dir / "fields.xmf");
  std::stringstream text;
  text << collection.rdbuf();
  // Two time steps, each with solid, liquid and grid.
  EXPECT_NE(text.str().find("step_00000020.h5:/liquid/pressure"), std::string::npos);
  EXPECT_NE(text.str().find("step_00000025.h5:/grid/quads"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir / "step_00000025.xmf"));
}

TEST(MpmOutput, RestartReproducesTheUninterruptedRunBitForBit) {
  TerzaghiSpec t;
  t.options.threads = 1;
  t.options.dt_update_interval = 7;  // the critical step is re-evaluated across the restart
  auto full = make_terzaghi(t);
  full->run_steps(30);
  const auto file = scratch("mpm_restart") / "checkpoint.h5";
  write_checkpoint(file, *full);
  full->run_steps(40);

  auto restarted = make_terzaghi(t);
  read_checkpoint(file, *restarted);
  EXPECT_EQ(restarted->steps(), 30);
  restarted->run_steps(40);
  EXPECT_EQ(restarted->time(), full->time());
  for (std::size_t p = 0; p < full->liquid().size(); ++p) {
    EXPECT_EQ(restarted->liquid().pressure[p], full->liquid().pressure[p]);
    EXPECT_EQ(restarted->liquid().y[p], full->liquid().y[p]);
  }
  for (std::size_t p = 0; p < full->solid().size(); ++p) {
    EXPECT_EQ(restarted->solid().syy[p], full->solid().syy[p]);
    EXPECT_EQ(restarted->solid().vy[p], full->solid().vy[p]);
  }
}
