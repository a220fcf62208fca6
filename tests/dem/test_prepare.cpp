// DEM preparation (kind: dem_prepare) and the transient constant-volume shear started from it
// (start.preparation), end to end through the granflow program, plus the contact network and
// the transient metrics as pure functions. Two 250-sphere packings at p0 = 100 Pa (frictionless
// and μ_prep = 0.5) are prepared once for the suite (~10-20 s), then sheared over small strains.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/result_file.hpp"
#include "core/run.hpp"
#include "dem_coupling/extraction/contact_network.hpp"
#include "dem_coupling/kind/series_table.hpp"
#include "dem_coupling/kind/transient.hpp"
#include "tests/dem/cli_run.hpp"

namespace {

using granflow::core::Summary;
using granflow::dem::testing::fresh_directory;
using granflow::dem::testing::read;
using granflow::dem::testing::run_cli;

// --- pure functions -------------------------------------------------------------------------

TEST(ContactNetwork, RattlersArePeeledRepeatedly) {
  using granflow::dem::ContactPair;
  const std::array<double, 3> x{1, 0, 0};
  // A ring 0-1-2-3 (two contacts each) with a chain 3-4-5 hanging from it: 5 has one contact,
  // and once it is gone so has 4; the ring stays. Z = 2·6/6, Z* = 2·4/4, x_nr = 4/6.
  const std::vector<ContactPair> pairs{{0, 1, x}, {1, 2, x}, {2, 3, x},
                                       {3, 0, x}, {3, 4, x}, {4, 5, x}};
  const auto s = granflow::dem::network_state(6, pairs);
  EXPECT_DOUBLE_EQ(s.coordination, 2.0);
  EXPECT_DOUBLE_EQ(s.coordination_nonrattler, 2.0);
  EXPECT_DOUBLE_EQ(s.nonrattler_fraction, 4.0 / 6.0);
  // Every contact along x: F = diag(1, 0, 0), F' = diag(2/3, -1/3, -1/3), anisotropy 1.
  EXPECT_DOUBLE_EQ(s.fabric[0], 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(s.fabric[1], -1.0 / 3.0);
  EXPECT_DOUBLE_EQ(s.fabric[3], 0.0);
  EXPECT_NEAR(s.anisotropy, 1.0, 1e-15);
  // An open chain has no 2-core: every particle is a rattler.
  const auto chain = granflow::dem::network_state(3, {{0, 1, x}, {1, 2, x}});
  EXPECT_DOUBLE_EQ(chain.nonrattler_fraction, 0.0);
  EXPECT_DOUBLE_EQ(chain.coordination_nonrattler, 0.0);
}

TEST(ContactNetwork, IsotropicFabricIsTraceFreeZero) {
  // The six directions ±x, ±y, ±z once each: <n n> = I/3, F' = 0.
  using granflow::dem::ContactPair;
  std::vector<ContactPair> pairs;
  const std::array<std::array<double, 3>, 3> axes{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  for (long k = 0; k < 3; ++k) pairs.push_back({k, (k + 1) % 3, axes[k]});  // a triangle
  const auto s = granflow::dem::network_state(3, pairs);
  for (double f : s.fabric) EXPECT_NEAR(f, 0.0, 1e-15);
  EXPECT_NEAR(s.anisotropy, 0.0, 1e-15);
}

TEST(StopMetrics, HaffDecaySampled) {
  // T = T0 / (1 + t/t_H)² sampled every 0.1 t_H: T = 0.1 T0 at t = (√10 - 1) t_H = 2.1623 t_H;
  // ln T is nearly linear over a sample there, so the interpolated time is within 1e-3 t_H.
  std::vector<double> t, T, p;
  for (int i = 1; i <= 100; ++i) {
    t.push_back(0.1 * i);
    T.push_back(2.0 / std::pow(1.0 + 0.1 * i, 2));
    p.push_back(3.0);
  }
  const auto m = granflow::dem::stop_metrics(t, T, p, 2.0, 100.0, 0.1);
  EXPECT_NEAR(m.cooling_time, std::sqrt(10.0) - 1.0, 1e-3);
  EXPECT_DOUBLE_EQ(m.final_temperature_ratio, 1.0 / (11.0 * 11.0));
  EXPECT_DOUBLE_EQ(m.final_p_over_p0, 0.03);
  // Never that cold within the series: -1.
  EXPECT_EQ(granflow::dem::stop_metrics(t, T, p, 2.0, 100.0, 1e-3).cooling_time, -1.0);
  // The shear's rows end at the first row with the strain of the stop.
  const std::vector<double> strain{0.1, 0.2, 0.3, 0.3, 0.3};
  EXPECT_EQ(granflow::dem::shear_rows(strain), 3u);
  EXPECT_EQ(granflow::dem::shear_rows(std::vector<double>{0.1, 0.2}), 2u);
}

TEST(TransientMetrics, ClosedFormDecay) {
  // p = p0 exp(-γ/0.1) falls below 0.05 p0 at γ = 0.1 ln 20 = 0.2996: the first sample after
  // it on a 0.01 grid is 0.30. τ = γ exp(-γ/0.1) peaks at γ = 0.1. Residual over the last 20 %
  // of γ ∈ [0, 1]: the mean of the samples there.
  std::vector<double> strain, p, tau;
  for (int i = 0; i <= 100; ++i) {
    const double g = 0.01 * i;
    strain.push_back(g);
    p.push_back(100.0 * std::exp(-g / 0.1));
    tau.push_back(g * std::exp(-g / 0.1));
  }
  const auto m = granflow::dem::transient_metrics(strain, p, tau, 100.0, 0.05, 0.2);
  EXPECT_NEAR(m.liquefaction_strain, 0.30, 1e-12);
  EXPECT_NEAR(m.peak_strain, 0.1, 1e-12);
  EXPECT_NEAR(m.peak_tau, 0.1 * std::exp(-1.0), 1e-15);
  double mean = 0;
  for (int i = 80; i <= 100; ++i) mean += p[i] / 21.0;
  EXPECT_NEAR(m.residual_p, mean, 1e-12);
  // Never below 0.5 % of p0 for a threshold of 1e-6: -1.
  EXPECT_EQ(granflow::dem::transient_metrics(strain, p, tau, 100.0, 1e-6, 0.2).liquefaction_strain,
            -1.0);
}

// --- end to end -----------------------------------------------------------------------------

std::string preparation_case(double friction) {
  return fmt::format(R"(kind: dem_prepare
name: prep
material:
  diameter: 1.0e-3
  particle_density: 2500
  restitution: 0.7
  youngs_modulus: 1.0e7
  poisson_ratio: 0.3
dem:
  particles: 250
preparation:
  pressure: 100
  friction: {}
  tolerance: 0.02
  kinetic_energy_ratio: 1.0e-3
)",
                     friction);
}

// Constant-volume shear at γ̇ = 2 1/s (I0 = γ̇ d / sqrt(p0/ρ_p) = 0.01) from `preparation`.
const char* shear_case = R"(kind: dem
name: shear
material:
  diameter: 1.0e-3
  particle_density: 2500
  restitution: 0.7
  particle_friction: 0.5
  youngs_modulus: 1.0e7
  poisson_ratio: 0.3
control:
  mode: constant_volume
shear_rate: 2
strain:
  total: 0.3
  sample: 0.002
)";

// One test (ctest runs every test in a process of its own; the preparations are its cost).
TEST(DemPrepare, LooseAndDensePackingsAndTheTransientsFromThem) {
  const auto dir_ = fresh_directory("prepare");
  std::ofstream(dir_ / "dense.yaml") << preparation_case(0.0);
  std::ofstream(dir_ / "loose.yaml") << preparation_case(0.5);
  std::ofstream(dir_ / "shear.yaml") << shear_case;
  const int dense_status_ = run_cli("run dense.yaml --out dense", dir_);
  const std::string dense_log_ = read(dir_ / "cli.txt");
  const int loose_status_ = run_cli("run loose.yaml --out loose", dir_);
  const std::string loose_log_ = read(dir_ / "cli.txt");
  {
    SCOPED_TRACE("the prepared state holds its target stress at rest");
    ASSERT_EQ(dense_status_, 0) << dense_log_;
    ASSERT_EQ(loose_status_, 0) << loose_log_;
    for (const char* run : {"dense", "loose"}) {
      const Summary s = Summary::read(dir_ / run / "summary.json");
      // The stopping rule itself: |p - p0| <= 2 % p0 and kinetic <= 1e-3 elastic energy.
      EXPECT_LE(std::abs(s.get("prepared.p") - 100.0), 2.0) << run;
      EXPECT_LE(s.get("prepared.energy_ratio"), 1e-3) << run;
      EXPECT_GT(s.get("prepared.energy_ratio"), 0.0) << run;  // measured, not a placeholder
      // An isotropic compression leaves σ_yy near p (the fabric anisotropy of 250 spheres is a
      // few %, measured 0.04): within 10 %.
      EXPECT_NEAR(s.get("prepared.sigma_yy"), 100.0, 10.0) << run;
      EXPECT_TRUE(std::filesystem::exists(dir_ / run / "seed_1" / "prepared.restart")) << run;
    }
  }
  {
    SCOPED_TRACE("frictionless preparation is denser and isostatic");
    ASSERT_EQ(dense_status_, 0) << dense_log_;
    ASSERT_EQ(loose_status_, 0) << loose_log_;
    const Summary dense = Summary::read(dir_ / "dense" / "summary.json");
    const Summary loose = Summary::read(dir_ / "loose" / "summary.json");
    // Agnolin & Roux 2007: φ 0.637 frictionless against ~0.59 at μ 0.3 and lower at 0.5 (measured
    // here 0.639 / 0.574 at 500 spheres); seed scatter at 250 spheres ~0.005, so a gap > 0.03.
    EXPECT_GT(dense.get("prepared.phi") - loose.get("prepared.phi"), 0.03);
    // Without rattlers, frictionless packings are isostatic, Z* = 2 d = 6 (+ O(sqrt(δ/d)) for soft
    // contacts; measured 6.3); frictional ones lie between d + 1 = 4 and 6 (measured 4.5).
    EXPECT_GT(dense.get("prepared.Z_nr"), 5.7);
    EXPECT_GE(loose.get("prepared.Z_nr"), 4.0);
    EXPECT_LT(loose.get("prepared.Z_nr"), dense.get("prepared.Z_nr"));
    EXPECT_GT(dense.get("prepared.nonrattler_fraction"), loose.get("prepared.nonrattler_fraction"));
  }
  {
    SCOPED_TRACE("the shear starts at the prepared state; the loose one liquefies");
    ASSERT_EQ(dense_status_, 0) << dense_log_;
    ASSERT_EQ(loose_status_, 0) << loose_log_;
    ASSERT_EQ(run_cli("run shear.yaml --out dense_shear --set start.preparation=dense", dir_), 0)
        << read(dir_ / "cli.txt");
    ASSERT_EQ(run_cli("run shear.yaml --out loose_shear --set start.preparation=loose", dir_), 0)
        << read(dir_ / "cli.txt");
    const Summary prep = Summary::read(dir_ / "dense" / "summary.json");
    const Summary dense = Summary::read(dir_ / "dense_shear" / "summary.json");
    const Summary loose = Summary::read(dir_ / "loose_shear" / "summary.json");
    // Continuity: the first sample (strain 0.002) is the prepared state. The loose packing's p
    // barely moves before γ ≈ 0.005 (measured +0.7 % at 0.002): within 5 % of p0. The dense one
    // dilates at once against the fixed volume (γ d = 0.002 d exceeds the contact overlap ≈ 1e-3
    // d; measured +7 % at 0.002, +30 % at 0.004): within 15 %, and above p0.
    EXPECT_NEAR(loose.get("transient.first_p_over_p0"), 1.0, 0.05);
    EXPECT_NEAR(dense.get("transient.first_p_over_p0"), 1.0, 0.15);
    EXPECT_DOUBLE_EQ(dense.get("transient.p0"), prep.get("prepared.p"));
    EXPECT_DOUBLE_EQ(dense.get("transient.phi0"), prep.get("prepared.phi"));
    const auto strain = granflow::core::read_dataset(dir_ / "dense_shear" / "result.h5",
                                                     "/transient/group_0/strain");
    ASSERT_GT(strain.size(), 100u);
    EXPECT_NEAR(strain.front(), 0.002, 1e-4);
    // The series the docs list, with the sample count of 0.3 / 0.002.
    for (const char* name : {"mean_stress_mean", "mean_stress_min", "mean_stress_max",
                             "shear_stress_mean", "normal_stress_mean", "granular_temperature_mean",
                             "coordination_number_nonrattler_mean", "nonrattler_fraction_mean"})
      EXPECT_EQ(granflow::core::read_dataset(dir_ / "dense_shear" / "result.h5",
                                             std::string("/transient/group_0/") + name)
                    .size(),
                strain.size())
          << name;
    // Constant volume below the critical φ (loose, φ0 ~0.57 < φ_c ~0.585 at μ_p 0.5): the contact
    // network collapses, p' < 5 % of p0 (measured at γ ≈ 0.02). Above it (dense, 0.64): never.
    EXPECT_EQ(loose.get("transient.liquefied"), 1.0);
    EXPECT_LT(loose.get("transient.liquefaction_strain"), 0.3);
    EXPECT_EQ(dense.get("transient.liquefied"), 0.0);
    EXPECT_FALSE(dense.contains("transient.liquefaction_strain"));
    EXPECT_GT(dense.get("transient.p_final_over_p0"), 0.5);
    // The contact network: a rigid frictional packing needs Z* >= d + 1 = 4 (isostatic) to carry
    // load. The loose one loses it (measured at 1000 spheres: Z* 4.3 -> 0.7 by γ 0.045, 1 % of
    // the particles in the network); the dense one keeps Z* above 5 (measured min 5.06).
    const auto z_min = [&](const char* run) {
      const auto z = granflow::core::read_dataset(
          dir_ / run / "result.h5", "/transient/group_0/coordination_number_nonrattler_mean");
      return *std::min_element(z.begin(), z.end());
    };
    EXPECT_LT(z_min("loose_shear"), 4.0);
    EXPECT_GT(z_min("dense_shear"), 4.0);
  }
  {
    SCOPED_TRACE("the shear stopped: the same shear, then the agitation decays at fixed volume");
    ASSERT_EQ(loose_status_, 0) << loose_log_;
    ASSERT_EQ(run_cli("run shear.yaml --out loose_stop --set start.preparation=loose "
                      "--set stop.duration=0.03 --set stop.cooling_fraction=0.8",
                      dir_),
              0)
        << read(dir_ / "cli.txt");
    const Summary sheared = Summary::read(dir_ / "loose_shear" / "summary.json");
    const Summary stopped = Summary::read(dir_ / "loose_stop" / "summary.json");
    // One rank, the same deck up to the stop: the shear and its metrics are the same run's, and
    // the stop's rows do not enter them.
    for (const char* key : {"transient.peak_tau", "transient.residual_tau", "transient.residual_p",
                            "transient.liquefaction_strain"})
      EXPECT_EQ(stopped.get(key), sheared.get(key)) << key;
    const auto h5 = dir_ / "loose_stop" / "result.h5";
    const auto strain = granflow::core::read_dataset(h5, "/transient/group_0/strain");
    EXPECT_EQ(strain.size(), granflow::core::read_dataset(dir_ / "loose_shear" / "result.h5",
                                                          "/transient/group_0/strain")
                                 .size());
    // 0.03 s sampled every 0.002 / γ̇ = 1 ms (in whole steps): 30 rows, 1, 2, ... ms after the stop.
    const auto time = granflow::core::read_dataset(h5, "/transient/group_0/stop/time");
    ASSERT_EQ(time.size(), 30u);
    EXPECT_NEAR(time.front(), 1e-3, 1e-5);  // whole time steps of Δt ≈ 3.9 µs
    const auto T =
        granflow::core::read_dataset(h5, "/transient/group_0/stop/granular_temperature_mean");
    // Nothing drives the stopped sample: T falls (inelastic, frictional contacts; measured 0.44 of
    // the flowing T after 30 ms at 250 spheres, T below 0.8 of it after 2 ms), and it is continuous
    // at the stop (the streaming flow taken out is the profile T was measured about): the first
    // sample within 2x.
    const double flowing = stopped.get("transient.flowing_T");
    EXPECT_GT(flowing, 0.0);
    EXPECT_LT(T.back(), T.front());
    EXPECT_LT(stopped.get("transient.stop_T_over_flowing_T"), 0.9);
    EXPECT_GT(T.front(), 0.5 * flowing);
    EXPECT_LT(T.front(), 2.0 * flowing);
    EXPECT_GT(stopped.get("transient.cooling_time"), 0.0);
    EXPECT_LT(stopped.get("transient.cooling_time"), 0.03);
  }
  {
    SCOPED_TRACE("a drained stop: sheared in water, the loose packing reconsolidates under p0");
    ASSERT_EQ(loose_status_, 0) << loose_log_;
    ASSERT_EQ(run_cli("run shear.yaml --out loose_drained --set start.preparation=loose "
                      "--set liquid.enabled=true --set liquid.viscosity=1e-3 "
                      "--set stop.duration=0.04 --set stop.drainage_length=0.01",
                      dir_),
              0)
        << read(dir_ / "cli.txt");
    const Summary s = Summary::read(dir_ / "loose_drained" / "summary.json");
    const auto h5 = dir_ / "loose_drained" / "result.h5";
    const auto sigma =
        granflow::core::read_dataset(h5, "/transient/group_0/stop/normal_stress_mean");
    const auto phi =
        granflow::core::read_dataset(h5, "/transient/group_0/stop/solid_fraction_mean");
    ASSERT_EQ(sigma.size(), 40u);
    // The liquefied packing (p' < 5 % p0) carries no load at the stop; under σ_n = p0 it compacts
    // while the water drains until its skeleton carries σ_n again (1000 spheres: φ 0.577 -> 0.587,
    // σ_yy = 0.9 σ_n after 17 ms; 250 spheres: φ up by 0.0085, 0.9 σ_n after 17.6 ms): φ up by
    // > 0.003, back to 0.9 σ_n within the 40 ms, and the last 5 ms at σ_n within 10 % (σ_yy of
    // the sample fluctuates by a few %).
    EXPECT_EQ(s.get("transient.liquefied"), 1.0);
    EXPECT_GT(s.get("transient.stop_phi_change"), 0.003);
    EXPECT_GT(s.get("transient.reconsolidation_time"), 0.0);
    EXPECT_LT(s.get("transient.reconsolidation_time"), 0.04);
    double last = 0.0;
    for (std::size_t i = sigma.size() - 5; i < sigma.size(); ++i) last += sigma[i] / 5.0;
    EXPECT_NEAR(last, s.get("transient.p0"), 0.1 * s.get("transient.p0"));
    EXPECT_GT(phi.back(), phi.front());
    // A dry sample has nothing to drain: one line and exit 2.
    EXPECT_EQ(run_cli("run shear.yaml --out x --set start.preparation=loose --set "
                      "stop.duration=0.01 --set stop.drainage_length=0.01",
                      dir_),
              granflow::core::exit_bad_input);
    const std::string out = read(dir_ / "cli.txt");
    EXPECT_NE(out.find("stop.drainage_length"), std::string::npos) << out;
  }
  {
    SCOPED_TRACE("a drained shear in water with a step in the shear rate");
    ASSERT_EQ(loose_status_, 0) << loose_log_;
    ASSERT_EQ(run_cli("run shear.yaml --out loose_step --set start.preparation=loose "
                      "--set liquid.enabled=true --set liquid.viscosity=1e-3 "
                      "--set control.mode=drained --set control.drainage_length=0.01 "
                      "--set rate_step.strain=0.15 --set rate_step.shear_rate=20",
                      dir_),
              0)
        << read(dir_ / "cli.txt");
    const Summary s = Summary::read(dir_ / "loose_step" / "summary.json");
    const auto h5 = dir_ / "loose_step" / "result.h5";
    const auto strain = granflow::core::read_dataset(h5, "/transient/group_0/strain");
    const auto sigma = granflow::core::read_dataset(h5, "/transient/group_0/normal_stress_mean");
    // Sampled every strain.sample at the faster rate (in whole steps: within 2 %), the same steps
    // at 1/10 of the rate before the step: 0.002 after it, 0.0002 before (series.tsv: 10 digits).
    ASSERT_GT(strain.size(), 800u);
    const double after = strain.back() - strain[strain.size() - 2];
    EXPECT_NEAR(after, 2e-3, 4e-5);
    EXPECT_NEAR((strain[1] - strain[0]) / after, 0.1, 1e-7);
    EXPECT_NEAR(strain.back(), 0.3, 2e-3);
    // Before the step the liquid has time to drain (k σ_n ≈ 50 1/s against γ̇ = 2 1/s): the grains
    // carry σ_n (the last 20 % before the step within 15 %: 250 spheres fluctuate by ~10 %) and
    // the loose packing compacts (1000 spheres: φ 0.5745 -> 0.587). The step up to I ≈ 0.1
    // dilates it (1000 spheres: -0.0115), raises μ (μ(I) rises with I: 0.39 -> 0.45) and T (30x;
    // T ∝ (d γ̇)² at a fixed φ would be 100x).
    double before = 0.0;
    int count = 0;
    for (std::size_t i = 0; i < strain.size(); ++i)
      if (strain[i] >= 0.12 && strain[i] <= 0.15) before += sigma[i], ++count;
    EXPECT_NEAR(before / count, s.get("transient.p0"), 0.15 * s.get("transient.p0"));
    EXPECT_GT(s.get("transient.phi_before_step") - s.get("transient.phi0"), 0.003);
    EXPECT_LT(s.get("transient.dilation"), -0.003);
    EXPECT_GT(s.get("transient.dilation_strain"), 0.0);
    EXPECT_GT(s.get("transient.mu_after_step"), s.get("transient.mu_before_step"));
    EXPECT_GT(s.get("transient.T_after_step"), 5.0 * s.get("transient.T_before_step"));
    // Dry, the same law with a constant resistance (control.mode damped_height, R = 100 Pa s,
    // the immersed case's η0 H²/κ at H = 1 cm): the box height obeys σ_yy + R ε̇_yy = σ_n, checked
    // from outside the fix on the sampled height and σ_yy over the last 20 % before the step
    // (measured 71.5 + 28.5 = 99.98 Pa: the loose packing still compacts there; within 3 %, the
    // sampling error of a mean of ~150 samples of a σ_yy that scatters ~20 %), and the compaction
    // and T's rise as in water (1000 spheres: φ 0.5745 -> 0.589, T 30x).
    ASSERT_EQ(run_cli("run shear.yaml --out loose_damped --set start.preparation=loose "
                      "--set control.mode=damped_height --set control.height_resistance=100 "
                      "--set rate_step.strain=0.15 --set rate_step.shear_rate=20",
                      dir_),
              0)
        << read(dir_ / "cli.txt");
    const Summary dry = Summary::read(dir_ / "loose_damped" / "summary.json");
    const auto dry_h5 = dir_ / "loose_damped" / "result.h5";
    const auto series = [&](const char* name) {
      return granflow::core::read_dataset(dry_h5, std::string("/conditions/0/series/") + name);
    };
    const auto g = series("strain"), t = series("time"), height = series("box_height"),
               sigma_yy = series("normal_stress");
    std::size_t first = 0, last = 0;
    double sigma_sum = 0.0;
    for (std::size_t i = 0; i < g.size(); ++i)
      if (g[i] >= 0.12 && g[i] <= 0.15) {
        if (first == 0) first = i;
        last = i;
        sigma_sum += sigma_yy[i];
      }
    ASSERT_GT(last, first + 10);
    const double compaction_rate = -std::log(height[last] / height[first]) / (t[last] - t[first]);
    const double sigma_mean = sigma_sum / double(last - first + 1);
    EXPECT_NEAR(sigma_mean + 100.0 * compaction_rate, dry.get("transient.p0"),
                0.03 * dry.get("transient.p0"));
    EXPECT_GT(dry.get("transient.phi_before_step") - dry.get("transient.phi0"), 0.003);
    EXPECT_GT(dry.get("transient.T_after_step"), 5.0 * dry.get("transient.T_before_step"));
    // Drained needs a liquid to drain: one line naming the key and exit 2.
    EXPECT_EQ(run_cli("run shear.yaml --out x --set start.preparation=loose --set "
                      "control.mode=drained",
                      dir_),
              granflow::core::exit_bad_input);
    const std::string out = read(dir_ / "cli.txt");
    EXPECT_NE(out.find("control.mode"), std::string::npos) << out;
  }
  {
    SCOPED_TRACE("a bad preparation reference is one line and exit 2");
    ASSERT_EQ(dense_status_, 0) << dense_log_;
    // Missing directory.
    EXPECT_EQ(run_cli("run shear.yaml --out x --set start.preparation=nowhere", dir_),
              granflow::core::exit_bad_input);
    std::string out = read(dir_ / "cli.txt");
    EXPECT_NE(out.find("start.preparation"), std::string::npos) << out;
    EXPECT_NE(out.find("nowhere"), std::string::npos) << out;
    EXPECT_FALSE(std::filesystem::exists(dir_ / "x"));
    // A run directory of another kind (a `kind: dem` run is not a preparation).
    std::filesystem::create_directories(dir_ / "other");
    std::ofstream(dir_ / "other" / "case.yaml") << "kind: dem\n";
    EXPECT_EQ(run_cli("run shear.yaml --out x --set start.preparation=other", dir_),
              granflow::core::exit_bad_input);
    out = read(dir_ / "cli.txt");
    EXPECT_NE(out.find("kind: dem"), std::string::npos) << out;
    // More seeds than were prepared.
    EXPECT_EQ(
        run_cli("run shear.yaml --out x --set start.preparation=dense --set statistics.seeds=2",
                dir_),
        granflow::core::exit_bad_input);
    out = read(dir_ / "cli.txt");
    EXPECT_NE(out.find("dem.seed 2"), std::string::npos) << out;
    // A stop stage only follows a transient from a prepared state.
    EXPECT_EQ(run_cli("run shear.yaml --out x --set stop.duration=0.1", dir_),
              granflow::core::exit_bad_input);
    out = read(dir_ / "cli.txt");
    EXPECT_NE(out.find("stop.duration"), std::string::npos) << out;
  }
}

}  // namespace
