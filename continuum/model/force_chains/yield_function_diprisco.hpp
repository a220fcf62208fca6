// Closed yield locus of di Prisco, Nova & Lanier (1993), as documented with TOCHNOG (plasti.cc,
// group_materi_plasti_diprisco), compression positive. χ is the unit axis of the locus
// (|χ| = 1; isotropic axis I/√3):
//   r = σ:χ,  s = σ - r χ,  η = √3 s / r,  J2η = η:η,  J3η = tr(η·η·η),
//   f = A ln(r/r_c) - γ J3η + (9/4)(γ-1) J2η,   A = 3 β_f (γ-3).
// f is dimensionless; f <= 0 inside. The locus passes through the origin (the stress-free state)
// and crosses the axis χ at r = r_c.
// Gradients (G_η = ∂f/∂η = -3γ η·η + (9/2)(γ-1) η):
//   ∂f/∂σ   = A χ/r + (√3/r) [G_η - (G_η:σ/r) χ]
//   ∂f/∂r_c = -A/r_c
//   ∂f/∂χ   = A σ/r - √3 [(G_η:σ) σ/r² + G_η]
#pragma once

#include <cmath>

#include "continuum/model/force_chains/force_chain_parameters.hpp"
#include "continuum/model/force_chains/stress_invariants.hpp"

namespace granflow::model::force_chains {

struct YieldGradients {
  double value;     // f
  Tensor d_stress;  // ∂f/∂σ, 1/Pa
  double d_size;    // ∂f/∂r_c, 1/Pa
  Tensor d_axis;    // ∂f/∂χ, -
};

class YieldFunctionDiPrisco {
 public:
  explicit YieldFunctionDiPrisco(const ForceChainParameters& p)
      : gamma_(p.gamma), a_(3.0 * p.beta_f * (p.gamma - 3.0)), c2_(2.25 * (p.gamma - 1.0)) {}

  double log_coefficient() const { return a_; }

  // f for r > 0 and r_c > 0 (the caller guarantees both; see ForceChainModel for r -> 0).
  double value(const Tensor& stress, const Tensor& axis, double size) const {
    const double r = double_contraction(stress, axis);
    const Tensor eta = (std::sqrt(3.0) / r) * (stress - r * axis);
    const Tensor eta2 = eta * eta;
    return a_ * std::log(r / size) - gamma_ * double_contraction(eta2, eta) +
           c2_ * double_contraction(eta, eta);
  }

  // ∂f/∂σ alone (the d_stress of gradients(), same expressions).
  Tensor stress_gradient(const Tensor& stress, const Tensor& axis, double size) const {
    (void)size;  // ∂f/∂σ does not depend on r_c
    return shape(stress, axis).d_stress(a_, axis);
  }

  YieldGradients gradients(const Tensor& stress, const Tensor& axis, double size) const {
    const Shape sh = shape(stress, axis);
    YieldGradients g;
    g.value = a_ * std::log(sh.r / size) - gamma_ * double_contraction(sh.eta2, sh.eta) +
              c2_ * double_contraction(sh.eta, sh.eta);
    g.d_stress = sh.d_stress(a_, axis);
    g.d_size = -a_ / size;
    g.d_axis = (a_ / sh.r) * stress - sh.sqrt3 * ((sh.g_sigma / (sh.r * sh.r)) * stress + sh.g_eta);
    return g;
  }

  // ∂f/∂σ, ∂f/∂r_c and ∂f/∂χ without f (no logarithm), the same formulas as gradients() with
  // 1/r and 1/r_c formed once (round-off apart, the same values).
  YieldGradients gradients_only(const Tensor& stress, const Tensor& axis, double size) const {
    constexpr double kSqrt3 = 1.7320508075688772;
    const double r = double_contraction(stress, axis), inv_r = 1.0 / r;
    const Tensor eta = (kSqrt3 * inv_r) * (stress - r * axis);
    const Tensor g_eta = -3.0 * gamma_ * (eta * eta) + 2.0 * c2_ * eta;
    const double g_sigma_r = double_contraction(g_eta, stress) * inv_r;  // g_η:σ / r
    YieldGradients g;
    g.value = 0.0;  // not evaluated
    g.d_stress = inv_r * ((a_ - kSqrt3 * g_sigma_r) * axis + kSqrt3 * g_eta);
    g.d_size = -a_ / size;
    g.d_axis = ((a_ - kSqrt3 * g_sigma_r) * inv_r) * stress - kSqrt3 * g_eta;
    return g;
  }

 private:
  // The pieces ∂f/∂σ and ∂f/∂α share: r = σ:α, η = √3 (σ - r α)/r, η², g_η = ∂f/∂η, g_η:σ.
  struct Shape {
    double sqrt3, r;
    Tensor eta, eta2, g_eta;
    double g_sigma;
    // ∂f/∂σ = (a/r) α + (√3/r) (g_η - (g_η:σ / r) α)
    Tensor d_stress(double a, const Tensor& axis) const {
      return (a / r) * axis + (sqrt3 / r) * (g_eta - (g_sigma / r) * axis);
    }
  };
  Shape shape(const Tensor& stress, const Tensor& axis) const {
    Shape sh;
    sh.sqrt3 = std::sqrt(3.0);
    sh.r = double_contraction(stress, axis);
    sh.eta = (sh.sqrt3 / sh.r) * (stress - sh.r * axis);
    sh.eta2 = sh.eta * sh.eta;
    sh.g_eta = -3.0 * gamma_ * sh.eta2 + 2.0 * c2_ * sh.eta;
    sh.g_sigma = double_contraction(sh.g_eta, stress);
    return sh;
  }

  double gamma_, a_, c2_;
};

}  // namespace granflow::model::force_chains
