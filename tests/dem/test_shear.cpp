// Small Lees-Edwards shear runs of granflow-dem (200-300 particles, a few seconds each).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <numeric>
#include <span>
#include <sstream>

#include "statistics/steady_state.hpp"
#include "dem_coupling/deck/shear_deck.hpp"
#include "tests/dem/driver_runner.hpp"

namespace {

using granflow::dem::make_shear_deck;
using granflow::dem::ShearDeckParams;
using granflow::dem::SizeDistribution;
using granflow::dem::testing::DriverRun;
using granflow::dem::testing::fresh_directory;
using granflow::dem::testing::run_driver;

DriverRun run_case(const std::string& name, const ShearDeckParams& p, int ranks = 1) {
  const auto dir = fresh_directory(name);
  const auto deck = make_shear_deck(p, "particles.data");
  std::ofstream(dir / "in.granflow") << deck.deck;
  std::ofstream(dir / "particles.data") << deck.data;
  return run_driver(dir, ranks);
}

ShearDeckParams dense_case() {
  ShearDeckParams p;
  p.particles = 300;
  p.solid_fraction = 0.55;
  p.shear_rate = 50.0;
  p.total_strain = 2.0;
  p.sample_strain = 0.02;
  p.compression_steps = 4000;
  return p;
}

TEST(DemShear, ImposedLinearProfileWithoutContactsHasZeroKineticStressAndTemperature) {
  // Monodisperse spheres on a loose lattice (1.05 d spacing, no compression) given exactly the
  // streaming velocity: rows slide past each other without touching for a strain below
  // (0.05 - 0.042) / 0.042 = 0.19, so every particle keeps v = u(y) (also across the
  // Lees-Edwards boundary, where remap v shifts v_x by gd L_y). Everything kinetic must vanish.
  // The decks now insert spheres at random and start with velocity fluctuations
  // (initial_state.hpp): this test writes the lattice itself and asks for no fluctuations
  // (initial_temperature 0), the frozen state of the old start, on purpose.
  ShearDeckParams p;
  p.material.size = SizeDistribution::monodisperse;
  p.particles = 216;  // full 6^3 lattice
  p.shear_rate = 50.0;
  p.total_strain = 0.15;
  p.sample_strain = 0.005;
  p.compression_steps = 1;
  p.initial_temperature = 0.0;
  const double d = p.material.diameter, spacing = 1.05 * d, box = 6 * spacing;
  p.solid_fraction = 216 * std::numbers::pi / 6.0 * d * d * d / (box * box * box);
  const auto dir = fresh_directory("linear_profile");
  const auto deck = make_shear_deck(p, "particles.data");
  std::ofstream(dir / "in.granflow") << deck.deck;
  std::ofstream data(dir / "particles.data");
  data << "LIGGGHTS data file: 6^3 lattice\n\n216 atoms\n1 atom types\n\n";
  for (const char* axis : {"x", "y", "z"})
    data << fmt::format("0 {:.17g} {}lo {}hi\n", box, axis, axis);
  data << "0 0 0 xy xz yz\n\nAtoms\n\n";
  for (int i = 0; i < 216; ++i)
    data << fmt::format("{} 1 {:.17g} {:.17g} {:.17g} {:.17g} {:.17g}\n", i + 1, d,
                        p.material.particle_density, (i % 6 + 0.5) * spacing,
                        (i / 6 % 6 + 0.5) * spacing, (i / 36 + 0.5) * spacing);
  data.close();
  const auto run = run_driver(dir);
  ASSERT_EQ(run.status, 0) << run.output;
  ASSERT_GE(run.series.rows(), 25u);
  const double speed = p.shear_rate * box;  // top speed gd L
  const double stress_scale = p.material.particle_density * speed * speed;
  for (std::size_t i = 0; i < run.series.rows(); ++i) {
    // Round-off of v - u(y) with |v| <= gd L: |v'| <~ 1e-15 gd L, so T and P^kin are ~1e-30 of
    // their scales; 1e-24 leaves a wide margin and still fails for any real fluctuation.
    EXPECT_LT(run.series.at("T")[i], 1e-24 * speed * speed) << "sample " << i;
    for (const char* c : {"Pkin_xx", "Pkin_yy", "Pkin_xy"})
      EXPECT_LT(std::abs(run.series.at(c)[i]), 1e-24 * stress_scale) << c << " sample " << i;
    EXPECT_EQ(run.series.at("Pvir_yy")[i], 0.0);
    EXPECT_EQ(run.series.at("Z")[i], 0.0);
    EXPECT_LT(run.series.at("profile_deviation")[i], 1e-12);
  }
  // The strain advanced as imposed.
  EXPECT_NEAR(run.series.at("strain").back(), p.total_strain, p.sample_strain);
}

TEST(DemShear, IdenticalSeedsGiveIdenticalResultsAndMomentumIsConserved) {
  const auto p = dense_case();
  const auto a = run_case("seed_a", p);
  const auto b = run_case("seed_b", p);
  ASSERT_EQ(a.status, 0) << a.output;
  ASSERT_EQ(b.status, 0) << b.output;
  ASSERT_GT(a.series.rows(), 50u);
  for (const auto& name : a.series.names)
    for (std::size_t i = 0; i < a.series.rows(); ++i)
      ASSERT_EQ(a.series.at(name)[i], b.series.at(name)[i]) << name << " sample " << i;
  auto other = p;
  other.seed = 7;
  const auto c = run_case("seed_c", other);
  ASSERT_EQ(c.status, 0) << c.output;
  EXPECT_NE(a.series.at("tau")[10], c.series.at("tau")[10]);

  // Contact forces are pairwise opposite (also across the Lees-Edwards boundary), so the
  // momentum sum m v_y, sum m v_z and the peculiar momentum sum m (v_x - gd (y - ylo)) (which is
  // unchanged when remap v moves a particle through the y boundary) stay at their initial values.
  // Scale: N m sqrt(T); round-off over ~10^4 steps leaves ~1e-12 of it.
  const double m = 2500.0 * std::numbers::pi / 6.0 * 1e-9;
  const double scale = p.particles * m * std::sqrt(a.series.at("T").back());
  for (const char* c : {"momentum_x", "momentum_y", "momentum_z"}) {
    const auto& series = a.series.at(c);
    for (double v : series) EXPECT_NEAR(v, series.front(), 1e-9 * scale) << c;
  }
}

TEST(DemShear, OneAndTwoRanksAgree) {
  auto p = dense_case();
  p.total_strain = 6.0;
  p.sample_strain = 0.01;
  const auto one = run_case("ranks_1", p, 1);
  const auto two = run_case("ranks_2", p, 2);
  ASSERT_EQ(one.status, 0) << one.output;
  ASSERT_EQ(two.status, 0) << two.output;
  ASSERT_EQ(one.series.rows(), two.series.rows());
  // Same initial state and forces; the only difference is the order of floating-point sums, so
  // the first sample (strain 0.01, ~50 steps) agrees to round-off amplified by the chaotic
  // dynamics over a few collision times (1e-6 relative is generous).
  for (const char* c : {"sigma_yy", "tau", "T", "phi"})
    EXPECT_NEAR(two.series.at(c)[0] / one.series.at(c)[0], 1.0, 1e-6) << c;
  // Later the trajectories decorrelate; the steady averages must agree within error bars
  // (4 combined standard errors: a false alarm rate below 1e-4 per quantity).
  for (const char* c : {"mu", "sigma_yy", "T", "Z"}) {
    const auto& s1 = one.series.at(c);
    const auto& s2 = two.series.at(c);
    const std::size_t start = s1.size() / 4;  // strain >= 1.5: past the start-up transient
    const auto e1 = granflow::statistics::batch_means(std::span(s1).subspan(start), 10);
    const auto e2 = granflow::statistics::batch_means(std::span(s2).subspan(start), 10);
    EXPECT_LT(std::abs(e1.mean - e2.mean), 4.0 * std::hypot(e1.standard_error, e2.standard_error))
        << c << ": " << e1.mean << " +- " << e1.standard_error << " vs " << e2.mean << " +- "
        << e2.standard_error;
  }
}

TEST(DemShear, ServoHoldsTheNormalStress) {
  // Constant normal stress p0 = 100 Pa at gd = 50 1/s (I ~ 0.25), starting from phi = 0.50: the
  // servo must compact the sample (phi rises) and hold sigma_yy near p0 after the transient.
  auto p = dense_case();
  p.constant_pressure = true;
  p.normal_stress = 100.0;
  p.servo_gain = 0.02;
  p.servo_strain = 0.05;
  p.solid_fraction = 0.50;
  p.total_strain = 6.0;
  const auto run = run_case("servo", p);
  ASSERT_EQ(run.status, 0) << run.output;
  const auto& sigma = run.series.at("sigma_yy");
  const auto& phi = run.series.at("phi");
  const std::size_t start = sigma.size() / 2;  // strain >= 3
  const auto e = granflow::statistics::batch_means(std::span(sigma).subspan(start), 10);
  // 300 particles: sigma_yy fluctuates by ~30 % per sample; the mean over 3 strain units has a
  // standard error of a few %. A working servo is within 4 standard errors + 10 % (the integral
  // controller's small bias from the convex sigma(phi)); without it sigma_yy stays ~10x off.
  EXPECT_LT(std::abs(e.mean / p.normal_stress - 1.0), 0.10 + 4.0 * e.standard_error / e.mean)
      << e.mean << " +- " << e.standard_error;
  EXPECT_GT(phi.back(), 0.52);
  // Constant volume would keep L_y; the servo moved it.
  EXPECT_NE(run.series.at("ly").front(), run.series.at("ly").back());
}

TEST(DemShear, KineticStressAndTemperatureAgreeWithLiggghtsAtomVariables) {
  // Independent path (liggghts-study.md section 3.3): atom-style variables about the same
  // profile, summed by compute reduce and printed by thermo at every chunk end, against the
  // harness' P^kin and T of the same step.
  auto p = dense_case();
  p.total_strain = 0.5;
  const auto dir = fresh_directory("kinetic_paths");
  const auto deck = make_shear_deck(p, "particles.data");
  std::ofstream(dir / "in.granflow")
      << deck.deck
      << fmt::format(
             "variable gfk_dvx atom vx-{:.17g}*(y-ylo)\n"
             "variable gfk_kxx atom mass*v_gfk_dvx*v_gfk_dvx\n"
             "variable gfk_kxy atom mass*v_gfk_dvx*vy\n"
             "variable gfk_t2 atom v_gfk_dvx*v_gfk_dvx+vy*vy+vz*vz\n"
             "compute gfk all reduce sum v_gfk_kxx v_gfk_kxy v_gfk_t2 v_gfk_dvx vy vz\n"
             "thermo_style custom step atoms c_gfk[1] c_gfk[2] c_gfk[3] c_gfk[4] c_gfk[5] "
             "c_gfk[6] c_gf_virial[2]\n"
             "thermo_modify format float %.15g norm no\n",
             p.shear_rate);
  std::ofstream(dir / "particles.data") << deck.data;
  const auto run = run_driver(dir, 1);
  ASSERT_EQ(run.status, 0) << run.output;
  // thermo lines: step atoms kxx kxy t2 sum(dvx) sum(vy) sum(vz) virial_yy
  std::map<long, std::array<double, 6>> thermo;
  std::istringstream lines(run.output);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream f(line);
    long step = 0, atoms = 0;
    std::array<double, 6> k{};
    double vir = 0;
    if (f >> step >> atoms >> k[0] >> k[1] >> k[2] >> k[3] >> k[4] >> k[5] >> vir &&
        atoms == p.particles)
      thermo[step] = k;
  }
  std::size_t compared = 0;
  for (std::size_t i = 0; i < run.series.rows(); ++i) {
    const auto it = thermo.find(long(run.series.at("step")[i]));
    if (it == thermo.end()) continue;
    const double volume = run.series.at("volume")[i];
    const auto& k = it->second;
    // Same sums in a different order (and 15 printed digits): 1e-9 relative.
    EXPECT_NEAR(run.series.at("Pkin_xx")[i] * volume / k[0], 1.0, 1e-9) << "sample " << i;
    EXPECT_NEAR(run.series.at("Pkin_xy")[i] * volume, k[1], 1e-9 * std::abs(k[0]));
    // T about the profile and the (number-weighted) mean drift: (sum |v'|^2 - |sum v'|^2 / N) / 3N
    const double n = double(p.particles);
    const double t2 = k[2] - (k[3] * k[3] + k[4] * k[4] + k[5] * k[5]) / n;
    EXPECT_NEAR(run.series.at("T")[i] * 3.0 * n / t2, 1.0, 1e-9);
    ++compared;
  }
  EXPECT_GE(compared, run.series.rows() - 1);
}

TEST(DemShear, LiggghtsErrorIsSurfacedWithItsMessage) {
  // A deck error (unknown style): LIGGGHTS' own message, non-zero exit.
  const auto dir = fresh_directory("deck_error");
  std::ofstream(dir / "in.granflow") << "atom_style granular\npair_style no/such/style\n";
  const auto run = run_driver(dir, 1);
  EXPECT_NE(run.status, 0);
  EXPECT_NE(run.output.find("ERROR"), std::string::npos) << run.output;
}

}  // namespace
