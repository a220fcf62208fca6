// Liquid closures: mixture viscosity η(ν), permeability, drag, Λ with R_diss
// (docs/model/closures.md).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "continuum/model/closures.hpp"

namespace gm = granflow::model;

namespace {
constexpr double pi = std::numbers::pi;
double relative_difference(double a, double b) { return std::fabs(a - b) / std::fabs(b); }
}  // namespace

TEST(ClosuresMixtureViscosity, EinsteinIsLinear) {
  gm::LiquidParameters l;
  l.mixture_viscosity = gm::MixtureViscosityKind::einstein;
  for (double nu : {0.0, 0.1, 0.3, 0.6}) {
    EXPECT_NEAR(gm::mixture_viscosity(l, nu), l.viscosity * (1.0 + 2.5 * nu), 1e-18);
  }
}

// Krieger-Dougherty and Boyer reduce to Einstein to first order in ν:
// (η/η0 - 1)/ν -> 2.5, with an O(ν) second-order remainder (coefficient < 6 for ν_m ≈ 0.585).
TEST(ClosuresMixtureViscosity, KriegerDoughertyAndBoyerReduceToEinstein) {
  for (auto kind : {gm::MixtureViscosityKind::krieger_dougherty, gm::MixtureViscosityKind::boyer}) {
    gm::LiquidParameters l;
    l.mixture_viscosity = kind;
    EXPECT_DOUBLE_EQ(gm::mixture_viscosity(l, 0.0), l.viscosity);
    for (double nu : {1e-3, 1e-4, 1e-5}) {
      const double slope = (gm::mixture_viscosity(l, nu) / l.viscosity - 1.0) / nu;
      // second order ≤ 6ν; rounding of η/η0 - 1 is ~1e-16/ν ≤ 1e-11
      EXPECT_NEAR(slope, 2.5, 6.0 * nu + 1e-10) << "nu=" << nu;
      EXPECT_GT(slope, 2.5);  // both stiffen faster than Einstein
    }
  }
}

// Seed Eq. 26 as printed (void ratio e) and the van der Hoef form A² d²/(18 ν F(ν)) with
// ν = 1/(1+e): two independent expressions of the same permeability.
TEST(ClosuresPermeability, SeedEq26EqualsVanDerHoefForm) {
  for (double sphericity : {1.0, 0.8}) {
    gm::LiquidParameters l;
    l.sphericity = sphericity;
    l.permeability = gm::PermeabilityKind::seed_eq26;
    const double d = 2e-4;
    for (double e = 0.1; e <= 10.0; e *= 1.1) {
      const double nu = 1.0 / (1.0 + e);
      const double as_written = gm::permeability_seed_eq26_void_ratio(sphericity, d, e);
      const double van_der_hoef =
          sphericity * sphericity * d * d / (18.0 * nu * gm::van_der_hoef_drag_factor(nu));
      // 1e-13: same number through different operations (ν = 1/(1+e) adds one rounding).
      EXPECT_LT(relative_difference(as_written, van_der_hoef), 1e-13) << "e=" << e;
      EXPECT_LT(relative_difference(gm::permeability(l, d, nu), as_written), 1e-13) << "e=" << e;
    }
  }
}

// β = η0 n / κ, and the per-particle coefficient is β × (volume per particle) = β π d³/(6ν).
TEST(ClosuresDrag, CoefficientsAreConsistentForAllCorrelations) {
  for (auto kind : {gm::PermeabilityKind::seed_eq26, gm::PermeabilityKind::kozeny_carman,
                    gm::PermeabilityKind::ergun}) {
    gm::LiquidParameters l;
    l.permeability = kind;
    const double d = 1e-3;
    for (double nu : {0.01, 0.2, 0.45, 0.6}) {
      const double beta = gm::drag_coefficient(l, d, nu);
      EXPECT_LT(relative_difference(beta, l.viscosity * (1.0 - nu) / gm::permeability(l, d, nu)),
                1e-14);
      EXPECT_LT(relative_difference(gm::particle_drag_coefficient(l, d, nu),
                                    beta * pi * d * d * d / (6.0 * nu)),
                1e-14);
    }
  }
}

// DEM consistency: the per-particle drag of seed Eq. 26 is 3π η0 d (1-ν) F(ν)/A², i.e. Stokes
// drag 3π η0 d as ν -> 0 (F - 1 ≈ 1.5 √ν).
TEST(ClosuresDrag, ParticleDragTendsToStokes) {
  gm::LiquidParameters l;
  const double d = 5e-4;
  const double stokes = 3.0 * pi * l.viscosity * d;
  EXPECT_LT(relative_difference(gm::particle_drag_coefficient(l, d, 0.0), stokes), 1e-15);
  for (double nu : {1e-6, 1e-8, 1e-10}) {
    EXPECT_LT(relative_difference(gm::particle_drag_coefficient(l, d, nu), stokes),
              1.6 * std::sqrt(nu));
  }
  EXPECT_EQ(gm::drag_coefficient(l, d, 0.0), 0.0);  // no grains, no drag
}

// Ergun: Darcy part in κ plus the Forchheimer term reproduce the classic Ergun pressure gradient
// 150 η0 ν² U/(A² d² n³) + 1.75 ρ_L ν U²/(A d n³) with U = n |u_L - u_G|.
TEST(ClosuresPermeability, ErgunViscousPlusInertialEqualsErgunEquation) {
  gm::LiquidParameters l;
  l.permeability = gm::PermeabilityKind::ergun;
  l.sphericity = 0.9;
  const double d = 2e-3;
  for (double nu : {0.3, 0.5, 0.6}) {
    for (double relative_speed : {1e-4, 0.1, 3.0}) {
      const double n = 1.0 - nu, U = n * relative_speed, A = l.sphericity;
      const double ergun = 150.0 * l.viscosity * nu * nu * U / (A * A * d * d * n * n * n) +
                           1.75 * l.density * nu * U * U / (A * d * n * n * n);
      const double granflow =
          gm::drag_coefficient_with_inertia(l, d, nu, relative_speed) * relative_speed;
      EXPECT_LT(relative_difference(granflow, ergun), 1e-13);
      EXPECT_LT(relative_difference(gm::drag_coefficient_with_inertia(l, d, nu, -relative_speed),
                                    gm::drag_coefficient_with_inertia(l, d, nu, relative_speed)),
                1e-15);
    }
  }
  // Kozeny-Carman has the same viscous structure with 180 instead of 150, and no inertial term.
  gm::LiquidParameters kc = l;
  kc.permeability = gm::PermeabilityKind::kozeny_carman;
  EXPECT_LT(relative_difference(gm::permeability(kc, d, 0.4) / gm::permeability(l, d, 0.4),
                                150.0 / 180.0),
            1e-15);
  EXPECT_EQ(gm::forchheimer_coefficient(kc, d, 0.4), 0.0);
  EXPECT_EQ(gm::drag_coefficient_with_inertia(kc, d, 0.4, 2.0), gm::drag_coefficient(kc, d, 0.4));
}

// R_diss -> 1 as ν -> 0, led by Koch & Sangani's 3 (ν/2)^½ term.
TEST(ClosuresDissipationResistance, DiluteLimit) {
  EXPECT_EQ(gm::dissipation_resistance(0.0, 1.0), 1.0);
  for (double nu : {1e-6, 1e-8, 1e-10}) {
    const double g0 = gm::g0_carnahan_starling(nu);
    const double excess = gm::dissipation_resistance(nu, g0) - 1.0;
    // next terms (135/64) ν ln ν + (11.26 + 4.6 g0) ν are below 60 √ν relative to 3 (ν/2)^½
    EXPECT_NEAR(excess / (3.0 * std::sqrt(nu / 2.0)), 1.0, 60.0 * std::sqrt(nu));
  }
}

// Λ as ν -> 0 is the Stokes-drag dissipation of the fluctuation energy: 3 × (3π η0 d per grain)
// × (number density 6ν/(π d³)) × T. Second path: the DEM per-particle drag coefficient.
TEST(ClosuresLiquidFluctuationDissipation, DiluteLimitIsStokesDrag) {
  gm::LiquidParameters l;
  const double d = 1e-3, T = 0.3;
  for (double nu : {1e-6, 1e-8, 1e-10}) {
    const double g0 = gm::g0_carnahan_starling(nu);
    const double number_density = 6.0 * nu / (pi * d * d * d);
    const double stokes = 3.0 * gm::particle_drag_coefficient(l, d, nu) * number_density * T;
    // R_diss - 1 ≈ 2.1 √ν and F(ν)(1-ν) - 1 ≈ 1.5 √ν
    EXPECT_LT(relative_difference(gm::liquid_fluctuation_dissipation(l, d, nu, g0, T), stokes),
              4.0 * std::sqrt(nu));
  }
}
