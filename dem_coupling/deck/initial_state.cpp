#include "dem_coupling/deck/initial_state.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>
#include <stdexcept>

#include "continuum/model/effective_restitution.hpp"
#include "continuum/model/g0_carnahan_starling.hpp"
#include "continuum/model/kinetic_theory_coefficients.hpp"

namespace granflow::dem {

namespace {

constexpr double dense_cap = 0.6;  // φ cap of the kinetic-theory start values (header)

struct KineticCoefficients {
  double f1, f2, f3;
};

KineticCoefficients kinetic(double phi, double restitution, double particle_friction) {
  const double nu = std::clamp(phi, 1e-6, dense_cap);
  const double G = nu * model::g0_carnahan_starling(nu);
  const double eps =
      model::effective_restitution_chialvo_sundaresan(restitution, particle_friction);
  return {model::kinetic_f1(nu, G, restitution),
          model::kinetic_f2(nu, G, model::kinetic_J(restitution, G)),
          model::kinetic_f3(nu, G, eps)};
}

double uniform(std::mt19937_64& rng) { return double(rng() >> 11) * 0x1.0p-53; }

}  // namespace

double kinetic_shear_temperature(double solid_fraction, double restitution,
                                 double particle_friction) {
  const KineticCoefficients k = kinetic(solid_fraction, restitution, particle_friction);
  if (!(k.f3 > 0.0)) return 1.0;  // ε >= 1: no steady state
  return k.f2 / k.f3;
}

double kinetic_solid_fraction_at(double inertial_number, double restitution,
                                 double particle_friction) {
  // I(φ) = (f1 f2 / f3)^(-1/2) falls with φ over [0.01, 0.6] (f1 f2/f3 ∝ ν² G² at dense φ).
  auto inertial = [&](double phi) {
    const KineticCoefficients k = kinetic(phi, restitution, particle_friction);
    return k.f3 > 0.0 ? std::sqrt(k.f3 / (k.f1 * k.f2)) : 0.0;
  };
  double lo = 0.01, hi = dense_cap;
  if (!(inertial_number < inertial(lo))) return lo;
  if (!(inertial_number > inertial(hi))) return hi;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (inertial(mid) > inertial_number ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

RandomPacking random_packing(const std::vector<double>& diameters, double solid_fraction,
                             std::uint64_t seed) {
  RandomPacking out;
  const std::size_t n = diameters.size();
  double volume = 0.0, d_max = 0.0;
  for (double d : diameters) {
    volume += std::numbers::pi / 6.0 * d * d * d;
    d_max = std::max(d_max, d);
  }
  const double box = std::cbrt(volume / solid_fraction);
  out.box_length = box;
  out.positions.assign(3 * n, 0.0);
  // Cell list: cells at least d_max wide, so an overlapping pair is in neighbouring cells.
  const long cells = std::max(1L, static_cast<long>(std::floor(box / d_max)));
  const double cell = box / double(cells);
  std::vector<std::vector<std::size_t>> members(cells * cells * cells);
  auto cell_of = [&](double c) {
    return std::min(cells - 1, static_cast<long>(std::floor(c / cell)));
  };
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return diameters[a] > diameters[b]; });
  std::mt19937_64 rng(seed);
  const long reach = cells >= 3 ? 1 : 0;  // fewer than 3 cells: one cell, test every sphere
  for (std::size_t i : order) {
    bool placed = false;
    for (long trial = 0; trial < 100000 && !placed; ++trial) {
      ++out.trials;
      const double p[3] = {uniform(rng) * box, uniform(rng) * box, uniform(rng) * box};
      const long c[3] = {cell_of(p[0]), cell_of(p[1]), cell_of(p[2])};
      bool overlap = false;
      for (long dx = -reach; dx <= reach && !overlap; ++dx)
        for (long dy = -reach; dy <= reach && !overlap; ++dy)
          for (long dz = -reach; dz <= reach && !overlap; ++dz) {
            const long k = reach ? ((c[0] + dx + cells) % cells) +
                                       cells * (((c[1] + dy + cells) % cells) +
                                                cells * ((c[2] + dz + cells) % cells))
                                 : 0;
            for (std::size_t j : members[k]) {
              double r2 = 0.0;
              for (int a = 0; a < 3; ++a) {
                double s = p[a] - out.positions[3 * j + a];
                s -= box * std::round(s / box);  // minimum image
                r2 += s * s;
              }
              const double contact = 0.5 * (diameters[i] + diameters[j]);
              if (r2 < contact * contact) {
                overlap = true;
                break;
              }
            }
          }
      if (overlap) continue;
      for (int a = 0; a < 3; ++a) out.positions[3 * i + a] = p[a];
      members[reach ? c[0] + cells * (c[1] + cells * c[2]) : 0].push_back(i);
      placed = true;
    }
    if (!placed)
      throw std::runtime_error(fmt::format(
          "random insertion: no place for sphere {} of {} at φ = {:.3g} after 1e5 trials", i + 1, n,
          solid_fraction));
  }
  return out;
}

}  // namespace granflow::dem
