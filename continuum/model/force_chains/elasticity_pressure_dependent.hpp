// Pressure-dependent isotropic hypo-elasticity of the force-chain skeleton (compression positive):
//   dσ = K(p) tr(dε) I + 2 G(p) dev(dε),  K(p) = K_ref (max(p, p_floor)/p_ref)^n,
//   G = K · 3(1-2ν)/(2(1+ν))   (constant Poisson ratio ν).
// The floor p_floor keeps K > 0 as p -> 0 (well-posed at liquefaction). Along a straight strain
// path the law integrates in closed form (`finite_update`): the volumetric part
// dp/dε_v = K(p) gives p^{1-n} - p0^{1-n} = (1-n) K_ref p_ref^{-n} Δε_v above the floor and a
// linear law below it; with ν constant ds = 2(G/K) dp/dε_v de, hence Δs = 2(G/K) (Δp/Δε_v) Δe.
// The plastic update calls the symmetric-tensor forms (symmetric_tensor.hpp); the 3 × 3 matrix
// forms serve diagnostics and tests.
#pragma once

#include <cmath>

#include "continuum/model/force_chains/force_chain_parameters.hpp"
#include "continuum/model/force_chains/stress_invariants.hpp"
#include "continuum/model/force_chains/symmetric_tensor.hpp"

namespace granflow::model::force_chains {

class PressureDependentElasticity {
 public:
  explicit PressureDependentElasticity(const ForceChainParameters& p)
      : k_ref_(p.bulk_modulus_ref),
        p_ref_(p.reference_pressure),
        n_(p.elastic_exponent),
        p_floor_(p.pressure_floor),
        shear_to_bulk_(1.5 * (1.0 - 2.0 * p.poisson_ratio) / (1.0 + p.poisson_ratio)),
        k_floor_(k_ref_ * std::pow(p_floor_ / p_ref_, n_)),
        k_scale_(k_ref_ / std::pow(p_ref_, n_)),
        power_coefficient_((1.0 - n_) * k_scale_),
        u_floor_(std::pow(p_floor_, 1.0 - n_)) {}

  // K(p) = K_ref (p/p_ref)^n = (K_ref p_ref^-n) p^n above the floor (no division per call)
  double bulk_modulus(double p) const { return p > p_floor_ ? k_scale_ * power(p, n_) : k_floor_; }
  double shear_modulus(double p) const { return shear_to_bulk_ * bulk_modulus(p); }
  double shear_to_bulk() const { return shear_to_bulk_; }

  // Tangent stiffness applied to a strain-like tensor at mean stress p.
  Tensor apply(double p, const Tensor& strain) const {
    return apply_with_modulus(bulk_modulus(p), strain);
  }
  // The same with K = bulk_modulus(p) known to the caller.
  Tensor apply_with_modulus(double k, const Tensor& strain) const {
    const double tr = strain.trace();
    return 2.0 * shear_to_bulk_ * k * (strain - tr / 3.0 * Tensor::Identity()) +
           k * tr * Tensor::Identity();
  }
  // K tr(ε) I + 2 G dev(ε) with K = bulk_modulus(p) known to the caller, symmetric storage.
  SymTensor apply_with_modulus(double k, const SymTensor& strain) const {
    const double tr = strain.trace(), two_g = 2.0 * shear_to_bulk_ * k;
    return (two_g * strain).add_identity((k - two_g * (1.0 / 3.0)) * tr);
  }
  // Compliance (inverse of `apply`) at mean stress p.
  Tensor apply_inverse(double p, const Tensor& stress) const {
    const double k = bulk_modulus(p);
    const double tr = stress.trace();
    return (stress - tr / 3.0 * Tensor::Identity()) / (2.0 * shear_to_bulk_ * k) +
           tr / (9.0 * k) * Tensor::Identity();
  }

  // Mean stress after a volumetric strain Δε_v from p0 (closed form, piecewise at the floor).
  // May return p < 0 (tension) when unloading below zero: the caller treats contact loss.
  double pressure_after(double p0, double strain_v) const {
    double p = p0, remaining = strain_v;
    if (p < p_floor_ || (p == p_floor_ && remaining < 0)) {  // linear branch
      const double to_floor = (p_floor_ - p) / k_floor_;     // strain needed to reach the floor
      if (remaining <= to_floor) return p + k_floor_ * remaining;
      remaining -= to_floor;
      p = p_floor_;
    }
    // power branch: u = p^{1-n} is linear in ε_v
    const double u0 = power(p, 1.0 - n_);
    const double u = u0 + power_coefficient_ * remaining;
    if (u >= u_floor_) return power(u, 1.0 / (1.0 - n_));
    const double strain_to_floor = (u_floor_ - u0) / power_coefficient_;  // < 0
    return p_floor_ + k_floor_ * (remaining - strain_to_floor);
  }

  // Exact update along the straight strain path 0 -> strain (the "finite" form):
  // σ + Δp I + 2 (G/K) K̄ dev(Δε) with K̄ = Δp/Δε_v.
  SymTensor finite_update(const SymTensor& stress, const SymTensor& strain) const {
    const double p0 = stress.trace() * (1.0 / 3.0);
    const double ev = strain.trace();
    const double p1 = pressure_after(p0, ev);
    // mean bulk modulus along the path, ∫K dt = Δp/Δε_v (t the path parameter)
    // (for |Δε_v| < 1e-9 the quotient loses digits; the midpoint modulus is then exact to
    // O(Δε_v²), far below round-off of the stress itself)
    const double k_mean = std::abs(ev) > 1e-9 ? (p1 - p0) / ev : bulk_modulus(0.5 * (p0 + p1));
    const double two_g = 2.0 * shear_to_bulk_ * k_mean;
    SymTensor out = stress + two_g * strain;
    return out.add_identity(p1 - p0 - two_g * (1.0 / 3.0) * ev);
  }
  Tensor finite_update(const Tensor& stress, const Tensor& strain) const {
    return finite_update(SymTensor::from(stress), SymTensor::from(strain)).matrix();
  }

 private:
  // x^e with the exponents of the default n = 0.5 (and n = 0) without a call to pow, which
  // otherwise dominates the cost of a plastic update
  static double power(double x, double e) {
    if (e == 0.5) return std::sqrt(x);
    if (e == 2.0) return x * x;
    if (e == 1.0) return x;
    if (e == 0.0) return 1.0;
    return std::pow(x, e);
  }

  double k_ref_, p_ref_, n_, p_floor_, shear_to_bulk_, k_floor_;
  double k_scale_;  // K_ref p_ref^-n
  double power_coefficient_, u_floor_;
};

}  // namespace granflow::model::force_chains
