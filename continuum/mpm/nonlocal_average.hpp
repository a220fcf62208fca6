// Non-local (integral) average over material points with a Gaussian weight of internal length ℓ
// (Bažant & Jirásek 2002, "Nonlocal integral formulations of plasticity and damage: survey of
// progress", J. Eng. Mech. 128(11):1119-1149, Eq. 1-3; in MPM: Burghardt, Brannon & Guilkey 2012):
//
//   f̄(x_i) = Σ_j α_ij f_j,   α_ij = V_j w(|x_i - x_j|) / Σ_k V_k w(|x_i - x_k|),
//   w(r) = exp(-(r/ℓ)²) for r < R = cutoff ℓ, 0 beyond,
//
// so the weights of each point sum to 1 (a uniform field is kept; near a boundary the missing part
// of the neighbourhood is renormalised away) and are symmetric in r (a linear field is kept in
// the interior where the neighbourhood is complete and the points are evenly spaced).
//
// The neighbour lists (CSR, structure of arrays) are built with square buckets of side R over
// the points' bounding box and kept until a point has moved more than `skin` ℓ since the build
// (update()): the kernel values V_j w(r_ij) are those of the build positions. Every sum runs over
// j in bucket order, independent of the thread count, so results are bit for bit reproducible.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace granflow::mpm {

class NonlocalAverage {
 public:
  // ℓ > 0, m; R = cutoff ℓ (w(R) = exp(-cutoff²): 0.2 % at 2.5); rebuild when a point moved
  // more than skin ℓ.
  explicit NonlocalAverage(double length, double cutoff = 2.5, double skin = 0.02);
  double length() const { return length_; }
  // Builds the lists of the n points (x, y, volume V) if none exist or a point moved more than
  // skin ℓ since the last build; returns true when it rebuilt.
  bool update(const double* x, const double* y, const double* volume, std::size_t n, int threads);
  // Forces a rebuild at the given positions.
  void build(const double* x, const double* y, const double* volume, std::size_t n, int threads);
  // out_i = Σ_j V_j w_ij a_j f_j / Σ_j V_j w_ij a_j over the neighbours j of i that are active
  // (active == nullptr: all; else active[j] != 0); out_i = f_i if none is.
  void average(const double* f, const std::uint8_t* active, double* out, int threads) const;
  std::size_t points() const { return start_.empty() ? 0 : start_.size() - 1; }
  std::size_t pairs() const { return neighbour_.size(); }
  long builds() const { return builds_; }
  // Σ_j α_ij of point i (1 up to rounding; for the tests).
  double weight_sum(std::size_t i) const;
  // Positions and volumes of the last build (empty before the first): a checkpoint stores them,
  // and build() from them after a restart gives the same lists, so the run continues bit for bit.
  const std::vector<double>& built_x() const { return x_built_; }
  const std::vector<double>& built_y() const { return y_built_; }
  const std::vector<double>& built_volume() const { return volume_built_; }

 private:
  double length_, cutoff_, skin_;
  std::vector<std::size_t> start_;        // CSR: neighbours of i are [start_[i], start_[i+1])
  std::vector<std::uint32_t> neighbour_;  // j
  std::vector<double> kernel_;            // V_j w(r_ij)
  std::vector<double> x_built_, y_built_, volume_built_;
  long builds_ = 0;
};

}  // namespace granflow::mpm
