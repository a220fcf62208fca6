// The multi-regime model as an MPM material: for a homogeneous velocity gradient without spin the
// material's batch update over SoA arrays gives, point by point, the stress and T of the
// MultiRegimePoint driven directly (two independent paths: sign conversion, state packing,
// porosity coupling); its state arrays are named for checkpoints; the registry builds it by name.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <vector>

#include "continuum/mpm/checkpoint.hpp"
#include "continuum/mpm/multi_regime_material.hpp"
#include "continuum/mpm/rheometer.hpp"
#include "core/numerical_failure.hpp"
#include "tests/mpm_rheometer/section4_settings.hpp"

using namespace granflow;

namespace {
using granflow::testing::section4_settings;

// The stress-update view of the solid points sp under the velocity gradient L, one thread.
mpm::StressUpdateView view_of(mpm::SolidPoints& sp, std::vector<double>& Lxx,
                              std::vector<double>& Lxy, std::vector<double>& Lyx,
                              std::vector<double>& Lyy, double* conductivity = nullptr) {
  return {Lxx.data(),
          Lxy.data(),
          Lyx.data(),
          Lyy.data(),
          sp.porosity.data(),
          sp.temperature.data(),
          sp.sxx.data(),
          sp.syy.data(),
          sp.szz.data(),
          sp.sxy.data(),
          1,
          conductivity};
}
}  // namespace

TEST(MpmRheometerMaterial, BatchUpdateEqualsThePointModel) {
  const auto settings = section4_settings();
  mpm::MultiRegimeInitialState init;
  init.effective_pressure = 50e3;
  mpm::MultiRegimeMaterial m(settings, init);
  const std::size_t n = 3;
  mpm::SolidPoints sp;
  sp.resize(n);
  const double porosity0 = 0.818 / 1.818;
  for (std::size_t p = 0; p < n; ++p) sp.porosity[p] = porosity0;
  m.attach(0, n);
  m.initialize(sp);
  EXPECT_DOUBLE_EQ(sp.sxx[0], -50e3);  // isotropic σ' = -p' I (tension positive)
  EXPECT_DOUBLE_EQ(sp.sxy[0], 0.0);
  // Pure shear without spin at three rates (rate-dependent parts differ per point).
  const double rates[n] = {1.0, 10.0, 100.0};
  std::vector<double> Lxx(n, 0.0), Lyy(n, 0.0), Lxy(n), Lyx(n);
  for (std::size_t p = 0; p < n; ++p) Lxy[p] = Lyx[p] = 0.5 * rates[p];
  continuum::MultiRegimePoint point(settings);
  std::vector<continuum::PointState> ref(n);
  for (std::size_t p = 0; p < n; ++p) ref[p] = point.initial_state(0.818, 50e3, 1.0, 0.0);
  const double dt = 1e-4;
  continuum::StressParts parts[n];
  std::vector<double> conductivity(n, -1.0);
  for (int step = 0; step < 200; ++step) {
    const mpm::StressUpdateView v = view_of(sp, Lxx, Lxy, Lyx, Lyy, conductivity.data());
    m.update_stress(v, dt);
    for (std::size_t p = 0; p < n; ++p) {
      Eigen::Matrix3d rate = Eigen::Matrix3d::Zero();  // compression positive: -D
      rate(0, 1) = rate(1, 0) = -0.5 * rates[p];
      parts[p] = point.advance(ref[p], rate, dt);
      // isochoric: the solver's porosity stays (n = 1 - V_s/V with tr D = 0)
    }
  }
  for (std::size_t p = 0; p < n; ++p) {
    const Eigen::Matrix3d total = parts[p].total_without_pore_pressure();
    const double scale = std::max(1.0, total.norm());
    // Same arithmetic in the same order: agreement to round-off (1e-10 relative).
    EXPECT_NEAR(sp.sxx[p], -total(0, 0), 1e-10 * scale) << p;
    EXPECT_NEAR(sp.syy[p], -total(1, 1), 1e-10 * scale) << p;
    EXPECT_NEAR(sp.szz[p], -total(2, 2), 1e-10 * scale) << p;
    EXPECT_NEAR(sp.sxy[p], -total(0, 1), 1e-10 * scale) << p;
    EXPECT_NEAR(sp.temperature[p], ref[p].granular_temperature,
                1e-10 * std::max(1e-12, ref[p].granular_temperature))
        << p;
    EXPECT_NEAR(m.locus_size()[p], ref[p].force_chains.r_c, 1e-10 * 50e3) << p;
    EXPECT_GE(sp.temperature[p], 0.0);
    // κ_T reported for the solver's conduction: ρ_p d f4 T^½ at the point's state.
    const auto& cp = settings.collisional_parameters;
    const double kappa = granflow::model::collisional_conductivity(
        cp, granflow::model::collisional_coefficients(cp, ref[p].solid_fraction),
        ref[p].granular_temperature);
    EXPECT_NEAR(conductivity[p], kappa, 1e-10 * std::max(1e-12, kappa)) << p;
  }
  EXPECT_GT(conductivity[2], 0.0);  // sheared at 100 1/s: T > 0, so κ_T > 0
  // The skeleton sheared: σ_xy non-zero (the test cannot pass on an idle material).
  EXPECT_GT(std::fabs(sp.sxy[0]), 100.0);
  EXPECT_EQ(m.state().size(), 10u);  // σ_FC (4), χ (4), r_c, e: checkpointed
}

TEST(MpmRheometerMaterial, BuiltFromTypedSettingsAndInitialState) {
  mpm::MultiRegimeMaterial m(section4_settings(), mpm::MultiRegimeInitialState{50e3, 1.0, 0.0});
  EXPECT_EQ(m.name(), "multi_regime");
  EXPECT_DOUBLE_EQ(m.grain_density(), 2650.0);
  EXPECT_GT(m.p_wave_modulus(), 1e6);  // skeleton at 50 kPa: K ≈ 28 MPa
}

// Checkpoint/restart with the multi-regime material: its state arrays (σ_FC, χ, r_c, e) and T go
// through checkpoint.h5, so a restarted rheometer continues bit for bit through the skeleton's
// collapse.
TEST(MpmRheometerMaterial, RestartReproducesTheUninterruptedRunBitForBit) {
  mpm::RheometerSpec spec = granflow::testing::section4_small_rheometer();
  spec.options.flip = 0.95;
  const long first = 300, second = 300;  // 300 steps ≈ 1 ms: the peak of τ̄ lies in the second
  auto a = mpm::make_rheometer(spec);
  a.solver->run_steps(first);
  const auto file =
      std::filesystem::path(GRANFLOW_BINARY_DIR) / "test_scratch" / "rheometer_checkpoint.h5";
  std::filesystem::create_directories(file.parent_path());
  mpm::write_checkpoint(file, *a.solver);
  a.solver->run_steps(second);
  auto b = mpm::make_rheometer(spec);
  mpm::read_checkpoint(file, *b.solver);
  b.solver->run_steps(second);
  const auto& sa = a.solver->solid();
  const auto& sb = b.solver->solid();
  ASSERT_EQ(sa.size(), sb.size());
  double max_sxy = 0;
  for (std::size_t p = 0; p < sa.size(); ++p) {
    EXPECT_EQ(sa.sxy[p], sb.sxy[p]) << p;
    EXPECT_EQ(sa.temperature[p], sb.temperature[p]) << p;
    EXPECT_EQ(sa.x[p], sb.x[p]) << p;
    EXPECT_EQ(a.material->locus_size()[p], b.material->locus_size()[p]) << p;
    max_sxy = std::max(max_sxy, std::fabs(sa.sxy[p]));
  }
  for (std::size_t p = 0; p < a.solver->liquid().size(); ++p)
    EXPECT_EQ(a.solver->liquid().pressure[p], b.solver->liquid().pressure[p]) << p;
  EXPECT_GT(max_sxy, 1e3);  // the skeleton was sheared (not a trivial state)
}

// The MPM's plane-strain point update (MultiRegimePoint::advance_plane) against the 3 × 3 one it
// stands for (advance_mass_balanced), two paths through the same closures: a skeleton with force
// chains, one below the fluidization size (advance_plane's own branch for a skeleton that
// fluidizes in this update), and one already fluidized, in the seed's section-4 material (liquid
// on) with the contacts' dense-flow stress switched on too, under compaction plus shear.
// Agreement to round-off: 1e-10 relative (η_COL is taken at the Riccati T^½, the 3 × 3 path at
// sqrt(T); they differ in the last bits).
TEST(MpmRheometerMaterial, PlaneUpdateEqualsTheThreeByThreeUpdate) {
  auto settings = section4_settings();
  settings.inertial_contact = 0.08;
  settings.viscous_contact = 0.4;
  const continuum::MultiRegimePoint point(settings);
  const double fluidization = settings.force_chain_parameters.fluidization_size;
  struct Start {
    double effective_pressure;
    bool fluidized;
  };
  for (const Start start :
       {Start{50e3, false}, Start{0.1 * fluidization, false}, Start{0.1 * fluidization, true}}) {
    continuum::PointState plane = point.initial_state(0.818, start.effective_pressure, 1.0, 1e-4);
    plane.force_chains.fluidized = start.fluidized;
    continuum::PointState full = plane;
    const double exx = 0.3, eyy = 1.2, exy = -4.0, dt = 1e-4;  // compression positive, 1/s
    bool crossed = false;  // the skeleton fluidized or regrew during the run
    Eigen::Matrix3d rate = Eigen::Matrix3d::Zero();
    rate(0, 0) = exx, rate(1, 1) = eyy, rate(0, 1) = rate(1, 0) = exy;
    for (int step = 0; step < 50; ++step) {
      const double volume_factor = std::exp(-(exx + eyy) * dt);
      const bool was_fluid = full.force_chains.fluidized;
      const continuum::PlaneStep a = point.advance_plane(plane, exx, eyy, exy, dt, volume_factor);
      const Eigen::Matrix3d b =
          point.advance_mass_balanced(full, rate, dt, volume_factor).total_without_pore_pressure();
      const double scale = std::max(1.0, b.norm());
      EXPECT_NEAR(a.xx, b(0, 0), 1e-10 * scale) << step;
      EXPECT_NEAR(a.yy, b(1, 1), 1e-10 * scale) << step;
      EXPECT_NEAR(a.zz, b(2, 2), 1e-10 * scale) << step;
      EXPECT_NEAR(a.xy, b(0, 1), 1e-10 * scale) << step;
      EXPECT_NEAR(plane.granular_temperature, full.granular_temperature,
                  1e-10 * full.granular_temperature)
          << step;
      EXPECT_NEAR(plane.force_chains.void_ratio, full.force_chains.void_ratio, 1e-12) << step;
      EXPECT_EQ(plane.force_chains.fluidized, full.force_chains.fluidized) << step;
      EXPECT_NEAR(plane.force_chains.r_c, full.force_chains.r_c, 1e-10 * start.effective_pressure)
          << step;
      EXPECT_NEAR((plane.force_chains.plastic_strain - full.force_chains.plastic_strain).norm(),
                  0.0, 1e-14)
          << step;
      crossed = crossed || full.force_chains.fluidized != was_fluid;
    }
    // each start crosses the transition (measured: the loose skeleton at 50 kPa fluidizes under
    // this shear, the two without a skeleton regrow under the compaction), so both branches of
    // the plane update meet the 3 × 3 one
    EXPECT_TRUE(crossed) << start.effective_pressure << (start.fluidized ? " fluidized" : "");
  }
}

// The solver updates the local multi-regime material from inside its parallel region, each
// thread over its part of the points (update_range), and combines the threads' results once
// (finish_ranges): the parts give the whole update bit for bit (stress, T, r_c, the largest σ_FC
// behind the CFL modulus); a failed point is reported by finish_ranges, not thrown from a thread;
// the non-local material (ℓ > 0) averages over neighbours and is never updated in parts.
TEST(MpmRheometerMaterial, RangesEqualTheWholeUpdateBitForBit) {
  const auto settings = section4_settings();
  const mpm::MultiRegimeInitialState init{50e3, 1.0, 0.0};
  mpm::MultiRegimeMaterial whole(settings, init), parts(settings, init);
  const std::size_t n = 5;
  mpm::SolidPoints a, b;
  for (auto* sp : {&a, &b}) {
    sp->resize(n);
    for (std::size_t p = 0; p < n; ++p) sp->porosity[p] = 0.818 / 1.818;
  }
  whole.attach(0, n);
  parts.attach(0, n);
  whole.initialize(a);
  parts.initialize(b);
  ASSERT_TRUE(parts.updates_points_independently());
  std::vector<double> Lxx(n), Lyy(n), Lxy(n), Lyx(n);
  for (std::size_t p = 0; p < n; ++p) {  // shear at 1-300 1/s with some compaction and spin
    Lxy[p] = 0.5 * std::pow(4.0, static_cast<double>(p)) + 0.1;
    Lyx[p] = Lxy[p] - 0.2;
    Lxx[p] = -0.01 * static_cast<double>(p);
    Lyy[p] = 0.0;
  }
  auto view = [&](mpm::SolidPoints& sp) { return view_of(sp, Lxx, Lxy, Lyx, Lyy); };
  for (int step = 0; step < 100; ++step) {
    whole.update_stress(view(a), 1e-4);
    parts.begin_ranges(2);
    parts.update_range(view(b), 1e-4, 3, 5, 1);
    parts.update_range(view(b), 1e-4, 0, 3, 0);
    parts.finish_ranges(view(b));
  }
  for (std::size_t p = 0; p < n; ++p) {
    EXPECT_EQ(a.sxx[p], b.sxx[p]) << p;
    EXPECT_EQ(a.sxy[p], b.sxy[p]) << p;
    EXPECT_EQ(a.szz[p], b.szz[p]) << p;
    EXPECT_EQ(a.temperature[p], b.temperature[p]) << p;
    EXPECT_EQ(whole.locus_size()[p], parts.locus_size()[p]) << p;
  }
  EXPECT_EQ(whole.p_wave_modulus(), parts.p_wave_modulus());
  EXPECT_GT(std::fabs(a.sxy[0]), 100.0);  // sheared: not an idle update
  // A non-finite rate at point 3: update_range records it, finish_ranges throws.
  Lxy[3] = std::numeric_limits<double>::quiet_NaN();
  parts.begin_ranges(2);
  EXPECT_NO_THROW(parts.update_range(view(b), 1e-4, 3, 5, 1));
  EXPECT_NO_THROW(parts.update_range(view(b), 1e-4, 0, 3, 0));
  try {
    parts.finish_ranges(view(b));
    ADD_FAILURE() << "no failure reported";
  } catch (const granflow::core::NumericalFailure& f) {
    EXPECT_EQ(f.point, "solid point 3");
  }
  parts.set_internal_length(0.01);
  EXPECT_FALSE(parts.updates_points_independently());
}
