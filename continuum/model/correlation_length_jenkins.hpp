// Correlation length of the velocity fluctuations in dense flows, Jenkins (2006, 2007; Granul.
// Matter 10, 47), in the form used by Berzi, di Prisco & Vescovi (2011) and Vescovi et al. (2013):
//   L / d = max{ 1, c [2 J / (15 (1 - ε²))]^{1/2} d γ̇ / T^{1/2} },
// so the collisional dissipation Γ = ρ_p f3 T^{3/2} / L is reduced when correlated motion of
// chains of grains (L > d) develops. c is `correlation_length_constant` in the case file.
// Uncertain points (docs/model/closures.md): Jenkins (2006) wrote (1-ε) where later papers write
// (1-ε²); some later papers add a factor G^{1/3}. Both would change only c at fixed ν.
#pragma once

#include <cmath>
#include <limits>

namespace granflow::model {

// a = c [2J/(15(1-ε²))]^{1/2} d |γ̇| (m/s): L/d = max(1, a / T^{1/2}).
inline double jenkins_correlation_speed(double constant, double J, double effective_restitution,
                                        double diameter, double shear_rate) {
  if (shear_rate == 0.0) return 0.0;  // also avoids ∞ · 0 when ε = 1
  const double inelasticity = 1.0 - effective_restitution * effective_restitution;
  return constant * std::sqrt(2.0 * J / (15.0 * inelasticity)) * diameter * std::fabs(shear_rate);
}

// L (m). At T = 0 with γ̇ ≠ 0 the length is unbounded: returns +infinity (the dissipation is
// then zero; use collisional_dissipation_at_shear_rate() for an expression finite at T = 0).
// Likewise +infinity for ε = 1 and γ̇ ≠ 0 (elastic: f3 = 0, so Γ = 0 whatever L).
inline double correlation_length_jenkins(double constant, double J, double effective_restitution,
                                         double diameter, double shear_rate, double T) {
  const double speed =
      jenkins_correlation_speed(constant, J, effective_restitution, diameter, shear_rate);
  const double sqrt_T = std::sqrt(T);
  if (speed <= sqrt_T) return diameter;
  if (sqrt_T == 0.0) return std::numeric_limits<double>::infinity();
  return diameter * speed / sqrt_T;
}

}  // namespace granflow::model
