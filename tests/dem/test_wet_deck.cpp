// Deck generation of immersed runs (kind: dem with liquid.enabled): the time step comes from the
// fluid limits of fluid_time_step.hpp and the deck carries the fix fluid/le line.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "dem_coupling/deck/shear_deck.hpp"

namespace {

using namespace granflow::dem;

ShearDeckParams monodisperse_wet(double viscosity) {
  ShearDeckParams p;
  p.material.size = SizeDistribution::monodisperse;
  p.material.diameter = 1e-3;
  p.material.particle_density = 2500;
  p.particles = 200;
  p.solid_fraction = 0.55;
  p.shear_rate = 50;
  p.total_strain = 1;
  p.wet.enabled = true;
  p.wet.viscosity = viscosity;
  p.wet.maximum_gap = 0.05;
  p.wet.minimum_gap = 0.001;
  return p;
}

TEST(DemWetDeck, ViscousLimitSetsTheTimeStepAtHighViscosity) {
  // η0 = 1 Pa s, equal spheres d = 1 mm, h_min = 1 µm: the normal-lubrication time
  // τ_n = m_eff h_min / (6π η0 a²), m_eff = m/2, a = d/4 (closed form, docs/dem_fluid.md) is
  // 5.6e-7 s, far below the contact limit 0.1 t_Rayleigh ≈ 4e-6 s: dt = 0.2 τ_n.
  const ShearDeckParams p = monodisperse_wet(1.0);
  const ShearDeck deck = make_shear_deck(p, "particles.data");
  const double d = 1e-3, mass = 2500 * std::numbers::pi / 6 * d * d * d, a = d / 4;
  const double tau_n = 0.5 * mass * 1e-6 / (6 * std::numbers::pi * 1.0 * a * a);
  EXPECT_EQ(deck.dt_limit, "normal lubrication");
  EXPECT_NEAR(deck.dt, 0.2 * tau_n, 1e-12 * tau_n);  // same closed form, round-off only
  EXPECT_NE(deck.deck.find("fix gf_fluid all fluid/le viscosity 1 permeability seed_eq26"),
            std::string::npos)
      << deck.deck;
  EXPECT_NE(
      deck.deck.find("lubrication 5.0000000000000002e-05 9.9999999999999995e-07 tangential yes"),
      std::string::npos);
  EXPECT_NE(deck.deck.find("variable gf_viscosity equal 1"), std::string::npos);
  // The number of steps follows dt: total strain / (γ̇ dt), rounded to whole samples.
  EXPECT_NEAR(double(deck.total_steps) * deck.dt * p.shear_rate, p.total_strain,
              double(deck.sample_every) * deck.dt * p.shear_rate);
}

TEST(DemWetDeck, LowViscosityKeepsTheContactTimeStepAndDryDecksHaveNoFluidFix) {
  ShearDeckParams p = monodisperse_wet(1e-3);
  const ShearDeck wet = make_shear_deck(p, "particles.data");
  p.wet.enabled = false;
  const ShearDeck dry = make_shear_deck(p, "particles.data");
  EXPECT_EQ(wet.dt_limit, "contact");
  EXPECT_EQ(wet.dt, dry.dt);  // both 0.1 × the contact time
  EXPECT_EQ(dry.deck.find("fluid/le"), std::string::npos);
  EXPECT_EQ(dry.deck.find("gf_viscosity"), std::string::npos);
}

TEST(DemWetDeck, GapsThatTheFixWouldRefuseAreCaseErrors) {
  ShearDeckParams p = monodisperse_wet(0.01);
  p.wet.maximum_gap = 0.6;  // h_max = 0.6 d >= the radius d/2
  p.wet.minimum_gap = 0.7;  // and h_min >= h_max
  const auto issues = check_shear_params(p);
  bool max_gap = false, min_gap = false;
  for (const auto& [path, expected] : issues) {
    max_gap |= path == "dem_liquid.maximum_gap";
    min_gap |= path == "dem_liquid.minimum_gap";
  }
  EXPECT_TRUE(max_gap);
  EXPECT_TRUE(min_gap);
  p.wet.maximum_gap = 0.05;
  p.wet.minimum_gap = 0.001;
  EXPECT_TRUE(check_shear_params(p).empty());
}

}  // namespace
