// The extraction harness and deck generation as pure functions (no LIGGGHTS).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "dem_coupling/deck/contact_time.hpp"
#include "dem_coupling/deck/shear_deck.hpp"
#include "dem_coupling/extraction/normal_stress_servo.hpp"
#include "dem_coupling/extraction/shear_sample.hpp"

namespace {

using namespace granflow::dem;

struct Particles {
  std::vector<double> x, v, m, r;
  ParticleView view() const { return {int(m.size()), x.data(), v.data(), m.data(), r.data()}; }
};

// n particles at random positions in a box [0,L)^3 moving exactly with u = (gd (y - ylo), 0, 0)
Particles on_profile(int n, double gd, double ylo, double l, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Particles p;
  for (int i = 0; i < n; ++i) {
    const double y = ylo + l * u(rng);
    p.x.insert(p.x.end(), {l * u(rng), y, l * u(rng)});
    p.v.insert(p.v.end(), {gd * (y - ylo), 0.0, 0.0});
    p.r.push_back(0.5e-3 * (0.9 + 0.2 * u(rng)));
    p.m.push_back(2500.0 * 4.0 / 3.0 * std::numbers::pi * std::pow(p.r.back(), 3));
  }
  return p;
}

TEST(DemExtraction, ImposedLinearProfileHasNoKineticStressNoTemperatureNoDeviation) {
  const double gd = 37.0, ylo = -0.002, l = 0.01;
  const auto p = on_profile(500, gd, ylo, l, 1);
  SampleSums sums(8);
  const ShearFrame frame{gd, ylo, l};
  accumulate_particles(p.view(), frame, sums);
  const auto s = finalize_sample(sums, {1, 2, 3, -0.5, 0, 0}, {l, l, l, 0.0}, frame, 2500.0);
  // v' = v - u(y) is computed as gd (y - ylo) - gd (y - ylo): exactly zero in floating point.
  for (double k : s.kinetic_stress) EXPECT_EQ(k, 0.0);
  EXPECT_EQ(s.temperature, 0.0);
  EXPECT_EQ(s.profile_deviation, 0.0);
  // Total stress is then the virial alone; mu = -P_xy / P_yy.
  EXPECT_EQ(s.stress[1], 2.0);
  EXPECT_DOUBLE_EQ(s.friction, 0.25);
  // Mean velocity in each bin lies on the line within the bin's spread (gd l / bins).
  for (std::size_t b = 0; b < s.profile_velocity.size(); ++b)
    EXPECT_NEAR(s.profile_velocity[b], gd * s.profile_y[b], 0.5 * gd * l / 8) << "bin " << b;
}

TEST(DemExtraction, KnownFluctuationsGiveKineticStressAndTemperature) {
  // Two particles of mass m with v' = (+a, +b, 0) and (-a, -b, 0) on the profile:
  // P^kin_xx = 2 m a^2 / V, P^kin_xy = 2 m a b / V, T = 2 (a^2 + b^2) / 6, momentum 0.
  const double gd = 10.0, l = 0.01, m = 1e-6, a = 0.03, b = -0.02;
  Particles p;
  p.x = {0.001, 0.002, 0.003, 0.004, 0.007, 0.001};
  p.v = {gd * 0.002 + a, b, 0.0, gd * 0.007 - a, -b, 0.0};
  p.m = {m, m};
  p.r = {0.5e-3, 0.5e-3};
  SampleSums sums(2);
  const ShearFrame frame{gd, 0.0, l};
  accumulate_particles(p.view(), frame, sums);
  const double volume = l * l * l;
  const auto s = finalize_sample(sums, {}, {l, l, l, 0.0}, frame, 2500.0);
  EXPECT_NEAR(s.kinetic_stress[0], 2 * m * a * a / volume, 1e-12 * 2 * m * a * a / volume);
  EXPECT_NEAR(s.kinetic_stress[3], 2 * m * a * b / volume,
              1e-12 * 2 * m * std::abs(a * b) / volume);
  EXPECT_NEAR(s.temperature, (a * a + b * b) / 3.0, 1e-15);
  EXPECT_NEAR(s.peculiar_momentum[0], 0.0, 1e-20);
  // phi = 2 (pi/6) d^3 / V, e = 1/phi - 1
  const double phi = 2 * std::numbers::pi / 6 * 1e-9 / volume;
  EXPECT_NEAR(s.solid_fraction, phi, 1e-15);
  EXPECT_NEAR(s.void_ratio, 1 / phi - 1, 1e-9 * (1 / phi));
}

TEST(DemExtraction, UniformDriftIsNotAgitation) {
  // Adding the same velocity to every particle (a drift of the whole periodic sample) must not
  // change the kinetic stress or T (Galilean invariance of the fluctuations).
  auto p = on_profile(300, 12.0, 0.0, 0.01, 5);
  std::mt19937_64 rng(9);
  std::normal_distribution<double> noise(0.0, 0.02);
  for (auto& c : p.v) c += noise(rng);
  SampleSums plain(4), drifting(4);
  const ShearFrame frame{12.0, 0.0, 0.01};
  accumulate_particles(p.view(), frame, plain);
  for (std::size_t i = 0; i < p.v.size(); i += 3) {
    p.v[i] += 0.05;
    p.v[i + 1] -= 0.03;
    p.v[i + 2] += 0.01;
  }
  accumulate_particles(p.view(), frame, drifting);
  const BoxState box{0.01, 0.01, 0.01, 0.0};
  const auto a = finalize_sample(plain, {}, box, frame, 2500.0);
  const auto b = finalize_sample(drifting, {}, box, frame, 2500.0);
  // Round-off of subtracting a drift 2.5x the fluctuation: 1e-10 relative.
  for (int k = 0; k < 6; ++k)
    EXPECT_NEAR(b.kinetic_stress[k], a.kinetic_stress[k], 1e-10 * a.kinetic_stress[0]) << k;
  EXPECT_NEAR(b.temperature / a.temperature, 1.0, 1e-10);
  // Fluctuations of 0.02 m/s per component: T = 4e-4 within sampling error (300 x 3 values).
  EXPECT_NEAR(a.temperature, 4e-4, 0.6e-4);
}

TEST(DemExtraction, RankSumsAddUpToTheSerialSample) {
  // What MPI_Allreduce does: sums of two halves equal the sums of the whole (up to round-off).
  const auto p = on_profile(200, 5.0, 0.0, 0.01, 3);
  Particles q = p;
  for (std::size_t i = 0; i < q.v.size(); i += 3) q.v[i] += 0.01 * std::sin(double(i));
  SampleSums whole(4), half(4), other(4);
  const ShearFrame frame{5.0, 0.0, 0.01};
  accumulate_particles(q.view(), frame, whole);
  ParticleView first{100, q.x.data(), q.v.data(), q.m.data(), q.r.data()};
  ParticleView second{100, q.x.data() + 300, q.v.data() + 300, q.m.data() + 100, q.r.data() + 100};
  accumulate_particles(first, frame, half);
  accumulate_particles(second, frame, other);
  for (int k = 0; k < whole.size(); ++k)
    EXPECT_NEAR(half.data()[k] + other.data()[k], whole.data()[k],
                1e-12 * std::abs(whole.data()[k]) + 1e-300);
}

TEST(DemExtraction, ContactsCountGhostPairsHalf) {
  // Three spheres of radius 1 on a line at x = 0, 1.5, 5 (local), ghost at 6.9 touching atom 2.
  const double x[] = {0, 0, 0, 1.5, 0, 0, 5, 0, 0, 6.9, 0, 0};
  const double r[] = {1, 1, 1, 1};
  int n0[] = {1, 2}, n1[] = {2}, n2[] = {3};
  int* firstneigh[] = {n0, n1, n2};
  const int ilist[] = {0, 1, 2}, numneigh[] = {2, 1, 1};
  HalfNeighborList list{3, ilist, numneigh, firstneigh};
  SampleSums sums(1);
  accumulate_contacts(list, x, r, 3, sums);
  // (0,1) overlap: 1; (0,2), (1,2) apart; (2, ghost) overlap: 1/2 (its owner lists it too).
  EXPECT_DOUBLE_EQ(sums[SampleSums::contact_count], 1.5);
}

TEST(DemServo, ConvergesOnAStiffStressResponse) {
  // Model response sigma(L) = p0 (L0 / L)^40 (d ln sigma / d ln phi = 40, dense flow); the
  // servo with gain 0.01 must settle within 0.1 % of L0 from 3 % too loose.
  const double p0 = 100.0, l0 = 0.01;
  NormalStressServo servo(p0, 0.01, 0.002);
  double l = 1.03 * l0;
  for (int k = 0; k < 200; ++k) l = servo.next_height(l, p0 * std::pow(l0 / l, 40.0));
  EXPECT_NEAR(l / l0, 1.0, 1e-3);
  // One update never changes the height by more than the clamp (fresh servos: the second call
  // on one servo would also pay out the carry of the first).
  NormalStressServo up(p0, 0.01, 0.002), down(p0, 0.01, 0.002);
  EXPECT_NEAR(up.next_height(1.0, 1e6), 1.002, 1e-15);
  EXPECT_NEAR(down.next_height(1.0, 0.0), 0.998, 1e-15);
}

TEST(DemDeck, ContactTimesMatchHandCalculation) {
  // r = 0.45 mm, rho 2500, E 1e7, nu 0.3: G = 3.846e6 Pa,
  // t_R = pi r sqrt(rho/G) / (0.1631*0.3 + 0.8766) = 1.41372e-3 * 0.0254951 / 0.92553
  //     = 3.8943e-5 s (liggghts-study.md: dt = 4e-6 s is ~0.1 t_R); 5 digits given.
  EXPECT_NEAR(rayleigh_time(0.45e-3, 2500, 1e7, 0.3), 3.8943e-5, 1e-4 * 3.8943e-5);
  // Hertz time scales as v^(-1/5) and E^(-2/5).
  const double t1 = hertz_contact_time(0.5e-3, 2500, 1e7, 0.3, 0.1);
  EXPECT_NEAR(hertz_contact_time(0.5e-3, 2500, 1e7, 0.3, 3.2) / t1, std::pow(32.0, -0.2), 1e-12);
  EXPECT_NEAR(hertz_contact_time(0.5e-3, 2500, 1e9, 0.3, 0.1) / t1, std::pow(100.0, -0.4), 1e-12);
}

TEST(DemDeck, SeedDeterminesTheSampleAndTimeStepIsReported) {
  ShearDeckParams p;
  p.particles = 300;
  const auto a = make_shear_deck(p, "particles.data");
  const auto b = make_shear_deck(p, "particles.data");
  EXPECT_EQ(a.data, b.data);
  p.seed = 2;
  EXPECT_NE(make_shear_deck(p, "particles.data").data, a.data);
  EXPECT_DOUBLE_EQ(a.dt, p.dt_safety * a.times.shortest());
  EXPECT_NE(a.deck.find(fmt::format("timestep        {:.17g}", a.dt)), std::string::npos);
  // Bidisperse 50/50 with ratio 1.22 and number-mean 1 mm: d_small = 1 mm / 1.11.
  EXPECT_NEAR(a.small_diameter, 1e-3 / 1.11, 1e-15);
  EXPECT_NEAR(a.mean_diameter, 1e-3, 1e-15);
  // The compressed box holds the requested solid fraction.
  EXPECT_NEAR(a.solid_volume / std::pow(a.box_length, 3), p.solid_fraction, 1e-12);
}

TEST(DemDeck, ImpossibleCasesAreRefused) {
  ShearDeckParams p;
  p.solid_fraction = 0.72;  // above the bound for soft grains, 0.70
  ASSERT_FALSE(check_shear_params(p).empty());
  EXPECT_EQ(check_shear_params(p)[0].first, "control.solid_fraction");
  p.solid_fraction = 0.55;
  p.particles = 20;  // box of ~3 diameters: periodic images would see themselves
  ASSERT_FALSE(check_shear_params(p).empty());
  EXPECT_EQ(check_shear_params(p)[0].first, "dem.particles");
  p.particles = 300;
  EXPECT_TRUE(check_shear_params(p).empty());
  p.material.contact_law = granflow::dem::ContactLaw::hooke;  // without k_n
  ASSERT_FALSE(check_shear_params(p).empty());
  EXPECT_EQ(check_shear_params(p)[0].first, "material.normal_stiffness");
  p.material.normal_stiffness = 1000.0;
  EXPECT_TRUE(check_shear_params(p).empty());
}

TEST(DemDeck, LinearSpringDeckTakesItsTimeStepFromTheSpringContactTime) {
  ShearDeckParams p;
  p.particles = 300;
  p.material.size = granflow::dem::SizeDistribution::monodisperse;
  p.material.contact_law = granflow::dem::ContactLaw::hooke;
  p.material.normal_stiffness = 1000.0;
  p.dt_safety = 0.05;
  const auto deck = make_shear_deck(p, "particles.data");
  // m* = ρ π d³/12 = 6.545e-7 kg, e = 0.7: t_c = π sqrt(m*/k_n) sqrt(1 + ln²0.7/π²)
  //    = π × 2.5583e-5 × 1.00643 = 8.0888e-5 s (5 digits by hand).
  EXPECT_NEAR(deck.times.linear_spring, 8.0888e-5, 1e-4 * 8.0888e-5);
  EXPECT_DOUBLE_EQ(deck.dt, 0.05 * deck.times.linear_spring);
  EXPECT_NE(deck.deck.find("gran model hooke/stiffness"), std::string::npos);
  EXPECT_NE(deck.deck.find("kt peratomtypepair 1 285.71428571428"), std::string::npos);
  EXPECT_EQ(deck.deck.find("youngsModulus"), std::string::npos);
}

}  // namespace
