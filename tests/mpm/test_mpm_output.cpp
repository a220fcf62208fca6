// Output and restart: the field files hold the point and grid arrays the solver has, the XDMF
// names them, and a run restored from a checkpoint continues bit for bit like the uninterrupted
// run (two-phase Terzaghi column, MUSL, semi-implicit drag).
#include <H5Cpp.h>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "continuum/mpm/checkpoint.hpp"
#include "continuum/mpm/field_writer.hpp"
#include "continuum/mpm/problems.hpp"
#include "core/process.hpp"
#include "core/run.hpp"

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
  // Three XDMF 3 series (solid, liquid, grid) with two frames each; no per-step XDMF.
  for (const char* series : {"solid.xmf", "liquid.xmf", "grid.xmf"}) {
    std::ifstream in(dir / series);
    std::stringstream text;
    text << in.rdbuf();
    EXPECT_NE(text.str().find("step_00000020.h5:/"), std::string::npos) << series;
    EXPECT_NE(text.str().find("step_00000025.h5:/"), std::string::npos) << series;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "step_00000025.xmf"));
}

// The series open in meshio (the reader of Python users; ParaView's default reader takes the same
// XDMF 3): frame count and times, one vertex cell per point, quads for the grid, vector and tensor
// shapes, the grid at t = 0 holding the projected mass, units on every HDF5 dataset.
TEST(MpmOutput, XdmfSeriesOpenInMeshio) {
  TerzaghiSpec t;
  t.options.threads = 1;
  auto s = make_terzaghi(t);
  const auto dir = scratch("mpm_xdmf");
  FieldWriter w(dir);
  std::vector<std::string> argv = {granflow::core::python_interpreter(),
                                   std::string(GRANFLOW_SOURCE_DIR) + "/tests/mpm/check_xdmf.py",
                                   dir.string()};
  std::vector<double> times;
  for (int k = 0; k < 3; ++k) {
    if (k) s->run_steps(10);
    w.write(*s);
    times.push_back(s->time());
  }
  const auto& grid = std::get<CartesianGrid>(s->grid());
  const std::size_t nodes = static_cast<std::size_t>(grid.nodes()),
                    cells = static_cast<std::size_t>(grid.cells_x() * grid.cells_y());
  for (std::size_t n : {s->solid().size(), s->liquid().size(), nodes, cells})
    argv.push_back(std::to_string(n));
  for (double time : times) argv.push_back(fmt::format("{:.17g}", time));
  const auto r = granflow::core::run_process(argv);
  EXPECT_TRUE(r.ok()) << "check_xdmf.py: exit " << r.status << " " << r.error
                      << " (python3-meshio and python3-h5py are dependencies)";
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
