#include "dem_coupling/kind/rate_step_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace granflow::dem {

RateStepMetrics rate_step_metrics(std::span<const double> strain, std::span<const double> tau,
                                  std::span<const double> sigma_yy,
                                  std::span<const double> solid_fraction,
                                  std::span<const double> temperature, double step_strain,
                                  double residual_fraction) {
  RateStepMetrics m;
  const std::size_t n = std::min(
      {strain.size(), tau.size(), sigma_yy.size(), solid_fraction.size(), temperature.size()});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (n == 0) return {nan, nan, nan, nan, nan, nan, nan, -1, nan};
  const auto mu = [&](std::size_t i) { return sigma_yy[i] != 0.0 ? tau[i] / sigma_yy[i] : nan; };
  // Means over the samples with γ in [from, to]; NaN when none.
  const auto window = [&](double from, double to, double& mu_mean, double& phi_mean,
                          double& T_mean) {
    double s_mu = 0, s_phi = 0, s_T = 0;
    std::size_t k = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (strain[i] >= from && strain[i] <= to)
        s_mu += mu(i), s_phi += solid_fraction[i], s_T += temperature[i], ++k;
    mu_mean = k ? s_mu / double(k) : nan;
    phi_mean = k ? s_phi / double(k) : nan;
    T_mean = k ? s_T / double(k) : nan;
  };
  const double end = strain[n - 1];
  window((1.0 - residual_fraction) * step_strain, step_strain, m.mu_before, m.phi_before,
         m.T_before);
  window(step_strain + (1.0 - residual_fraction) * (end - step_strain), end, m.mu_after,
         m.phi_after, m.T_after);
  m.dilation = m.phi_after - m.phi_before;
  m.peak_mu = nan;
  const double half = m.phi_before + 0.5 * m.dilation;
  bool crossed = !(m.dilation != 0.0);  // no change (or NaN): no dilation strain
  for (std::size_t i = 0; i < n; ++i) {
    if (strain[i] <= step_strain) continue;
    if (!(mu(i) <= m.peak_mu)) m.peak_mu = mu(i);
    if (crossed) continue;
    // first sample past half of the change, in the direction of the change
    if ((solid_fraction[i] - half) * m.dilation >= 0.0) {
      const bool first = i == 0 || strain[i - 1] < step_strain;
      const double g0 = first ? step_strain : strain[i - 1];
      const double f0 = first ? m.phi_before : solid_fraction[i - 1];
      const double w = solid_fraction[i] != f0 ? (half - f0) / (solid_fraction[i] - f0) : 1.0;
      m.dilation_strain = g0 + std::clamp(w, 0.0, 1.0) * (strain[i] - g0) - step_strain;
      crossed = true;
    }
  }
  return m;
}

}  // namespace granflow::dem
