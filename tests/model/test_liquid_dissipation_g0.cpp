// Λ with the liquid's own g0 (liquid.dissipation_radial_distribution): R_diss's lubrication term
// takes that option's g0 at ν instead of the one the caller passes (the collisional closures').
#include <gtest/gtest.h>

#include <cmath>

#include "continuum/model/closures.hpp"
#include "continuum/model/dissipation_resistance.hpp"

using namespace granflow::model;

TEST(LiquidDissipation, OwnRadialDistributionReplacesTheCollisionalOne) {
  LiquidParameters l;
  const double d = 1e-3, nu = 0.5745, T = 2e-6, g0_collisional = 77.4;
  // Unset: the g0 passed in.
  const double passed = liquid_fluctuation_dissipation(l, d, nu, g0_collisional, T);
  EXPECT_DOUBLE_EQ(passed, 54.0 * nu * l.viscosity *
                               dissipation_resistance_koch_sangani(nu, g0_collisional) * T /
                               (d * d));
  // Carnahan-Starling at ν (closed form (1 - ν/2)/(1 - ν)³ = 9.252 at 0.5745), whatever is
  // passed; R_diss falls from 203 to 22.6 there.
  l.dissipation_radial_distribution = RadialDistributionKind::carnahan_starling;
  const double g0_cs = (1.0 - nu / 2.0) / std::pow(1.0 - nu, 3);
  const double own = liquid_fluctuation_dissipation(l, d, nu, g0_collisional, T);
  EXPECT_DOUBLE_EQ(
      own, 54.0 * nu * l.viscosity * dissipation_resistance_koch_sangani(nu, g0_cs) * T / (d * d));
  EXPECT_NEAR(dissipation_resistance_koch_sangani(nu, g0_cs), 22.6, 0.05);
  EXPECT_NEAR(passed / own, 203.0 / 22.6, 0.05);
}
