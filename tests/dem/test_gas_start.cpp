// The shear start (dem_coupling/deck/initial_state.hpp) and the tangential dashpot
// key (material.tangential_damping), docs/dem_dataset.md.
//  * A frictionless e 0.9 gas at φ 0.2 (cases/dem/gas_point.yaml: 300 spheres, stiff linear
//    springs, constant volume), started from the streaming profile plus fluctuations and a
//    random packing, reaches kinetic theory's homogeneous-shear state; started as before (lattice
//    expanded to φ, affine profile alone) it stayed at T ~ 1e-4 of it. ~15 s.
//  * The decks: dashpot conventions, the random packing, the φ bound, the frozen flag's bound.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <regex>
#include <string>

#include "continuum/model/g0_carnahan_starling.hpp"
#include "continuum/model/kinetic_theory_coefficients.hpp"
#include "core/process.hpp"
#include "core/run.hpp"
#include "dem_coupling/deck/initial_state.hpp"
#include "dem_coupling/deck/shear_deck.hpp"
#include "dem_coupling/kind/steady_checks.hpp"

namespace {

using namespace granflow::dem;

std::filesystem::path fresh_directory(const std::string& name) {
  const auto dir = std::filesystem::path(GRANFLOW_BINARY_DIR) / "test-dem" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

TEST(DemGasStart, FrictionlessGasReachesKineticTheory) {
  const auto dir = fresh_directory("gas_start");
  granflow::core::ProcessOptions options;
  options.directory = dir;
  options.output = dir / "cli.txt";
  const auto run = granflow::core::run_process(
      {GRANFLOW_CLI_PATH, "run", GRANFLOW_SOURCE_DIR "/cases/dem/gas_point.yaml", "--out", "run"},
      options);
  ASSERT_TRUE(run.ok()) << run.error << " status " << run.status << ", see " << options.output;
  const auto s = granflow::core::Summary::read(dir / "run" / "summary.json");
  // Kinetic theory (L = d, Garzó-Dufty J, Carnahan-Starling g0, ε = e for μ_p = 0):
  // T/(dγ̇)² = f2/f3 = 2.019, μ = sqrt(f2 f3)/f1 = 0.275, σ_yy = ρ_p f1 T.
  const double phi = 0.2, e = 0.9;
  const double G = phi * granflow::model::g0_carnahan_starling(phi);
  const double f1 = granflow::model::kinetic_f1(phi, G, e);
  const double f2 = granflow::model::kinetic_f2(phi, G, granflow::model::kinetic_J(e, G));
  const double f3 = granflow::model::kinetic_f3(phi, G, e);
  ASSERT_NEAR(kinetic_shear_temperature(phi, e, 0.0), f2 / f3, 1e-12);
  EXPECT_EQ(s.get("steady.frozen"), 0.0);
  // T: measured 1.73 and 1.85 (seeds 1, 2; T wanders by ±5 % over blocks of a few strain in a
  // 300-sphere box) and 1.90 with 1000 spheres, i.e. 6-14 % below f2/f3: Navier-Stokes-order
  // kinetic theory overestimates the steady uniform-shear T, whose shear rate is not small at
  // e = 0.9 (shear thinning of the non-Newtonian rheology, Santos, Garzó & Dufty 2004, Phys.
  // Rev. E 69, 061303). 20 % holds that bias and the seed scatter; before the fix T/(f2/f3) was
  // ~1e-4.
  const double t_scaled = s.get("steady.T_scaled");
  EXPECT_NEAR(t_scaled / (f2 / f3), 1.0, 0.20) << "T/(d γ̇)² = " << t_scaled;
  // μ = sqrt(f2 f3)/f1 does not depend on T: measured 0.278-0.281 against 0.275; 5 % is ~5
  // standard errors of μ (±0.006).
  EXPECT_NEAR(s.get("steady.mu") / (std::sqrt(f2 * f3) / f1), 1.0, 0.05);
  // Equation of state σ_yy = ρ_p f1 T at the measured T (Enskog; kinetic stress plus collisional
  // transfer): measured within 2 %; 5 % holds the anisotropy of the normal stresses in shear.
  EXPECT_NEAR(s.get("steady.p") / (2500.0 * f1 * s.get("steady.T")), 1.0, 0.05);
  // Started at kinetic theory's T, the steady window starts early: within half the run.
  EXPECT_LT(s.get("steady.start_strain"), 10.0);
}

ShearDeckParams hooke_gas() {
  ShearDeckParams p;
  p.material.size = SizeDistribution::monodisperse;
  p.material.contact_law = ContactLaw::hooke;
  p.material.normal_stiffness = 1e4;
  p.material.restitution = 0.9;
  p.material.particle_friction = 0.5;
  p.particles = 300;
  p.solid_fraction = 0.2;
  p.total_strain = 2;
  return p;
}

double deck_number(const std::string& deck, const std::string& pattern) {
  std::smatch m;
  if (!std::regex_search(deck, m, std::regex(pattern))) return std::nan("");
  return std::stod(m[1]);
}

TEST(DemGasStart, TangentialDashpotConventions) {
  // hooke/stiffness: gammat = (γ_t/γ_n) gamman with 1, 1/2, 0 (shear_deck.hpp TangentialDamping).
  const double expected[] = {1.0, 0.5, 0.0};
  const TangentialDamping conventions[] = {TangentialDamping::liggghts,
                                           TangentialDamping::lammps_hooke_history,
                                           TangentialDamping::none};
  for (int k = 0; k < 3; ++k) {
    ShearDeckParams p = hooke_gas();
    p.material.tangential_damping = conventions[k];
    EXPECT_TRUE(check_shear_params(p).empty());
    const std::string deck = make_shear_deck(p, "particles.data").deck;
    const double gamman = deck_number(deck, R"(gamman peratomtypepair 1 (\S+))");
    const double gammat = deck_number(deck, R"(gammat peratomtypepair 1 (\S+))");
    ASSERT_GT(gamman, 0.0);
    EXPECT_NEAR(gammat, expected[k] * gamman, 1e-12 * gamman);
    EXPECT_EQ(deck.find("tangential_damping off") != std::string::npos, k == 2);
  }
  // hertz: LIGGGHTS' own γ_t/γ_n = √(2(1-ν)/(2-ν)) (0.907 at ν 0.3), `tangential_damping off`
  // for none, and no γ_n/2 option (refused before LIGGGHTS starts).
  ShearDeckParams p = hooke_gas();
  p.material.contact_law = ContactLaw::hertz;
  EXPECT_NEAR(tangential_damping_ratio(p.material), std::sqrt(1.4 / 1.7), 1e-12);
  EXPECT_EQ(make_shear_deck(p, "d").deck.find("tangential_damping off"), std::string::npos);
  p.material.tangential_damping = TangentialDamping::none;
  EXPECT_NE(make_shear_deck(p, "d").deck.find("hertz tangential history tangential_damping off"),
            std::string::npos);
  p.material.tangential_damping = TangentialDamping::lammps_hooke_history;
  ASSERT_FALSE(check_shear_params(p).empty());
  EXPECT_EQ(check_shear_params(p).front().first, "material.tangential_damping");
}

TEST(DemGasStart, RandomPackingAndStartTemperature) {
  // Random sequential addition at φ 0.2: no pair closer than d (minimum image), φ exact.
  ShearDeckParams p = hooke_gas();
  const ShearDeck deck = make_shear_deck(p, "particles.data");
  EXPECT_DOUBLE_EQ(deck.insertion_solid_fraction, 0.2);
  EXPECT_NEAR(deck.initial_box_length, deck.box_length, 1e-12 * deck.box_length);
  const RandomPacking packing = random_packing(deck.diameters, 0.3, 7);
  const double box = packing.box_length;
  const std::size_t n = deck.diameters.size();
  double closest = 1e9;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      double r2 = 0.0;
      for (int a = 0; a < 3; ++a) {
        double s = packing.positions[3 * i + a] - packing.positions[3 * j + a];
        s -= box * std::round(s / box);
        r2 += s * s;
      }
      closest = std::min(closest, std::sqrt(r2));
    }
  EXPECT_GE(closest, 1e-3 * (1.0 - 1e-12));
  EXPECT_NEAR(double(n) * std::numbers::pi / 6.0 * 1e-9 / (box * box * box), 0.3, 1e-12);
  // The deck passes T0 = f2/f3 (d γ̇)² (ε = e - 1.5 μ_p exp(-3 μ_p) with μ_p 0.5) to the driver.
  const double t0 = deck_number(deck.deck, R"(variable gf_initial_temperature equal (\S+))");
  const double scale = std::pow(1e-3 * p.shear_rate, 2);
  EXPECT_NEAR(t0 / scale, kinetic_shear_temperature(0.2, 0.9, 0.5), 1e-9);
  p.initial_temperature = 0.5;
  EXPECT_NEAR(initial_temperature(p, 1e-3) / scale, 0.5, 1e-12);
  // Above random close packing up to max_solid_fraction, compressed from φ 0.3.
  p.solid_fraction = max_solid_fraction;
  EXPECT_TRUE(check_shear_params(p).empty());
  EXPECT_DOUBLE_EQ(make_shear_deck(p, "d").insertion_solid_fraction, insertion_solid_fraction);
  p.solid_fraction = max_solid_fraction + 0.01;
  EXPECT_FALSE(check_shear_params(p).empty());
}

TEST(DemGasStart, FrozenBoundSeparatesFrozenFromColliding) {
  // The frozen gas of the old start: T/(dγ̇)² ~ 1e-8 (2.5e-5 of f2/f3); kinetic theory's smallest steady
  // value is its dense limit 2 J/(15 (1-ε²)) >= 1/15.
  EXPECT_GT(frozen_temperature, 1e-6);
  EXPECT_LT(frozen_temperature, 1e-2 / 15.0);
  EXPECT_GT(kinetic_shear_temperature(0.6, 0.1, 0.5), 1.0 / 15.0 * 0.99);
}

}  // namespace
