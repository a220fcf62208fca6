// Steady-state statistics of a simulation time series: where the initial transient ends, and the
// mean with an error bar that accounts for autocorrelation.
//   - MSER-m truncation (White 1997; White, Cobb & Spratt 2000): average the series in batches of
//     m (MSER-5: m = 5), and choose the number d of leading batches to drop that minimises
//       MSER(d) = sum_{j>d} (Z_j - Zbar_d)^2 / (k - d)^2,   d <= k/2,
//     i.e. the squared standard error of the mean of what is kept (bias vs variance).
//   - Non-overlapping batch means (e.g. Law & Kelton 2000, section 9.5.3): the kept series is cut
//     into B batches; the standard error of the mean is s_B / sqrt(B) and the 95 % half-width
//     t_{0.975, B-1} s_B / sqrt(B).
//   - Integrated autocorrelation time tau_int = 1 + 2 sum_t rho(t) with Sokal's automatic window
//     (the sum stops at the first W >= c tau_int(W), c = 5; Sokal 1997), so that
//     Var(mean) ~= tau_int Var(x) / n.
//   - Correlated standard error (correlated_mean): batch means whose batch size follows tau_int,
//     b = max(n / 20, 5 tau_int) (batch means underestimate Var(mean) by ~tau_int / (2 b) for an
//     AR(1) series, so b >= 5 tau_int keeps that below 10 %; Flegal & Jones 2010 on batch sizes
//     that grow with the correlation), at least 4 batches, and the reported standard error is the
//     larger of that and the autocorrelation estimate sqrt(tau_int Var(x) / n). Only the
//     sampling noise of one run is in it: neither the bias of a transient left in the window nor
//     the sample-to-sample (seed) scatter.
//   - Drift test (drift_test): the window is cut in halves; z = (m_2 - m_1) / sqrt(se_1^2 + se_2^2)
//     with correlated_mean errors of the halves of the residuals about the window's least-squares
//     line (a trend would inflate the halves' own errors and hide itself). A stationary series
//     gives |z| > 3 with probability ~0.3 % (normal) to ~1 % (Student t of the few batches per
//     half); a linear trend whose change over the window is 12 standard errors of the mean of the
//     whole window gives E[z] = 3 (halves differ by half the change; their combined error is twice
//     the window's), 24 gives |z| > 3 in > 99 % of cases.
#pragma once

#include <cstddef>
#include <span>

namespace granflow::statistics {

// Index of the first sample of the steady part (a multiple of batch_size).
std::size_t mser_truncation(std::span<const double> series, std::size_t batch_size = 5);

struct MeanEstimate {
  double mean = 0.0;
  double standard_error = 0.0;  // batch-means standard error of the mean
  double ci95 = 0.0;            // 95 % half-width, Student t with batches-1 degrees of freedom
  std::size_t batches = 0;
  std::size_t batch_size = 0;
};

// Batch means over the whole span (the first n mod B samples are dropped so batches are equal).
// Fewer than 2 * batches samples: batches shrink to n/2 (at least 2 needed, else SE = NaN).
MeanEstimate batch_means(std::span<const double> series, std::size_t batches = 20);

// tau_int in samples (1 for uncorrelated data).
double integrated_autocorrelation_time(std::span<const double> series, double window_factor = 5.0);

// Two-sided 95 % quantile t_{0.975, dof} of Student's t (Cornish-Fisher expansion, Abramowitz &
// Stegun 26.7.5; better than 1e-3 relative for dof >= 5).
double student_t_975(std::size_t dof);

// Mean of every sample with a standard error that accounts for correlation (see the header):
// batches of max(n / 20, 5 tau_int) samples (at least 4 batches), standard error the larger of the
// batch-means and the tau_int estimates; ci95 from Student t with batches - 1 degrees of freedom.
MeanEstimate correlated_mean(std::span<const double> series);

struct DriftTest {
  double first_half = 0.0, second_half = 0.0;  // means of the two halves
  double z = 0.0;  // (second - first) / combined standard error; NaN if < 16 samples
};
DriftTest drift_test(std::span<const double> series);

struct SteadyEstimate {
  std::size_t start = 0;  // first steady sample (MSER)
  MeanEstimate mean;      // batch means of series[start:]
  double tau_int = 1.0;   // integrated autocorrelation time of series[start:], samples
};

// MSER start, then the mean of what is kept: batches == 0 (default) correlated_mean, else
// batch_means with that many batches.
SteadyEstimate steady_state(std::span<const double> series, std::size_t mser_batch = 5,
                            std::size_t batches = 0);

}  // namespace granflow::statistics
