#include "continuum/mpm/nonlocal_average.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace granflow::mpm {

NonlocalAverage::NonlocalAverage(double length, double cutoff, double skin)
    : length_(length), cutoff_(cutoff), skin_(skin) {
  if (!(length > 0) || !(cutoff > 0) || !(skin >= 0))
    throw std::invalid_argument("nonlocal average: need length > 0, cutoff > 0, skin >= 0");
}

bool NonlocalAverage::update(const double* x, const double* y, const double* volume, std::size_t n,
                             int threads) {
  bool stale = builds_ == 0 || x_built_.size() != n;
  if (!stale) {
    const double s2 = skin_ * length_ * skin_ * length_;
    for (std::size_t i = 0; i < n && !stale; ++i) {
      const double dx = x[i] - x_built_[i], dy = y[i] - y_built_[i];
      stale = dx * dx + dy * dy > s2;
    }
  }
  if (stale) build(x, y, volume, n, threads);
  return stale;
}

void NonlocalAverage::build(const double* x, const double* y, const double* volume, std::size_t n,
                            int threads) {
  if (n > std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument("nonlocal average: too many points");
  ++builds_;
  x_built_.assign(x, x + n);
  y_built_.assign(y, y + n);
  volume_built_.assign(volume, volume + n);
  start_.assign(n + 1, 0);
  neighbour_.clear();
  kernel_.clear();
  if (n == 0) return;
  // Buckets of side R over the bounding box; the neighbours of i lie in its 3 × 3 buckets.
  const double R = cutoff_ * length_, R2 = R * R, inv_l2 = 1.0 / (length_ * length_);
  const auto [xmin, xmax] = std::minmax_element(x, x + n);
  const auto [ymin, ymax] = std::minmax_element(y, y + n);
  const double x0 = *xmin, y0 = *ymin;
  const long nbx = static_cast<long>((*xmax - x0) / R) + 1;
  const long nby = static_cast<long>((*ymax - y0) / R) + 1;
  std::vector<long> bucket_of(n);
  std::vector<std::size_t> bucket_start(static_cast<std::size_t>(nbx * nby) + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const long bx = std::min(static_cast<long>((x[i] - x0) / R), nbx - 1);
    const long by = std::min(static_cast<long>((y[i] - y0) / R), nby - 1);
    bucket_of[i] = by * nbx + bx;
    ++bucket_start[static_cast<std::size_t>(bucket_of[i]) + 1];
  }
  for (std::size_t b = 1; b < bucket_start.size(); ++b) bucket_start[b] += bucket_start[b - 1];
  std::vector<std::uint32_t> members(n);
  {
    std::vector<std::size_t> fill(bucket_start.begin(), bucket_start.end() - 1);
    for (std::size_t i = 0; i < n; ++i)  // counting sort: ascending i inside every bucket
      members[fill[static_cast<std::size_t>(bucket_of[i])]++] = static_cast<std::uint32_t>(i);
  }
  // Two passes over the same loop: count, then fill (each point writes its own slots).
  auto visit = [&](std::size_t i, auto&& emit) {
    const long bx = bucket_of[i] % nbx, by = bucket_of[i] / nbx;
    for (long cy = std::max(by - 1, 0L); cy <= std::min(by + 1, nby - 1); ++cy)
      for (long cx = std::max(bx - 1, 0L); cx <= std::min(bx + 1, nbx - 1); ++cx) {
        const std::size_t b = static_cast<std::size_t>(cy * nbx + cx);
        for (std::size_t m = bucket_start[b]; m < bucket_start[b + 1]; ++m) {
          const std::uint32_t j = members[m];
          const double dx = x[j] - x[i], dy = y[j] - y[i], r2 = dx * dx + dy * dy;
          if (r2 < R2) emit(j, r2);
        }
      }
  };
  const long ln = static_cast<long>(n);
#pragma omp parallel for schedule(static) num_threads(threads) if (threads > 1)
  for (long i = 0; i < ln; ++i) {
    std::size_t c = 0;
    visit(static_cast<std::size_t>(i), [&](std::uint32_t, double) { ++c; });
    start_[static_cast<std::size_t>(i) + 1] = c;
  }
  for (std::size_t i = 0; i < n; ++i) start_[i + 1] += start_[i];
  neighbour_.resize(start_[n]);
  kernel_.resize(start_[n]);
#pragma omp parallel for schedule(static) num_threads(threads) if (threads > 1)
  for (long i = 0; i < ln; ++i) {
    std::size_t k = start_[static_cast<std::size_t>(i)];
    visit(static_cast<std::size_t>(i), [&](std::uint32_t j, double r2) {
      neighbour_[k] = j;
      kernel_[k] = volume[j] * std::exp(-r2 * inv_l2);  // V_j w(r_ij), w = exp(-(r/ℓ)²)
      ++k;
    });
  }
}

void NonlocalAverage::average(const double* f, const std::uint8_t* active, double* out,
                              int threads) const {
  const long n = static_cast<long>(points());
#pragma omp parallel for schedule(static) num_threads(threads) if (threads > 1)
  for (long i = 0; i < n; ++i) {
    const std::size_t b = start_[static_cast<std::size_t>(i)];
    const std::size_t e = start_[static_cast<std::size_t>(i) + 1];
    double num = 0.0, den = 0.0;
    if (active) {
      for (std::size_t k = b; k < e; ++k) {
        const std::uint32_t j = neighbour_[k];
        const double w = active[j] ? kernel_[k] : 0.0;
        num += w * f[j];
        den += w;
      }
    } else {
      for (std::size_t k = b; k < e; ++k) {
        num += kernel_[k] * f[neighbour_[k]];
        den += kernel_[k];
      }
    }
    out[i] = den > 0.0 ? num / den : f[i];
  }
}

double NonlocalAverage::weight_sum(std::size_t i) const {
  double den = 0.0;
  for (std::size_t k = start_[i]; k < start_[i + 1]; ++k) den += kernel_[k];
  double s = 0.0;
  for (std::size_t k = start_[i]; k < start_[i + 1]; ++k) s += kernel_[k] / den;
  return s;
}

}  // namespace granflow::mpm
