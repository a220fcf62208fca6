// Collisional (extended kinetic theory) closures: closed forms of homogeneous steady simple
// shear, dilute limits, published values and independent re-derivations (docs/model/closures.md).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "continuum/model/closures.hpp"

namespace gm = granflow::model;

namespace {

constexpr double pi = std::numbers::pi;
const double sqrt_pi = std::sqrt(pi);

// Every combination of g0 and ε options, with the case-file defaults otherwise.
std::vector<gm::CollisionalParameters> all_collisional_options() {
  std::vector<gm::CollisionalParameters> out;
  for (auto g0 : gm::all_options<gm::RadialDistributionKind>()) {
    for (auto eps : gm::all_options<gm::EffectiveRestitutionKind>()) {
      for (double restitution : {0.3, 0.7, 0.95}) {
        gm::CollisionalParameters p;
        p.radial_distribution = g0;
        p.effective_restitution = eps;
        p.restitution = restitution;
        out.push_back(p);
      }
    }
  }
  return out;
}

double relative_difference(double a, double b) { return std::fabs(a - b) / std::fabs(b); }

}  // namespace

// Homogeneous steady simple shear with L = d: the production τ γ̇ balances Γ at
// T = (f2/f3) d² γ̇², and then τ/p = sqrt(f2 f3)/f1 and I = (f1 f2/f3)^(-1/2). The closed forms
// are evaluated independently of the pressure/viscosity/dissipation functions.
TEST(ClosuresSteadySimpleShear, ClosedFormsAgreeWithIndividualClosures) {
  for (const auto& p : all_collisional_options()) {
    for (double nu : {1e-4, 0.05, 0.3, 0.49, 0.55, 0.58}) {
      for (double shear_rate : {1e-3, 1.0, 1e3}) {
        const auto c = gm::collisional_coefficients(p, nu);
        const double d = p.diameter;
        const double T = c.f2 / c.f3 * d * d * shear_rate * shear_rate;
        const double pressure = gm::collisional_pressure(p, c, T);
        const double shear_stress = gm::collisional_viscosity(p, c, T) * shear_rate;
        const double dissipation = gm::collisional_dissipation(p, c, T, d);
        // 1e-12: the balance is an algebraic identity; each side takes ~10 floating-point
        // operations, i.e. a few 1e-16 of rounding, so 1e-12 only fails on a wrong factor.
        EXPECT_LT(relative_difference(shear_stress * shear_rate, dissipation), 1e-12)
            << "nu=" << nu << " e_r=" << p.restitution;
        EXPECT_LT(relative_difference(shear_stress / pressure, std::sqrt(c.f2 * c.f3) / c.f1),
                  1e-12);
        const double inertial_number = shear_rate * d / std::sqrt(pressure / p.particle_density);
        EXPECT_LT(relative_difference(inertial_number, 1.0 / std::sqrt(c.f1 * c.f2 / c.f3)), 1e-12);
        // With L = d, the shear-rate form of Γ is the same number (same rounding budget).
        EXPECT_LT(relative_difference(
                      gm::collisional_dissipation_at_shear_rate(p, c, shear_rate, T), dissipation),
                  1e-12);
      }
    }
  }
}

// Dilute limit of the viscosity with e_r = 1: Chapman-Enskog (5 √π / 96) ρ_p d T^½. The
// deviation is O(ν) (g0 - 1 ≈ 2.5ν and the 1/G expansion of J), so it must shrink ~10x per
// decade of ν.
TEST(ClosuresDiluteLimits, ChapmanEnskogViscosity) {
  gm::CollisionalParameters p;
  p.restitution = 1.0;
  p.effective_restitution = gm::EffectiveRestitutionKind::restitution;
  const double T = 2.0;
  const double chapman_enskog =
      5.0 * sqrt_pi / 96.0 * p.particle_density * p.diameter * std::sqrt(T);
  double previous_error = 1.0;
  for (double nu : {1e-4, 1e-5, 1e-6, 1e-7}) {
    const auto c = gm::collisional_coefficients(p, nu);
    const double error = relative_difference(gm::collisional_viscosity(p, c, T), chapman_enskog);
    EXPECT_LT(error, 20.0 * nu);  // O(ν) with a coefficient of order 10 (g0, J expansions)
    EXPECT_LT(error, 0.2 * previous_error);  // converges linearly in ν
    previous_error = error;
  }
}

TEST(ClosuresDiluteLimits, PressureCoefficientTendsToSolidFraction) {
  for (const auto& p : all_collisional_options()) {
    for (double nu : {1e-5, 1e-6, 1e-7}) {
      const auto c = gm::collisional_coefficients(p, nu);
      // f1/ν - 1 = 2 (1+e_r) ν g0 ≤ 4.1 ν for ν ≤ 1e-5: ideal-gas pressure ρ_p ν T.
      EXPECT_LT(std::fabs(c.f1 / nu - 1.0), 4.1 * nu);
      EXPECT_GT(c.f1 / nu - 1.0, 0.0);
    }
  }
}

// Dilute elastic conductivity: Chapman-Enskog first Sonine approximation
// k = (75/64) k_B/d² (k_B T/(π m))^½, i.e. (25 √π / 128) ρ_p d T^½ in granular units.
TEST(ClosuresDiluteLimits, ChapmanEnskogConductivity) {
  gm::CollisionalParameters p;
  p.restitution = 1.0;
  p.effective_restitution = gm::EffectiveRestitutionKind::restitution;
  const double T = 0.5;
  const double chapman_enskog =
      25.0 * sqrt_pi / 128.0 * p.particle_density * p.diameter * std::sqrt(T);
  for (double nu : {1e-5, 1e-6, 1e-7}) {
    const auto c = gm::collisional_coefficients(p, nu);
    // O(ν) deviation: (1 + 12G/5)²/g0 expansion, coefficient ~ 5 + 2.5 + 4/√π·...
    EXPECT_LT(relative_difference(gm::collisional_conductivity(p, c, T), chapman_enskog),
              20.0 * nu);
  }
}

// Dense elastic limit of f4: Enskog's conductivity (Chapman & Cowling, first approximation)
// (25 √π/128) [(1 + 12G/5)²/g0 + (512/(25π)) ν G], a different algebraic path from M.
TEST(ClosuresDenseElastic, ConductivityEqualsEnskog) {
  for (auto g0_kind : {gm::RadialDistributionKind::carnahan_starling,
                       gm::RadialDistributionKind::chialvo_sundaresan}) {
    gm::CollisionalParameters p;
    p.radial_distribution = g0_kind;
    p.restitution = 1.0;
    for (double nu : {0.01, 0.2, 0.4, 0.55, 0.585}) {
      const auto c = gm::collisional_coefficients(p, nu);
      const double G = c.G;
      const double enskog =
          25.0 * sqrt_pi / 128.0 *
          ((1.0 + 2.4 * G) * (1.0 + 2.4 * G) / c.g0 + 512.0 / (25.0 * pi) * nu * G);
      EXPECT_LT(relative_difference(c.f4, enskog), 1e-12);  // rounding only (identity)
    }
  }
}

// Independent re-derivation of f2 and f4 from Garzó & Dufty (1999) in their own variables
// (as implemented in MFiX GT_PDE_GD, with c* = 0): η* = η_k*(1 + (4/5)φχ(1+e)) + (3/5)γ*,
// κ* = κ_k*(1 + (6/5)φχ(1+e)) + (256/25π)φ²χ(1+e); f2 = (5√π/96) η*, f4 = (25√π/128) κ*.
TEST(ClosuresGarzoDufty1999, TransportCoefficientsMatchTheirOwnForm) {
  for (const auto& p : all_collisional_options()) {
    for (double nu : {0.001, 0.1, 0.3, 0.5, 0.57}) {
      const auto c = gm::collisional_coefficients(p, nu);
      const double e = p.restitution, chi = c.g0, phi = nu;
      const double zeta = 5.0 / 12.0 * chi * (1.0 - e * e);
      const double nu_eta = chi * (1.0 - 0.25 * (1.0 - e) * (1.0 - e));
      const double gamma = 128.0 / (5.0 * pi) * phi * phi * chi * (1.0 + e);
      const double eta_k =
          (1.0 - 0.4 * (1.0 + e) * (1.0 - 3.0 * e) * phi * chi) / (nu_eta - 0.5 * zeta);
      const double eta = eta_k * (1.0 + 0.8 * phi * chi * (1.0 + e)) + 0.6 * gamma;
      const double nu_kappa = chi / 3.0 * (1.0 + e) * (1.0 + 33.0 / 16.0 * (1.0 - e));
      const double kappa_k = 2.0 / 3.0 *
                             (1.0 + 0.6 * phi * chi * (1.0 + e) * (1.0 + e) * (2.0 * e - 1.0)) /
                             (nu_kappa - 2.0 * zeta);
      const double kappa = kappa_k * (1.0 + 1.2 * phi * chi * (1.0 + e)) +
                           256.0 / 25.0 * phi * phi / pi * chi * (1.0 + e);
      // 1e-11: two algebraically equal forms; near ν -> 0 both carry 1/G terms and lose a few
      // digits to cancellation-free rounding only, so 1e-11 flags any wrong coefficient.
      EXPECT_LT(relative_difference(c.f2, 5.0 * sqrt_pi / 96.0 * eta), 1e-11) << nu << " " << e;
      EXPECT_LT(relative_difference(c.f4, 25.0 * sqrt_pi / 128.0 * kappa), 1e-11) << nu << " " << e;
      // Pressure p = n T p*, p* = 1 + 2(1+e)φχ, and cooling: Γ = (3/2) n T ζ* ν0 with
      // ν0 = n T/η0 the Chapman-Enskog collision frequency (η0 = (5√π/96) ρ_p d T^½) and ε in
      // place of e in ζ* (docs/model/closures.md). n T = ρ_p ν T in granular units.
      const double T = 0.7;
      const double nT = p.particle_density * nu * T;
      EXPECT_LT(relative_difference(gm::collisional_pressure(p, c, T),
                                    nT * (1.0 + 2.0 * (1.0 + e) * phi * chi)),
                1e-13);
      const double eta0 = 5.0 * sqrt_pi / 96.0 * p.particle_density * p.diameter * std::sqrt(T);
      const double zeta_eps = 5.0 / 12.0 * chi * (1.0 - c.epsilon * c.epsilon);
      EXPECT_LT(relative_difference(gm::collisional_dissipation(p, c, T, p.diameter),
                                    1.5 * nT * zeta_eps * nT / eta0),
                1e-13);
    }
  }
}

// Published values of g0.
TEST(ClosuresRadialDistribution, PublishedValues) {
  // Carnahan-Starling at ν = 0.5: (1 - 0.25)/0.125 = 6 exactly.
  EXPECT_DOUBLE_EQ(gm::g0_carnahan_starling(0.5), 6.0);
  // Torquato: equals Carnahan-Starling up to freezing 0.49, continuous there, simple pole at ν_c
  // with residue g0(0.49)(ν_c - 0.49).
  const double nu_c = 0.64;
  EXPECT_DOUBLE_EQ(gm::g0_torquato(0.3, nu_c), gm::g0_carnahan_starling(0.3));
  const double at_freezing = gm::g0_carnahan_starling(0.49);
  EXPECT_NEAR(gm::g0_torquato(0.49 + 1e-12, nu_c), at_freezing, 1e-9);  // slope ~40 × 1e-12
  for (double distance : {1e-2, 1e-6, 1e-12}) {
    // 1e-9 relative: (ν_c - ν) recomputed from ν_c - distance loses ~1e-16/distance.
    EXPECT_NEAR(gm::g0_torquato(nu_c - distance, nu_c) * distance, at_freezing * (nu_c - 0.49),
                at_freezing * (nu_c - 0.49) * (1e-9 + 1e-15 / distance));
  }
  // Chialvo-Sundaresan: the excess over Carnahan-Starling is 0.58 ν²/(ν_c - ν)^{3/2}.
  for (double nu : {0.1, 0.4, 0.58}) {
    const double excess = gm::g0_chialvo_sundaresan(nu, 0.587) - gm::g0_carnahan_starling(nu);
    EXPECT_NEAR(excess * std::pow(0.587 - nu, 1.5) / (nu * nu), 0.58, 1e-9);
  }
}

// Chialvo & Sundaresan (2013) effective restitution: largest reduction 1/(2e) at μ_p = 1/3.
TEST(ClosuresEffectiveRestitution, ChialvoSundaresanFrictionCorrection) {
  gm::CollisionalParameters p;
  p.restitution = 0.9;
  p.particle_friction = 1.0 / 3.0;
  EXPECT_NEAR(gm::effective_restitution(p), 0.9 - 0.5 / std::numbers::e, 1e-15);
  p.particle_friction = 0.0;
  EXPECT_DOUBLE_EQ(gm::effective_restitution(p), 0.9);  // frictionless: ε = e_r
  for (double mu : {0.1, 0.25, 0.5, 1.0}) {             // maximum of the reduction is at 1/3
    p.particle_friction = mu;
    EXPECT_GT(gm::effective_restitution(p), 0.9 - 0.5 / std::numbers::e);
  }
  p.effective_restitution = gm::EffectiveRestitutionKind::restitution;
  EXPECT_DOUBLE_EQ(gm::effective_restitution(p), 0.9);
}

// Jenkins correlation length: L = d max(1, a/T^½), and Γ with L folded in is finite at T = 0.
TEST(ClosuresCorrelationLength, JenkinsFormAndDissipation) {
  gm::CollisionalParameters p;
  p.correlation_length = gm::CorrelationLengthKind::jenkins;
  const auto c = gm::collisional_coefficients(p, 0.55);
  const double shear_rate = 10.0;
  const double a = p.correlation_length_constant *
                   std::sqrt(2.0 * c.J / (15.0 * (1.0 - c.epsilon * c.epsilon))) * p.diameter *
                   shear_rate;
  for (double T : {1e-12, 1e-8, a * a * 0.99, a * a * 1.01, 1.0}) {
    const double L = gm::correlation_length(p, c, shear_rate, T);
    const double expected = p.diameter * std::max(1.0, a / std::sqrt(T));
    EXPECT_LT(relative_difference(L, expected), 1e-14);
    EXPECT_GE(L, p.diameter);
    EXPECT_LT(relative_difference(gm::collisional_dissipation_at_shear_rate(p, c, shear_rate, T),
                                  gm::collisional_dissipation(p, c, T, L)),
              1e-13);  // two algebraic paths, a few roundings each
  }
  EXPECT_EQ(gm::collisional_dissipation_at_shear_rate(p, c, shear_rate, 0.0), 0.0);
  EXPECT_EQ(gm::collisional_dissipation_at_shear_rate(p, c, 0.0, 0.0), 0.0);
  EXPECT_EQ(gm::correlation_length(p, c, 0.0, 0.0), p.diameter);
  p.correlation_length = gm::CorrelationLengthKind::diameter;
  EXPECT_EQ(gm::correlation_length(p, c, shear_rate, 1e-12), p.diameter);
}

// Elastic frictionless grains (ε = 1, f3 = 0) with Jenkins' L: no dissipation and no NaN, at
// rest (γ̇ = 0, where a naive ∞ · 0 would give NaN) and sheared (L = ∞ documented).
TEST(ClosuresCorrelationLength, ElasticGrainsGiveNoNaN) {
  gm::CollisionalParameters p;
  p.restitution = 1.0;
  p.particle_friction = 0.0;
  p.correlation_length = gm::CorrelationLengthKind::jenkins;
  const auto c = gm::collisional_coefficients(p, 0.5);
  ASSERT_EQ(c.epsilon, 1.0);
  for (double shear_rate : {0.0, 5.0}) {
    for (double T : {0.0, 1e-3}) {
      EXPECT_EQ(gm::collisional_dissipation_at_shear_rate(p, c, shear_rate, T), 0.0);
      const double L = gm::correlation_length(p, c, shear_rate, T);
      EXPECT_FALSE(std::isnan(L));
      EXPECT_EQ(gm::collisional_dissipation(p, c, T, L), 0.0);
      if (shear_rate == 0.0) {
        EXPECT_EQ(L, p.diameter);
      }
    }
  }
}
