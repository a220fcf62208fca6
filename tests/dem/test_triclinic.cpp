// Triclinic regression for Debian's LIGGGHTS 3.8.0 (upstream bug domain.cpp:144-145, repaired by
// granflow-dem): two spheres overlapping across the periodic x boundary must interact in a
// zero-tilt prism box exactly as in an orthogonal block (liggghts-study.md section 3.1; the stock
// binary gives no ghost atoms, zero force and zero kinetic energy in the prism box).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "tests/dem/driver_runner.hpp"

namespace {

using granflow::dem::testing::fresh_directory;
using granflow::dem::testing::run_driver;

// Two 1 mm spheres at x = 0.3 mm and 11.7 mm in a 12 mm box: 0.6 mm apart through the x
// boundary, i.e. 0.4 mm overlap. No shear (gf_shear_rate 0): the driver samples P^vir and
// T = sum |v|^2 / (3 N) every 10 steps for 30 steps.
std::string two_sphere_deck(const std::string& region) {
  return granflow::dem::testing::driver_deck_header(30, 10, 2500) +
         fmt::format(R"(region          box {} units box
create_box      1 box
neighbor        0.0002 bin
neigh_modify    delay 0
fix m1 all property/global youngsModulus peratomtype 1.e7
fix m2 all property/global poissonsRatio peratomtype 0.3
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.7
fix m4 all property/global coefficientFriction peratomtypepair 1 0.5
pair_style      gran model hertz tangential history
pair_coeff      * *
timestep        1e-6
create_atoms    1 single 0.0003 0.006 0.006 units box
create_atoms    1 single 0.0117 0.006 0.006 units box
set             group all diameter 0.001 density 2500
fix             integr all nve/sphere
compute         gf_virial all pressure thermo_temp virial
thermo_style    custom step atoms ke c_gf_virial[1]
thermo          10
)",
                     region);
}

granflow::dem::testing::DriverRun run_two_spheres(const std::string& name,
                                                  const std::string& region, int ranks) {
  const auto dir = fresh_directory(name);
  std::ofstream(dir / "in.granflow") << two_sphere_deck(region);
  return run_driver(dir, ranks);
}

TEST(DemTriclinic, PairAcrossPeriodicBoundaryInteractsAsInOrthogonalBox) {
  const auto block = run_two_spheres("triclinic_block", "block 0 0.012 0 0.012 0 0.012", 1);
  const auto prism = run_two_spheres("triclinic_prism", "prism 0 0.012 0 0.012 0 0.012 0 0 0", 1);
  ASSERT_EQ(block.status, 0) << block.output;
  ASSERT_EQ(prism.status, 0) << prism.output;
  ASSERT_EQ(block.series.rows(), 3u);
  ASSERT_EQ(prism.series.rows(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    const double pxx = block.series.at("Pvir_xx")[i];
    const double t = block.series.at("T")[i];
    // The spheres must interact (the stock binary gives exactly 0 for both): a contact virial
    // (its sign changes once damping dominates the separating pair) and kinetic energy.
    EXPECT_NE(pxx, 0.0);
    EXPECT_GT(t, 0.0);
    // Same physics in both boxes; only the periodic-image arithmetic (lamda vs box coordinates)
    // differs, so agreement is at round-off level (1e-9 relative allows ~1e6 ulp of growth).
    EXPECT_NEAR(prism.series.at("Pvir_xx")[i] / pxx, 1.0, 1e-9) << "sample " << i;
    EXPECT_NEAR(prism.series.at("T")[i] / t, 1.0, 1e-9) << "sample " << i;
    EXPECT_EQ(prism.series.at("Z")[i], block.series.at("Z")[i]);
  }
  // Head-on central repulsion of equal spheres: total momentum stays zero.
  EXPECT_NEAR(prism.series.at("momentum_x")[2], 0.0, 1e-15);
}

TEST(DemTriclinic, TwoRanksGiveTheSameInteraction) {
  // With 2 ranks the spheres sit on different ranks (x split): the stock binary hangs here.
  const auto serial =
      run_two_spheres("triclinic_prism_np1", "prism 0 0.012 0 0.012 0 0.012 0 0 0", 1);
  const auto parallel =
      run_two_spheres("triclinic_prism_np2", "prism 0 0.012 0 0.012 0 0.012 0 0 0", 2);
  ASSERT_EQ(serial.status, 0) << serial.output;
  ASSERT_EQ(parallel.status, 0) << parallel.output;
  ASSERT_EQ(parallel.series.rows(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    // Two particles: sums differ only in reduction order (round-off).
    EXPECT_NEAR(parallel.series.at("Pvir_xx")[i] / serial.series.at("Pvir_xx")[i], 1.0, 1e-9);
    EXPECT_NEAR(parallel.series.at("T")[i] / serial.series.at("T")[i], 1.0, 1e-9);
  }
}

}  // namespace
