#include "dem_coupling/kind/mixed_number_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace granflow::dem {

double boyer_friction(double viscous_number) {
  // Boyer, Guazzelli & Pouliquen 2011 (docs/dem_dataset.md).
  constexpr double mu_1 = 0.32, mu_2 = 0.7, j_0 = 0.005, nu_m = 0.585;
  const double j = viscous_number;
  return mu_1 + (mu_2 - mu_1) / (1.0 + j_0 / j) + j + 2.5 * nu_m * std::sqrt(j);
}

MixedNumberFit fit_trulsson_alpha(const std::vector<double>& viscous_number,
                                  const std::vector<double>& inertial_number,
                                  const std::vector<double>& friction,
                                  const std::vector<double>& friction_err) {
  struct Point {
    double j, i2, mu, weight;
  };
  std::vector<Point> points;
  const std::size_t n = std::min(
      {viscous_number.size(), inertial_number.size(), friction.size(), friction_err.size()});
  for (std::size_t k = 0; k < n; ++k) {
    const double j = viscous_number[k], i = inertial_number[k], mu = friction[k];
    if (!(std::isfinite(j) && std::isfinite(i) && std::isfinite(mu) && j > 0)) continue;
    const double s = std::isfinite(friction_err[k]) ? std::max(friction_err[k], 1e-3) : 1e-3;
    points.push_back({j, i * i, mu, 1.0 / (s * s)});
  }
  MixedNumberFit fit;
  fit.points = static_cast<int>(points.size());
  if (points.size() < 2) {
    fit.alpha = std::numeric_limits<double>::quiet_NaN();
    return fit;
  }
  auto objective = [&](double log_alpha) {
    const double alpha = std::pow(10.0, log_alpha);
    double sum = 0;
    for (const Point& p : points) {
      const double r = p.mu - boyer_friction(p.j + alpha * p.i2);
      sum += p.weight * r * r;
    }
    return sum;
  };
  constexpr double lo = -3.0, hi = 2.0;
  constexpr int scan = 500;
  int best = 0;
  double best_value = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= scan; ++k) {
    const double v = objective(lo + (hi - lo) * k / scan);
    if (v < best_value) best_value = v, best = k;
  }
  // Golden section in the bracketing cells of the scan minimum.
  double a = lo + (hi - lo) * std::max(best - 1, 0) / scan;
  double b = lo + (hi - lo) * std::min(best + 1, scan) / scan;
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double c = b - g * (b - a), d = a + g * (b - a);
  for (int it = 0; it < 80; ++it) {
    if (objective(c) < objective(d))
      b = d;
    else
      a = c;
    c = b - g * (b - a);
    d = a + g * (b - a);
  }
  const double log_alpha = 0.5 * (a + b);
  fit.alpha = std::pow(10.0, log_alpha);
  double sq = 0;
  for (const Point& p : points) {
    const double r = p.mu - boyer_friction(p.j + fit.alpha * p.i2);
    sq += r * r;
  }
  fit.rms = std::sqrt(sq / double(points.size()));
  fit.chi2_per_dof = objective(log_alpha) / double(points.size() - 1);
  return fit;
}

}  // namespace granflow::dem
