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
#pragma once

#include <cstddef>
#include <span>

namespace granflow::analysis {

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

struct SteadyEstimate {
  std::size_t start = 0;  // first steady sample (MSER)
  MeanEstimate mean;      // batch means of series[start:]
  double tau_int = 1.0;   // integrated autocorrelation time of series[start:], samples
};

SteadyEstimate steady_state(std::span<const double> series, std::size_t mser_batch = 5,
                            std::size_t batches = 20);

}  // namespace granflow::analysis
