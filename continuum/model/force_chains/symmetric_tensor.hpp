// Symmetric second-order tensor stored as its 6 independent components (Voigt order xx, yy, zz,
// yz, zx, xy; the off-diagonal values themselves, no √2 or 2 factors). The force-chain plastic
// update works on these: σ, χ, ε and every flow tensor of the model are symmetric, so a sum or a
// scaling costs 6 operations instead of 9, a double contraction 6 products instead of 9,
//   a:b = a_xx b_xx + a_yy b_yy + a_zz b_zz + 2 (a_yz b_yz + a_zx b_zx + a_xy b_xy),
// and the square a·a (symmetric) 18 products instead of the 27 of a 3 × 3 matrix product.
// Value type; conversion from a 3 × 3 matrix takes its symmetric part.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace granflow::model::force_chains {

struct SymTensor {
  enum : int { XX = 0, YY = 1, ZZ = 2, YZ = 3, ZX = 4, XY = 5 };
  double c[6];

  static SymTensor zero() { return {{0.0, 0.0, 0.0, 0.0, 0.0, 0.0}}; }
  static SymTensor identity(double d) { return {{d, d, d, 0.0, 0.0, 0.0}}; }
  // The symmetric part (a + aᵀ)/2 of a 3 × 3 matrix (exact for a symmetric one).
  static SymTensor from(const Eigen::Matrix3d& a) {
    return {{a(0, 0), a(1, 1), a(2, 2), 0.5 * (a(1, 2) + a(2, 1)), 0.5 * (a(2, 0) + a(0, 2)),
             0.5 * (a(0, 1) + a(1, 0))}};
  }
  Eigen::Matrix3d matrix() const {
    Eigen::Matrix3d a;
    a << c[XX], c[XY], c[ZX], c[XY], c[YY], c[YZ], c[ZX], c[YZ], c[ZZ];
    return a;
  }

  double trace() const { return c[XX] + c[YY] + c[ZZ]; }
  bool finite() const { return std::isfinite(c[0] + c[1] + c[2] + c[3] + c[4] + c[5]); }
  SymTensor& operator+=(const SymTensor& b) {
    for (int i = 0; i < 6; ++i) c[i] += b.c[i];
    return *this;
  }
  SymTensor& operator-=(const SymTensor& b) {
    for (int i = 0; i < 6; ++i) c[i] -= b.c[i];
    return *this;
  }
  SymTensor& operator*=(double s) {
    for (int i = 0; i < 6; ++i) c[i] *= s;
    return *this;
  }
  // a + d I
  SymTensor& add_identity(double d) {
    c[XX] += d;
    c[YY] += d;
    c[ZZ] += d;
    return *this;
  }
};

inline SymTensor operator+(SymTensor a, const SymTensor& b) { return a += b; }
inline SymTensor operator-(SymTensor a, const SymTensor& b) { return a -= b; }
inline SymTensor operator*(double s, SymTensor a) { return a *= s; }
// a s + b t (one pass)
inline SymTensor combine(double s, const SymTensor& a, double t, const SymTensor& b) {
  SymTensor out;
  for (int i = 0; i < 6; ++i) out.c[i] = s * a.c[i] + t * b.c[i];
  return out;
}

inline double double_contraction(const SymTensor& a, const SymTensor& b) {
  return a.c[0] * b.c[0] + a.c[1] * b.c[1] + a.c[2] * b.c[2] +
         2.0 * (a.c[3] * b.c[3] + a.c[4] * b.c[4] + a.c[5] * b.c[5]);
}
inline double norm(const SymTensor& a) { return std::sqrt(double_contraction(a, a)); }
inline SymTensor deviator(SymTensor a) { return a.add_identity(-a.trace() * (1.0 / 3.0)); }

// a·a: (a·a)_ij = a_ik a_kj, symmetric for a symmetric a.
inline SymTensor square(const SymTensor& a) {
  const double xx = a.c[0], yy = a.c[1], zz = a.c[2], yz = a.c[3], zx = a.c[4], xy = a.c[5];
  return {{xx * xx + xy * xy + zx * zx, xy * xy + yy * yy + yz * yz, zx * zx + yz * yz + zz * zz,
           xy * zx + yy * yz + yz * zz, xx * zx + xy * yz + zx * zz, xx * xy + xy * yy + zx * yz}};
}

// det a by cofactors of the first row.
inline double determinant(const SymTensor& a) {
  const double xx = a.c[0], yy = a.c[1], zz = a.c[2], yz = a.c[3], zx = a.c[4], xy = a.c[5];
  return xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * zx) + zx * (xy * yz - yy * zx);
}

// a positive semi-definite within a relative round-off tolerance: every principal minor >= 0
// (Sylvester's criterion for semi-definiteness), as is_compressive(Tensor) in
// stress_invariants.hpp.
inline bool is_compressive(const SymTensor& a, double tolerance) {
  const double xx = a.c[0], yy = a.c[1], zz = a.c[2], yz = a.c[3], zx = a.c[4], xy = a.c[5];
  const double scale = std::max(
      {std::abs(xx), std::abs(yy), std::abs(zz), std::abs(yz), std::abs(zx), std::abs(xy)});
  const double t1 = -tolerance * scale, t2 = t1 * scale, t3 = t2 * scale;
  if (xx < t1 || yy < t1 || zz < t1) return false;
  const double m01 = xx * yy - xy * xy, m02 = xx * zz - zx * zx, m12 = yy * zz - yz * yz;
  if (m01 < t2 || m02 < t2 || m12 < t2) return false;
  return xx * m12 - xy * (xy * zz - yz * zx) + zx * (xy * yz - yy * zx) >= t3;
}

}  // namespace granflow::model::force_chains
