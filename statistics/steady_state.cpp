#include "statistics/steady_state.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

namespace granflow::statistics {

namespace {
double mean_of(std::span<const double> x) {
  return std::accumulate(x.begin(), x.end(), 0.0) / double(x.size());
}
}  // namespace

std::size_t mser_truncation(std::span<const double> series, std::size_t batch_size) {
  batch_size = std::max<std::size_t>(batch_size, 1);
  const std::size_t k = series.size() / batch_size;
  if (k < 4) return 0;
  std::vector<double> z(k);
  for (std::size_t j = 0; j < k; ++j) z[j] = mean_of(series.subspan(j * batch_size, batch_size));
  // Suffix sums give MSER(d) for every d in O(k): sum (z - zbar)^2 = S2 - S1^2 / m.
  double s1 = 0.0, s2 = 0.0;
  std::vector<double> mser(k, std::numeric_limits<double>::infinity());
  for (std::size_t j = k; j-- > 0;) {
    s1 += z[j];
    s2 += z[j] * z[j];
    const double m = double(k - j);
    mser[j] = std::max(0.0, s2 - s1 * s1 / m) / (m * m);
  }
  std::size_t best = 0;
  for (std::size_t d = 1; d <= k / 2; ++d)
    if (mser[d] < mser[best]) best = d;
  return best * batch_size;
}

double student_t_975(std::size_t dof) {
  if (dof == 0) return std::numeric_limits<double>::quiet_NaN();
  const double z = 1.959963984540054;  // standard normal 97.5 % quantile
  const double z2 = z * z, v = double(dof);
  const double g1 = (z2 + 1.0) * z / 4.0;
  const double g2 = ((5.0 * z2 + 16.0) * z2 + 3.0) * z / 96.0;
  const double g3 = (((3.0 * z2 + 19.0) * z2 + 17.0) * z2 - 15.0) * z / 384.0;
  const double g4 =
      ((((79.0 * z2 + 776.0) * z2 + 1482.0) * z2 - 1920.0) * z2 - 945.0) * z / 92160.0;
  return z + g1 / v + g2 / (v * v) + g3 / (v * v * v) + g4 / (v * v * v * v);
}

MeanEstimate batch_means(std::span<const double> series, std::size_t batches) {
  MeanEstimate e;
  const std::size_t n = series.size();
  e.batches = std::min(batches, n / 2);
  if (e.batches < 2) {
    e.mean = n ? mean_of(series) : std::numeric_limits<double>::quiet_NaN();
    e.standard_error = e.ci95 = std::numeric_limits<double>::quiet_NaN();
    e.batch_size = n;
    e.batches = n ? 1 : 0;
    return e;
  }
  e.batch_size = n / e.batches;
  const auto kept = series.subspan(n - e.batches * e.batch_size);  // drop the oldest remainder
  e.mean = mean_of(kept);
  double ss = 0.0;
  for (std::size_t b = 0; b < e.batches; ++b) {
    const double d = mean_of(kept.subspan(b * e.batch_size, e.batch_size)) - e.mean;
    ss += d * d;
  }
  const double batch_variance = ss / double(e.batches - 1);
  e.standard_error = std::sqrt(batch_variance / double(e.batches));
  e.ci95 = student_t_975(e.batches - 1) * e.standard_error;
  return e;
}

double integrated_autocorrelation_time(std::span<const double> series, double window_factor) {
  const std::size_t n = series.size();
  if (n < 4) return std::numeric_limits<double>::quiet_NaN();
  const double m = mean_of(series);
  double c0 = 0.0;
  for (double x : series) c0 += (x - m) * (x - m);
  c0 /= double(n);
  if (c0 <= 0.0) return 1.0;
  double tau = 1.0;
  for (std::size_t t = 1; t < n / 2; ++t) {
    double c = 0.0;
    for (std::size_t i = 0; i + t < n; ++i) c += (series[i] - m) * (series[i + t] - m);
    tau += 2.0 * c / double(n) / c0;
    if (double(t) >= window_factor * tau) break;  // Sokal's automatic window
  }
  return std::max(tau, 1.0 / double(n));
}

MeanEstimate correlated_mean(std::span<const double> series) {
  const std::size_t n = series.size();
  const double tau = integrated_autocorrelation_time(series);
  if (n < 8 || !std::isfinite(tau)) return batch_means(series, 20);
  // b = max(n / 20, ceil(5 tau_int)), B = n / b within [4, 20]
  const auto wanted = std::size_t(std::ceil(5.0 * tau));
  const std::size_t batches = std::clamp<std::size_t>(n / std::max<std::size_t>(wanted, 1), 4, 20);
  MeanEstimate e = batch_means(series, batches);
  // The mean of every sample (batch_means drops the n mod B oldest): linear in the series, so
  // the means of parts that add up per sample add up (the immersed τ split).
  e.mean = mean_of(series);
  double var = 0.0;
  for (double x : series) var += (x - e.mean) * (x - e.mean);
  var /= double(n - 1);
  const double tau_se = std::sqrt(tau * var / double(n));
  if (!(e.standard_error >= tau_se)) {
    e.standard_error = tau_se;
    e.ci95 = student_t_975(e.batches - 1) * tau_se;
  }
  return e;
}

DriftTest drift_test(std::span<const double> series) {
  DriftTest d;
  const std::size_t half = series.size() / 2;
  if (half < 8) {
    d.z = std::numeric_limits<double>::quiet_NaN();
    return d;
  }
  // Errors of the halves from the residuals about the least-squares line x = c0 + c1 t: a trend
  // would otherwise inflate the halves' own errors (batch means spread by it, tau_int lengthened)
  // and hide itself; without a trend the residuals are the fluctuations.
  const std::size_t n = series.size();
  const double tm = 0.5 * double(n - 1), xm = mean_of(series);
  double stt = 0.0, stx = 0.0;
  for (std::size_t t = 0; t < n; ++t) {
    stt += (double(t) - tm) * (double(t) - tm);
    stx += (double(t) - tm) * (series[t] - xm);
  }
  const double slope = stx / stt;
  std::vector<double> residual(n);
  for (std::size_t t = 0; t < n; ++t) residual[t] = series[t] - xm - slope * (double(t) - tm);
  // the middle sample of an odd count is left out, so the halves have equal length
  d.first_half = mean_of(series.first(half));
  d.second_half = mean_of(series.last(half));
  const double se =
      std::hypot(correlated_mean(std::span<const double>(residual).first(half)).standard_error,
                 correlated_mean(std::span<const double>(residual).last(half)).standard_error);
  const MeanEstimate a{d.first_half}, b{d.second_half};
  d.z = se > 0.0           ? (b.mean - a.mean) / se
        : b.mean == a.mean ? 0.0
                           : std::copysign(std::numeric_limits<double>::max(),
                                           b.mean - a.mean);  // finite: summary.json
  return d;
}

SteadyEstimate steady_state(std::span<const double> series, std::size_t mser_batch,
                            std::size_t batches) {
  SteadyEstimate s;
  s.start = mser_truncation(series, mser_batch);
  const auto steady = series.subspan(s.start);
  s.mean = batches == 0 ? correlated_mean(steady) : batch_means(steady, batches);
  s.tau_int = integrated_autocorrelation_time(steady);
  return s;
}

}  // namespace granflow::statistics
