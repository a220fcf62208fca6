#include "continuum/mpm/analytic.hpp"

#include <cmath>
#include <numbers>

namespace granflow::mpm::analytic {

namespace {
// Enough terms for T_v >= 1e-4 to round-off: exp(-M_k² T_v) with M_k ~ 1.57 (2k+1) and k = 2000.
constexpr int series_terms = 2000;
inline double Mk(int k) { return 0.5 * std::numbers::pi * (2 * k + 1); }
}  // namespace

double consolidation_coefficient(double k, double gamma_w, double M, double n, double K) {
  return k / (gamma_w * (1.0 / M + n / K));
}

double undrained_pressure(double q, double M, double n, double K) { return q / (1.0 + n * M / K); }

double terzaghi_pressure(double d, double t, double H, double cv, double p0) {
  const double Tv = cv * t / (H * H);
  double sum = 0;
  for (int k = 0; k < series_terms; ++k) {
    const double M = Mk(k), decay = std::exp(-M * M * Tv);
    if (decay < 1e-18 && k > 0) break;
    sum += 2.0 / M * std::sin(M * d / H) * decay;
  }
  return p0 * sum;
}

double terzaghi_displacement(double d, double t, double H, double cv, double p0, double M_oed) {
  const double Tv = cv * t / (H * H);
  double sum = 0;
  for (int k = 0; k < series_terms; ++k) {
    const double M = Mk(k), decay = std::exp(-M * M * Tv);
    if (decay < 1e-18 && k > 0) break;
    sum += 2.0 * H / (M * M) * std::cos(M * d / H) * decay;
  }
  return p0 * ((H - d) - sum) / M_oed;
}

double terzaghi_degree(double t, double H, double cv) {
  const double Tv = cv * t / (H * H);
  double sum = 0;
  for (int k = 0; k < series_terms; ++k) {
    const double M = Mk(k), decay = std::exp(-M * M * Tv);
    if (decay < 1e-18 && k > 0) break;
    sum += 2.0 / (M * M) * decay;
  }
  return 1.0 - sum;
}

double couette_velocity(double r, double r1, double r2, double v) {
  const double A = v * r2 / (r2 * r2 - r1 * r1), B = -A * r1 * r1;
  return A * r + B / r;
}

}  // namespace granflow::mpm::analytic
