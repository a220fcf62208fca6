// Stress invariants in the soil-mechanics convention (compression positive,
// docs/model/multi_regime.md §1): p = tr(σ)/3, s = σ - p I, q = sqrt(3/2 s:s), Lode angle through
// cos 3θ = (3√3/2) J3 / J2^{3/2} with J2 = s:s/2 and J3 = det s, so that cos 3θ = +1 in triaxial
// compression (σ1 > σ2 = σ3) and -1 in triaxial extension.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace granflow::model::force_chains {

using Tensor = Eigen::Matrix3d;

inline double double_contraction(const Tensor& a, const Tensor& b) {
  return a.cwiseProduct(b).sum();
}
inline double mean_stress(const Tensor& stress) { return stress.trace() / 3.0; }
inline Tensor deviator(const Tensor& t) { return t - (t.trace() / 3.0) * Tensor::Identity(); }
inline double deviatoric_stress(const Tensor& stress) {
  const Tensor s = deviator(stress);
  return std::sqrt(1.5 * double_contraction(s, s));
}
// Equivalent deviatoric strain ε_q = sqrt(2/3 e:e), e = dev(ε) (work-conjugate of q).
inline double deviatoric_strain(const Tensor& strain) {
  const Tensor e = deviator(strain);
  return std::sqrt(2.0 / 3.0 * double_contraction(e, e));
}
// det t by cofactors of the first row (no Eigen/LU needed).
inline double determinant(const Tensor& t) {
  return t(0, 0) * (t(1, 1) * t(2, 2) - t(1, 2) * t(2, 1)) -
         t(0, 1) * (t(1, 0) * t(2, 2) - t(1, 2) * t(2, 0)) +
         t(0, 2) * (t(1, 0) * t(2, 1) - t(1, 1) * t(2, 0));
}
// cos 3θ of a deviator s; returns 1 (compression) when s vanishes, so that the callers get the
// compression branch at the isotropic axis, where every Lode-dependent quantity is irrelevant.
inline double lode_cos3theta(const Tensor& s) {
  const double j2 = 0.5 * double_contraction(s, s);
  if (!(j2 > 0.0)) return 1.0;
  const double j3 = determinant(s);
  const double c = 1.5 * std::sqrt(3.0) * j3 / (j2 * std::sqrt(j2));
  return std::clamp(c, -1.0, 1.0);
}

// Smallest principal stress from the invariants: σ_3 = p + (2/3) q cos(θ + 2π/3), θ =
// acos(cos3θ)/3 in [0, π/3] (no eigen-solver needed).
inline double minimum_principal_stress(const Tensor& stress) {
  const double p = mean_stress(stress);
  const Tensor s = deviator(stress);
  const double q = std::sqrt(1.5 * double_contraction(s, s));
  if (!(q > 0.0)) return p;
  const double theta = std::acos(lode_cos3theta(s)) / 3.0;
  return p + 2.0 / 3.0 * q * std::cos(theta + 2.0943951023931955);
}

// σ positive semi-definite (all principal stresses >= 0, compression positive), tested through
// the principal minors (Sylvester's criterion for semi-definiteness: every principal minor
// >= 0), each with a relative round-off tolerance; no eigen-solver, no transcendental call.
inline bool is_compressive(const Tensor& s, double tolerance) {
  const double scale = s.cwiseAbs().maxCoeff();
  const double t1 = -tolerance * scale, t2 = t1 * scale, t3 = t2 * scale;
  if (s(0, 0) < t1 || s(1, 1) < t1 || s(2, 2) < t1) return false;
  const double m01 = s(0, 0) * s(1, 1) - s(0, 1) * s(1, 0);
  const double m02 = s(0, 0) * s(2, 2) - s(0, 2) * s(2, 0);
  const double m12 = s(1, 1) * s(2, 2) - s(1, 2) * s(2, 1);
  if (m01 < t2 || m02 < t2 || m12 < t2) return false;
  const double det = s(0, 0) * m12 - s(0, 1) * (s(1, 0) * s(2, 2) - s(1, 2) * s(2, 0)) +
                     s(0, 2) * (s(1, 0) * s(2, 1) - s(1, 1) * s(2, 0));
  return det >= t3;
}

}  // namespace granflow::model::force_chains
