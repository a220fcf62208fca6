#include "dem_coupling/driver/initial_fluctuations.hpp"

#include <mpi.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "library.h"

namespace granflow::dem {

namespace {
// SplitMix64 (Steele, Lea & Flood 2014): a well-mixed 64-bit hash, so that the fluctuation of an
// atom depends only on (seed, atom id), not on which rank holds it.
std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

}  // namespace

double add_fluctuations(void* handle, double temperature, std::uint64_t seed) {
  const int nlocal = *static_cast<int*>(lammps_extract_global(handle, "nlocal"));
  auto** v = static_cast<double**>(lammps_extract_atom(handle, "v"));
  const auto* mass = static_cast<double*>(lammps_extract_atom(handle, "rmass"));
  const auto* id = static_cast<int*>(lammps_extract_atom(handle, "id"));
  std::vector<double> c(3 * std::size_t(std::max(nlocal, 0)));
  std::array<double, 5> local{}, global{};  // Σ m c (3), Σ m, N
  for (int i = 0; i < nlocal; ++i) {
    std::mt19937_64 rng(splitmix64(seed * 0x100000001b3ULL + std::uint64_t(id[i])));
    auto uniform = [&] { return (double(rng() >> 11) + 0.5) * 0x1.0p-53; };  // (0, 1)
    for (int k = 0; k < 3; ++k) {
      // Box-Muller: sqrt(-2 ln u1) cos(2 π u2) is standard normal
      c[3 * i + k] = std::sqrt(-2.0 * std::log(uniform())) * std::cos(2.0 * M_PI * uniform());
      local[k] += mass[i] * c[3 * i + k];
    }
    local[3] += mass[i];
    local[4] += 1.0;
  }
  MPI_Allreduce(local.data(), global.data(), 5, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  double sum_sq_local = 0.0, sum_sq = 0.0;
  for (int i = 0; i < nlocal; ++i)
    for (int k = 0; k < 3; ++k) {
      c[3 * i + k] -= global[k] / global[3];
      sum_sq_local += c[3 * i + k] * c[3 * i + k];
    }
  MPI_Allreduce(&sum_sq_local, &sum_sq, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  if (!(sum_sq > 0.0) || !(temperature > 0.0)) return 0.0;
  const double scale = std::sqrt(3.0 * global[4] * temperature / sum_sq);
  for (int i = 0; i < nlocal; ++i)
    for (int k = 0; k < 3; ++k) v[i][k] += scale * c[3 * i + k];
  return temperature;
}

}  // namespace granflow::dem
