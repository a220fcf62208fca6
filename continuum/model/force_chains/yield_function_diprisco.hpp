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
// The evaluation works on symmetric tensors (symmetric_tensor.hpp): the pieces r, 1/r, η and
// η·η (`Locus`) are formed once and serve f and the gradients; the 3 × 3 matrix forms below
// convert (their symmetric parts) and call them.
#pragma once

#include <cmath>

#include "continuum/model/force_chains/force_chain_parameters.hpp"
#include "continuum/model/force_chains/stress_invariants.hpp"
#include "continuum/model/force_chains/symmetric_tensor.hpp"

namespace granflow::model::force_chains {

struct YieldGradients {
  double value;     // f
  Tensor d_stress;  // ∂f/∂σ, 1/Pa
  double d_size;    // ∂f/∂r_c, 1/Pa
  Tensor d_axis;    // ∂f/∂χ, -
};

class YieldFunctionDiPrisco {
 public:
  // r = σ:χ, 1/r, η = √3 (σ/r - χ) and η·η at one (σ, χ) with r > 0.
  struct Locus {
    double r, inv_r;
    SymTensor eta, eta2;
  };
  // ∂f/∂σ and ∂f/∂χ at one (σ, χ) (∂f/∂r_c = -A/r_c needs no tensor).
  struct Gradients {
    SymTensor d_stress, d_axis;
  };

  explicit YieldFunctionDiPrisco(const ForceChainParameters& p)
      : gamma_(p.gamma), a_(3.0 * p.beta_f * (p.gamma - 3.0)), c2_(2.25 * (p.gamma - 1.0)) {}

  double log_coefficient() const { return a_; }  // A

  Locus locus(const SymTensor& stress, const SymTensor& axis) const {
    Locus l;
    l.r = double_contraction(stress, axis);
    l.inv_r = 1.0 / l.r;
    l.eta = combine(kSqrt3 * l.inv_r, stress, -kSqrt3, axis);
    l.eta2 = square(l.eta);
    return l;
  }
  // f = A ln(r/r_c) - γ η·η:η + (9/4)(γ-1) η:η for r > 0 and r_c > 0 (the caller guarantees
  // both; see ForceChainModel for r -> 0).
  double value(const Locus& l, double size) const {
    return a_ * std::log(l.r / size) - gamma_ * double_contraction(l.eta2, l.eta) +
           c2_ * double_contraction(l.eta, l.eta);
  }
  double value(const SymTensor& stress, const SymTensor& axis, double size) const {
    return value(locus(stress, axis), size);
  }
  // ∂f/∂σ = (1/r) [(A - √3 G_η:σ/r) χ + √3 G_η],  ∂f/∂χ = ((A - √3 G_η:σ/r)/r) σ - √3 G_η
  // (the header's formulas with 1/r formed once).
  Gradients gradients(const Locus& l, const SymTensor& stress, const SymTensor& axis) const {
    const SymTensor g_eta = combine(-3.0 * gamma_, l.eta2, 2.0 * c2_, l.eta);
    const double k = a_ - kSqrt3 * double_contraction(g_eta, stress) * l.inv_r;
    return {combine(k * l.inv_r, axis, kSqrt3 * l.inv_r, g_eta),
            combine(k * l.inv_r, stress, -kSqrt3, g_eta)};
  }

  // 3 × 3 matrix forms (diagnostics and tests).
  double value(const Tensor& stress, const Tensor& axis, double size) const {
    return value(SymTensor::from(stress), SymTensor::from(axis), size);
  }
  Tensor stress_gradient(const Tensor& stress, const Tensor& axis, double size) const {
    return gradients(stress, axis, size).d_stress;
  }
  YieldGradients gradients(const Tensor& stress, const Tensor& axis, double size) const {
    const SymTensor s = SymTensor::from(stress), x = SymTensor::from(axis);
    const Locus l = locus(s, x);
    const Gradients g = gradients(l, s, x);
    return {value(l, size), g.d_stress.matrix(), -a_ / size, g.d_axis.matrix()};
  }

 private:
  static constexpr double kSqrt3 = 1.7320508075688772;
  double gamma_, a_, c2_;
};

}  // namespace granflow::model::force_chains
