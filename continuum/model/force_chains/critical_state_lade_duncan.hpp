// Critical state of the force-chain model (seed §3.1: "the critical state locus shape in the
// deviatoric plane is assumed to coincide with Lade-Duncan"), compression positive.
//
// Lade & Duncan (1975): I1³/I3 = k_LD at critical state. With I1 = 3p, I3 = p³ - p q²/3 +
// (2/27) q³ cos3θ this reads, for η = q/p,
//   h(η) = 1 - η²/3 + (2/27) cos3θ η³ - 27/k_LD = 0,
// and k_LD follows from the compression value M_c (cos3θ = 1). M(θ) is the smallest positive
// root (in (0, 3): q/p = 3 is σ3 = 0 in compression).
// Critical void ratio (Li & Wang 1998): e_cs(p) = e_Γ - λ_c (p/p_atm)^ξ_c; state parameter
// ψ = e - e_cs(p) (Been & Jefferies 1985), e clamped to [e_min, e_max].
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "continuum/model/force_chains/force_chain_parameters.hpp"
#include "continuum/model/force_chains/stress_invariants.hpp"

namespace granflow::model::force_chains {

class CriticalStateLadeDuncan {
 public:
  explicit CriticalStateLadeDuncan(const ForceChainParameters& p)
      : m_c_(p.M_c),
        k_ld_(27.0 / (1.0 - p.M_c * p.M_c / 3.0 + 2.0 / 27.0 * p.M_c * p.M_c * p.M_c)),
        e_gamma_(p.e_Gamma),
        xi_c_(p.xi_c),
        e_min_(p.e_min),
        e_max_(p.e_max),
        target_(27.0 / k_ld_),
        lambda_scaled_(p.lambda_c * std::pow(p.atmospheric_pressure, -p.xi_c)) {
    // the table of stress_ratio(): roots and their slopes times the interval width 2/kIntervals
    for (int i = 0; i <= kIntervals; ++i) {
      const double c = -1.0 + 2.0 * i / kIntervals;
      const double eta = stress_ratio_newton(c);
      root_[i] = eta;
      slope_[i] = -(2.0 / 27.0) * eta * eta * eta / (-2.0 * eta / 3.0 + 2.0 / 9.0 * c * eta * eta) *
                  (2.0 / kIntervals);
    }
  }

  double lade_duncan_constant() const { return k_ld_; }
  double compression_ratio() const { return m_c_; }

  // Critical stress ratio q/p at the Lode angle given by cos3theta. The root of h(η) is
  // tabulated over cos3θ in [-1, 1] (cubic Hermite on kIntervals intervals with the slopes
  // dη/dc = -(∂h/∂c)/(∂h/∂η) = -(2/27)η³ / (-2η/3 + (2/9) c η²); interpolation error of order
  // (2/kIntervals)⁴ max|d⁴η/dc⁴|/384), then one Newton step on h, which squares that error to
  // round-off. Where the step is not small (M_c near 3, where ∂h/∂η vanishes at the root) the
  // safeguarded Newton iteration from M_c decides, as before.
  double stress_ratio(double cos3theta) const {
    const double c = std::clamp(cos3theta, -1.0, 1.0);
    const double eta = tabulated_ratio(c);
    // (η²/3 and 27/k_LD as products: no division but the Newton step's)
    const double h = 1.0 - eta * eta * (1.0 / 3.0) + 2.0 / 27.0 * c * eta * eta * eta - target_;
    const double dh = -2.0 / 3.0 * eta + 2.0 / 9.0 * c * eta * eta;
    if (dh < 0.0) {
      const double next = eta - h / dh;
      if (std::abs(next - eta) <= 1e-7 * eta) return next;
    }
    return stress_ratio_newton(c);
  }

  // The cubic Hermite interpolant of the table at c in [-1, 1].
  double tabulated_ratio(double c) const {
    const double u = (c + 1.0) * (0.5 * kIntervals);
    const int i = std::min(static_cast<int>(u), kIntervals - 1);
    const double t = u - i, w = 1.0 - t;
    return (1.0 + 2.0 * t) * w * w * root_[i] + t * w * w * slope_[i] +
           t * t * (3.0 - 2.0 * t) * root_[i + 1] - t * t * w * slope_[i + 1];
  }

  // The safeguarded Newton iteration on h(η) from η = M_c (c in [-1, 1]).
  double stress_ratio_newton(double c) const {
    const double target = 27.0 / k_ld_;
    double lo = 0.0, hi = 3.0, eta = m_c_;
    for (int it = 0; it < 60; ++it) {
      const double h = 1.0 - eta * eta / 3.0 + 2.0 / 27.0 * c * eta * eta * eta - target;
      if (h == 0.0) return eta;
      if (h > 0)
        lo = eta;
      else
        hi = eta;
      const double dh = -2.0 * eta / 3.0 + 2.0 / 9.0 * c * eta * eta;
      double next = dh < 0 ? eta - h / dh : 0.5 * (lo + hi);
      if (!(next >= lo && next <= hi)) next = 0.5 * (lo + hi);  // safeguard: bisection
      if (std::abs(next - eta) <= 1e-15 * eta) return next;
      eta = next;
    }
    return eta;
  }

  // Lode-normalized stress ratio η̃ = M_c q/(p M(θ)): equals M_c on the critical state locus at
  // every Lode angle. Capped at 3 M_c (beyond the no-tension limit) so that it stays finite as
  // p -> 0.
  double normalized_stress_ratio(const Tensor& stress) const {
    const Tensor s = deviator(stress);
    return normalized_stress_ratio(mean_stress(stress), s, lode_cos3theta(s));
  }
  // The same from p, the deviator s and its cos 3θ (lode_cos3theta(s)) when the caller has them.
  double normalized_stress_ratio(double p, const Tensor& s, double cos3theta) const {
    return normalized_stress_ratio_q(p, std::sqrt(1.5 * double_contraction(s, s)), cos3theta);
  }
  // The same from p, q = sqrt(3/2 s:s) and cos 3θ.
  // With the table's Newton step η_1 = η_0 - h/h' accepted (as in stress_ratio), M_c q/(p η_1)
  // = M_c q h'/(p (η_0 h' - h)): one division for the step and the ratio.
  double normalized_stress_ratio_q(double p, double q, double cos3theta) const {
    const double cap = 3.0 * m_c_;
    if (!(q > 0.0)) return 0.0;
    if (!(p > 0.0)) return cap;
    const double c = std::clamp(cos3theta, -1.0, 1.0);
    const double eta = tabulated_ratio(c);
    const double h = 1.0 - eta * eta * (1.0 / 3.0) + 2.0 / 27.0 * c * eta * eta * eta - target_;
    const double dh = -2.0 / 3.0 * eta + 2.0 / 9.0 * c * eta * eta;
    // |h/h'| <= 1e-7 η, tested without the division (h' < 0)
    const double ratio = dh < 0.0 && std::abs(h) <= -1e-7 * eta * dh
                             ? m_c_ * q * dh / (p * (eta * dh - h))
                             : m_c_ * q / (p * stress_ratio_newton(c));
    return std::min(ratio, cap);
  }

  // e_cs = e_Γ - λ_c (p/p_atm)^ξ_c, as e_Γ - (λ_c p_atm^-ξ_c) p^ξ_c (no division per call)
  double critical_void_ratio(double p) const {
    return e_gamma_ - lambda_scaled_ * std::pow(std::max(p, 0.0), xi_c_);
  }
  double state_parameter(double void_ratio, double p) const {
    return std::clamp(void_ratio, e_min_, e_max_) - critical_void_ratio(p);
  }
  // ψ from (max(p, 0))^ξ_c known to the caller; ξ_c
  double state_parameter_from_power(double void_ratio, double p_power) const {
    return std::clamp(void_ratio, e_min_, e_max_) - (e_gamma_ - lambda_scaled_ * p_power);
  }
  double pressure_exponent() const { return xi_c_; }

 private:
  static constexpr int kIntervals = 128;
  double m_c_, k_ld_, e_gamma_, xi_c_, e_min_, e_max_;
  double target_;         // 27/k_LD
  double lambda_scaled_;  // λ_c p_atm^-ξ_c
  std::array<double, kIntervals + 1> root_{}, slope_{};
};

}  // namespace granflow::model::force_chains
