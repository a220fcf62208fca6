// Singular closures: finite and monotone increasing up to the singularity minus 1e-12, refused
// (std::domain_error) at and beyond it; no NaN anywhere in the admissible domain.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "continuum/model/closures.hpp"

namespace gm = granflow::model;

namespace {

// Fine grid on (lower, upper - 1e-12]: 4000 uniform points plus points geometrically
// approaching the singularity down to 1e-12 (where the singular terms dominate).
std::vector<double> fine_grid(double lower, double upper) {
  std::vector<double> grid;
  for (int i = 1; i <= 4000; ++i) grid.push_back(lower + (upper - lower) * i / 4001.0);
  for (double gap = 1e-2; gap >= 0.99e-12; gap /= 3.0) grid.push_back(upper - gap);
  grid.push_back(upper - 1e-12);
  std::sort(grid.begin(), grid.end());
  grid.erase(std::unique(grid.begin(), grid.end()), grid.end());
  return grid;
}

std::vector<gm::CollisionalParameters> singular_options() {
  std::vector<gm::CollisionalParameters> out;
  for (auto g0 : gm::all_options<gm::RadialDistributionKind>()) {
    for (double nu_c : {0.587, 0.636}) {
      gm::CollisionalParameters p;
      p.radial_distribution = g0;
      p.jamming_fraction = nu_c;
      out.push_back(p);
    }
  }
  return out;
}

}  // namespace

TEST(ClosuresSingular, CollisionalFiniteAndMonotoneUpToJamming) {
  for (const auto& p : singular_options()) {
    const double nu_c = gm::maximum_solid_fraction(p);
    EXPECT_EQ(nu_c, p.jamming_fraction);  // every option, Carnahan-Starling included
    gm::CollisionalCoefficients previous;
    bool first = true;
    for (double nu : fine_grid(1e-6, nu_c)) {
      const auto c = gm::collisional_coefficients(p, nu);
      for (double value : {c.g0, c.f1, c.f2, c.f3, c.f4, c.J}) {
        ASSERT_TRUE(std::isfinite(value) && value > 0.0) << "nu=" << nu;
      }
      const double R = gm::dissipation_resistance(nu, c.g0);
      ASSERT_TRUE(std::isfinite(R));
      if (!first) {
        // g0, pressure, dissipation and R_diss grow with ν everywhere; viscosity and
        // conductivity only in the dense regime (their dilute limit ∝ 1/g0 decreases first).
        EXPECT_GT(c.g0, previous.g0) << "nu=" << nu;
        EXPECT_GT(c.f1, previous.f1) << "nu=" << nu;
        EXPECT_GT(c.f3, previous.f3) << "nu=" << nu;
        EXPECT_GT(R, gm::dissipation_resistance(previous.nu, previous.g0)) << "nu=" << nu;
        if (nu > 0.1) {
          EXPECT_GT(c.f2, previous.f2) << "nu=" << nu;
          EXPECT_GT(c.f4, previous.f4) << "nu=" << nu;
        }
      }
      previous = c;
      first = false;
    }
    for (double nu :
         {nu_c, nu_c + 1e-12, 0.7, 1.0, 0.0, -0.1, std::numeric_limits<double>::quiet_NaN()}) {
      EXPECT_THROW(gm::collisional_coefficients(p, nu), std::domain_error) << "nu=" << nu;
    }
  }
}

TEST(ClosuresSingular, BadJammingFractionRefused) {
  gm::CollisionalParameters p;
  p.radial_distribution = gm::RadialDistributionKind::torquato;
  p.jamming_fraction = 0.45;  // below Torquato's freezing point 0.49
  EXPECT_THROW(gm::maximum_solid_fraction(p), std::invalid_argument);
  p.radial_distribution = gm::RadialDistributionKind::chialvo_sundaresan;
  p.jamming_fraction = 1.2;
  EXPECT_THROW(gm::collisional_coefficients(p, 0.3), std::invalid_argument);
}

TEST(ClosuresSingular, MixtureViscosityFiniteAndMonotoneUpToMaximumPacking) {
  for (auto kind : {gm::MixtureViscosityKind::krieger_dougherty, gm::MixtureViscosityKind::boyer}) {
    gm::LiquidParameters l;
    l.mixture_viscosity = kind;
    const double nu_m = gm::maximum_mixture_solid_fraction(l);
    EXPECT_EQ(nu_m, l.maximum_packing);
    double previous = gm::mixture_viscosity(l, 0.0);
    for (double nu : fine_grid(1e-6, nu_m)) {
      const double eta = gm::mixture_viscosity(l, nu);
      ASSERT_TRUE(std::isfinite(eta)) << "nu=" << nu;
      EXPECT_GT(eta, previous) << "nu=" << nu;
      previous = eta;
    }
    for (double nu : {nu_m, nu_m + 1e-12, 0.9, -1e-9, std::numeric_limits<double>::quiet_NaN()}) {
      EXPECT_THROW(gm::mixture_viscosity(l, nu), std::domain_error) << "nu=" << nu;
    }
  }
  gm::LiquidParameters einstein;
  einstein.mixture_viscosity = gm::MixtureViscosityKind::einstein;
  EXPECT_EQ(gm::maximum_mixture_solid_fraction(einstein), 1.0);
  EXPECT_THROW(gm::mixture_viscosity(einstein, 1.0), std::domain_error);
}

TEST(ClosuresSingular, PermeabilityDomain) {
  gm::LiquidParameters l;
  for (double nu : {0.0, 1.0, -0.1, 1.5}) {
    EXPECT_THROW(gm::permeability(l, 1e-3, nu), std::domain_error) << "nu=" << nu;
  }
  for (double nu : {1.0, -0.1}) {
    EXPECT_THROW(gm::drag_coefficient(l, 1e-3, nu), std::domain_error) << "nu=" << nu;
    EXPECT_THROW(gm::particle_drag_coefficient(l, 1e-3, nu), std::domain_error) << "nu=" << nu;
  }
  // drag grows monotonically and stays finite up to 1 - 1e-12 for every correlation
  for (auto kind : gm::all_options<gm::PermeabilityKind>()) {
    l.permeability = kind;
    double previous = 0.0;
    for (double nu : fine_grid(1e-6, 1.0)) {
      const double beta = gm::drag_coefficient(l, 1e-3, nu);
      ASSERT_TRUE(std::isfinite(beta)) << "nu=" << nu;
      EXPECT_GT(beta, previous) << "nu=" << nu;
      previous = beta;
    }
  }
}

// No NaN/Inf for ν in (1e-6, ν_c - 1e-12), T in [0, 1e3], γ̇ in [0, 1e4], every option.
TEST(ClosuresSingular, NoNaNOverTheWholeDomain) {
  for (auto p : singular_options()) {
    for (auto L_kind : gm::all_options<gm::CorrelationLengthKind>()) {
      p.correlation_length = L_kind;
      for (auto eta_kind : gm::all_options<gm::MixtureViscosityKind>()) {
        for (auto kappa_kind : gm::all_options<gm::PermeabilityKind>()) {
          gm::LiquidParameters l;
          l.mixture_viscosity = eta_kind;
          l.permeability = kappa_kind;
          l.maximum_packing = p.jamming_fraction;
          const double nu_max =
              std::min(gm::maximum_solid_fraction(p), gm::maximum_mixture_solid_fraction(l));
          for (double nu : {1e-6, 1e-3, 0.1, 0.3, 0.5, nu_max - 1e-6, nu_max - 1e-12}) {
            const auto c = gm::collisional_coefficients(p, nu);
            for (double T : {0.0, 1e-30, 1e-12, 1e-3, 1.0, 1e3}) {
              for (double shear_rate : {0.0, 1e-6, 1.0, 1e4}) {
                const double values[] = {
                    gm::collisional_pressure(p, c, T),
                    gm::collisional_viscosity(p, c, T),
                    gm::collisional_dissipation_at_shear_rate(p, c, shear_rate, T),
                    gm::collisional_conductivity(p, c, T),
                    gm::mixture_viscosity(l, nu),
                    gm::permeability(l, p.diameter, nu),
                    gm::drag_coefficient_with_inertia(l, p.diameter, nu, shear_rate * p.diameter),
                    gm::particle_drag_coefficient(l, p.diameter, nu),
                    gm::liquid_fluctuation_dissipation(l, p.diameter, nu, c.g0, T)};
                for (double value : values) {
                  ASSERT_TRUE(std::isfinite(value) && value >= 0.0)
                      << "nu=" << nu << " T=" << T << " shear_rate=" << shear_rate;
                }
                const double L = gm::correlation_length(p, c, shear_rate, T);
                ASSERT_FALSE(std::isnan(L));
                ASSERT_GE(L, p.diameter);
                // L is infinite only where documented: T = 0 with γ̇ ≠ 0 and Jenkins' L
                if (std::isinf(L)) {
                  ASSERT_TRUE(T == 0.0 && shear_rate != 0.0);
                }
                ASSERT_FALSE(std::isnan(gm::collisional_dissipation(p, c, T, L)));
              }
            }
          }
        }
      }
    }
  }
}
