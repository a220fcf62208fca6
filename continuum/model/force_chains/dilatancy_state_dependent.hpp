// Plastic flow of the force-chain model (seed §3.1): "dilatancy is assumed not to depend on the
// Lode angle and to be governed by a function depending on both void ratio and stress level,
// nullifying when critical state locus is reached, whereas in the deviatoric plane the flow rule
// is associated". Compression positive.
//
// Dilatancy D = dε^p_v / dε^p_q (ε_q = sqrt(2/3 e:e)):
//   D = d_0 (M_d - η̃)/η̃,   M_d = M_c exp(n_d ψ),   ψ = e - e_cs(p)
// (the state-dependent dilatancy of Li & Dafalias 2000, with the extra 1/η̃ of Rowe/Nova-type
// rules so that the flow is purely volumetric on the isotropic axis). η̃ is the Lode-normalized
// stress ratio of CriticalStateLadeDuncan, so D is the same at every Lode angle for the same
// (η̃, e, p) and vanishes on the critical state locus (η̃ = M_c, ψ = 0) at every Lode angle.
// Direction: m ∝ η̃ sqrt(3/2) n̂ + d_0 (M_d - η̃) I/3, n̂ = dev(∂f/∂σ)/|dev(∂f/∂σ)|, |m| = 1.
#pragma once

#include <algorithm>
#include <cmath>

#include "continuum/model/force_chains/critical_state_lade_duncan.hpp"
#include "continuum/model/force_chains/force_chain_parameters.hpp"
#include "continuum/model/force_chains/stress_invariants.hpp"

namespace granflow::model::force_chains {

class DilatancyStateDependent {
 public:
  explicit DilatancyStateDependent(const ForceChainParameters& p)
      : m_c_(p.M_c), d_0_(p.d_0), n_d_(p.n_d) {}

  // Dilatancy stress ratio M_d(ψ).
  double dilatancy_ratio(double state_parameter) const {
    return m_c_ * std::exp(ratio_exponent(state_parameter));
  }
  // x = n_d ψ clamped to ±20: M_d = M_c exp(x)
  double ratio_exponent(double state_parameter) const {
    return std::clamp(n_d_ * state_parameter, -20.0, 20.0);
  }
  // D(η̃, ψ); +inf-like on the isotropic axis (returns a large number there).
  double dilatancy(double normalized_ratio, double state_parameter) const {
    const double a_v = d_0_ * (dilatancy_ratio(state_parameter) - normalized_ratio);
    return normalized_ratio > 1e-12 ? a_v / normalized_ratio : 1e12 * a_v;
  }

  // a_v = d_0 (M_d(ψ) - η̃): D = a_v/η̃, and the isotropic part of m before normalisation is a_v I/3.
  double volumetric_coefficient(double normalized_ratio, double state_parameter) const {
    return volumetric_coefficient_at(dilatancy_ratio(state_parameter), normalized_ratio);
  }
  // The same with M_d = dilatancy_ratio(ψ) known to the caller.
  double volumetric_coefficient_at(double dilatancy_ratio, double normalized_ratio) const {
    return d_0_ * (dilatancy_ratio - normalized_ratio);
  }

  // Unit flow direction m given the yield gradient and the state.
  Tensor direction(const Tensor& yield_gradient, double normalized_ratio,
                   double state_parameter) const {
    Tensor n_dev = deviator(yield_gradient);
    const double norm_dev = n_dev.norm();
    const double a_v = d_0_ * (dilatancy_ratio(state_parameter) - normalized_ratio);
    Tensor m = (a_v / 3.0) * Tensor::Identity();
    if (norm_dev > 0.0) m += (normalized_ratio * std::sqrt(1.5) / norm_dev) * n_dev;
    const double norm = m.norm();
    return norm > 0.0 ? Tensor(m / norm) : Tensor(Tensor::Identity() / std::sqrt(3.0));
  }

 private:
  double m_c_, d_0_, n_d_;
};

}  // namespace granflow::model::force_chains
