// One-dimensional shape functions on a uniform grid of spacing h, as functions of the distance
// d = x_p - x_node. Both families are tensor-multiplied into 2D functions by CartesianGrid.
#pragma once

#include <cmath>

namespace granflow::mpm {

// Linear hat: N = 1 - |d|/h for |d| < h (the 1D factor of the bilinear Q4 function).
struct HatValue {
  double N, dN;
};
inline HatValue linear_hat(double d, double h) {
  const double a = std::fabs(d);
  if (a >= h) return {0.0, 0.0};
  return {1.0 - a / h, (d > 0.0 ? -1.0 : 1.0) / h};
}

// Uniform GIMP (Bardenhagen & Kober 2004, CMES 5, 477; also Steffen, Kirby & Berzins 2008,
// Eq. 16) for a particle of half-length l <= h/2:
//   |d| < l          : N = 1 - (d² + l²)/(2 h l),      dN/dx = -d/(h l)
//   l <= |d| < h - l : N = 1 - |d|/h,                  dN/dx = -sign(d)/h
//   h - l <= |d| < h + l : N = (h + l - |d|)²/(4 h l), dN/dx = -sign(d)(h + l - |d|)/(2 h l)
inline HatValue gimp(double d, double h, double l) {
  const double a = std::fabs(d);
  const double s = d > 0.0 ? 1.0 : -1.0;
  if (a < l) return {1.0 - (d * d + l * l) / (2.0 * h * l), -d / (h * l)};
  if (a < h - l) return {1.0 - a / h, -s / h};
  if (a < h + l) {
    const double b = h + l - a;
    return {b * b / (4.0 * h * l), -s * b / (2.0 * h * l)};
  }
  return {0.0, 0.0};
}

}  // namespace granflow::mpm
