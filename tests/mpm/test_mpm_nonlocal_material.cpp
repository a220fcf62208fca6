// The multi-regime material with an internal length (MultiRegimeMaterial::set_internal_length):
// ℓ = 0 is the local model bit for bit; a homogeneous deformation is not changed by the average
// (round-off); a single sheared point among points at rest shares its softening with its
// neighbours (the over-nonlocal m = 2: the sheared point itself softens less than locally, or
// hardens) and leaves points beyond the cutoff 2.5 ℓ nearly as they were (only the return
// mapping of the softened neighbours reaches them: 1e-5 in 10 steps); threads change no bit.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <vector>

#include "continuum/mpm/checkpoint.hpp"
#include "continuum/mpm/multi_regime_material.hpp"
#include "continuum/mpm/rheometer.hpp"
#include "tests/mpm_rheometer/section4_settings.hpp"

using namespace granflow;

namespace {
using granflow::testing::section4_settings;

// A row of n points 1 mm apart (volume 1 mm²), pure shear at rate[i] without spin, `steps`
// steps of dt; returns the material after the run and the solid points.
struct Row {
  std::size_t n;
  mpm::SolidPoints sp;
  std::vector<double> Lxx, Lyy, Lxy, Lyx, vol;
  mpm::MultiRegimeMaterial m;
  Row(std::size_t n_, double length, const std::vector<double>& rate)
      : n(n_),
        Lxx(n_, 0.0),
        Lyy(n_, 0.0),
        Lxy(n_),
        Lyx(n_),
        vol(n_, 1e-6),
        m(section4_settings(), mpm::MultiRegimeInitialState{}) {
    sp.resize(n);
    for (std::size_t p = 0; p < n; ++p) {
      sp.porosity[p] = 0.818 / 1.818;
      sp.x[p] = 1e-3 * static_cast<double>(p);
      sp.y[p] = 0.0;
      Lxy[p] = Lyx[p] = 0.5 * rate[p];
    }
    m.attach(0, n);
    m.initialize(sp);
    if (length >= 0) m.set_internal_length(length);
  }
  void run(int steps, double dt, int threads) {
    for (int s = 0; s < steps; ++s) {
      mpm::StressUpdateView v{Lxx.data(),
                              Lxy.data(),
                              Lyx.data(),
                              Lyy.data(),
                              sp.porosity.data(),
                              sp.temperature.data(),
                              sp.sxx.data(),
                              sp.syy.data(),
                              sp.szz.data(),
                              sp.sxy.data(),
                              threads,
                              nullptr,
                              sp.x.data(),
                              sp.y.data(),
                              vol.data()};
      m.update_stress(v, dt);
    }
  }
};
}  // namespace

TEST(MpmNonlocalMaterial, LengthZeroIsTheLocalModelBitForBit) {
  std::vector<double> rate(30);
  for (std::size_t p = 0; p < rate.size(); ++p) rate[p] = 5.0 + 3.0 * std::sin(0.7 * p);
  Row local(30, -1.0, rate), off(30, 0.0, rate);
  local.run(100, 1e-4, 1);
  off.run(100, 1e-4, 1);
  EXPECT_EQ(off.m.internal_length(), 0.0);
  for (std::size_t p = 0; p < 30; ++p) {
    ASSERT_EQ(off.sp.sxy[p], local.sp.sxy[p]);
    ASSERT_EQ(off.sp.sxx[p], local.sp.sxx[p]);
    ASSERT_EQ(off.m.locus_size()[p], local.m.locus_size()[p]);
  }
}

TEST(MpmNonlocalMaterial, HomogeneousShearIsUnchangedByTheAverage) {
  std::vector<double> rate(30, 5.0);
  Row local(30, -1.0, rate), nl(30, 4e-3, rate);
  local.run(100, 1e-4, 1);
  nl.run(100, 1e-4, 1);
  const double rc0 = std::sqrt(3.0) * 50e3;
  EXPECT_LT(local.m.locus_size()[0], 0.99 * rc0);  // it did soften
  for (std::size_t p = 0; p < 30; ++p) {
    EXPECT_NEAR(nl.m.locus_size()[p], local.m.locus_size()[p], 1e-9 * rc0) << p;
    EXPECT_NEAR(nl.sp.sxy[p], local.sp.sxy[p], 1e-9 * 50e3) << p;
  }
}

TEST(MpmNonlocalMaterial, OneShearedPointSharesItsSofteningWithinTheLength) {
  const std::size_t n = 41, c = 20;
  std::vector<double> rate(n, 0.0);
  rate[c] = 5.0;
  Row local(n, -1.0, rate), nl(n, 4e-3, rate), nl2(n, 4e-3, rate);
  // 10 steps of 1e-4 s at 5 1/s: γ = 0.005 at the centre, early in its softening
  local.run(10, 1e-4, 1);
  nl.run(10, 1e-4, 1);
  nl2.run(10, 1e-4, 2);
  const double rc0 = std::sqrt(3.0) * 50e3;
  const auto& a = local.m.locus_size();
  const auto& b = nl.m.locus_size();
  EXPECT_LT(a[c], 0.99 * rc0);            // locally, the sheared point softens
  EXPECT_EQ(a[c - 1], rc0);               // and nothing else does
  EXPECT_GT(b[c], a[c]);                  // non-locally it softens less (over-nonlocal: may harden)
  for (std::size_t d = 1; d <= 3; ++d) {  // the nearest neighbours soften
    EXPECT_LT(b[c - d], rc0) << d;
    EXPECT_LT(b[c + d], rc0) << d;
    EXPECT_NEAR(b[c - d], b[c + d], 1e-6 * rc0) << d;  // symmetric (x rounding: 1e-7)
  }
  for (std::size_t d = 15; d <= 20; ++d) EXPECT_NEAR(b[c - d], rc0, 1e-4 * rc0) << d;  // far
  std::printf(
      "r_c / r_c0: local centre %.6f; non-local centre %.6f, at 1, 4, 7, 10, 15, 20 mm: "
      "%.6f %.6f %.6f %.6f %.6f %.6f\n",
      a[c] / rc0, b[c] / rc0, b[c - 1] / rc0, b[c - 4] / rc0, b[c - 7] / rc0, b[c - 10] / rc0,
      b[c - 15] / rc0, b[c - 20] / rc0);
  for (std::size_t p = 0; p < n; ++p) ASSERT_EQ(nl2.m.locus_size()[p], b[p]);  // 2 threads
}

// Checkpoint/restart with ℓ > 0: the positions and volumes of the last neighbour-list build are
// checkpointed with the state, so the restarted rheometer rebuilds the same lists and continues
// bit for bit through the peak (as the local material does, tests/mpm_rheometer).
TEST(MpmNonlocalMaterial, RestartReproducesTheUninterruptedRunBitForBit) {
  mpm::RheometerSpec spec = granflow::testing::section4_small_rheometer();
  spec.options.pic_relaxation_time = 2.3e-4;
  auto a = mpm::make_rheometer(spec);
  a.material->set_internal_length(4e-3);
  a.solver->run_steps(300);
  const auto file =
      std::filesystem::path(GRANFLOW_BINARY_DIR) / "test_scratch" / "nonlocal_checkpoint.h5";
  std::filesystem::create_directories(file.parent_path());
  mpm::write_checkpoint(file, *a.solver);
  a.solver->run_steps(300);
  auto b = mpm::make_rheometer(spec);
  b.material->set_internal_length(4e-3);
  mpm::read_checkpoint(file, *b.solver);
  b.solver->run_steps(300);
  EXPECT_GT(a.material->nonlocal()->builds(), 0);
  const auto& sa = a.solver->solid();
  const auto& sb = b.solver->solid();
  for (std::size_t p = 0; p < sa.size(); ++p) {
    ASSERT_EQ(sa.sxy[p], sb.sxy[p]) << p;
    ASSERT_EQ(a.material->locus_size()[p], b.material->locus_size()[p]) << p;
  }
}
