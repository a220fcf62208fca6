#include "continuum/mpm/linear_elastic.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <memory>
#include <stdexcept>

#include "core/case.hpp"
#include "core/schema.hpp"

namespace granflow::mpm {

LinearElastic::LinearElastic(const LinearElasticParameters& p) : grain_density_(p.density) {
  const double E = p.young_modulus, nu = p.poisson_ratio;
  if (!(E > 0.0) || !(nu > -1.0 && nu < 0.5) || !(p.density > 0.0)) {
    throw std::invalid_argument(
        "linear_elastic: need E > 0, -1 < poisson_ratio < 0.5, density > 0");
  }
  lambda_ = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  shear_modulus_ = E / (2.0 * (1.0 + nu));
}

namespace {

// σ' += dt (λ tr D I + 2 G D + W σ' - σ' W) over points [b, e); the arrays do not overlap, which
// __restrict tells the compiler so that it vectorises the loop.
void jaumann_elastic(std::size_t b, std::size_t e, double dt, double lam, double G2,
                     const double* __restrict Lxx, const double* __restrict Lxy,
                     const double* __restrict Lyx, const double* __restrict Lyy,
                     double* __restrict sxx, double* __restrict syy, double* __restrict szz,
                     double* __restrict sxy) {
  for (std::size_t p = b; p < e; ++p) {
    const double Dxx = Lxx[p], Dyy = Lyy[p], Dxy = 0.5 * (Lxy[p] + Lyx[p]);
    const double Wxy = 0.5 * (Lxy[p] - Lyx[p]);  // W = [[0, Wxy], [-Wxy, 0]]
    const double tr = Dxx + Dyy;
    const double s_xx = sxx[p], s_yy = syy[p], s_xy = sxy[p];
    // (W σ - σ W): xx = 2 Wxy σxy, yy = -2 Wxy σxy, xy = Wxy (σyy - σxx)
    sxx[p] = s_xx + dt * (lam * tr + G2 * Dxx + 2.0 * Wxy * s_xy);
    syy[p] = s_yy + dt * (lam * tr + G2 * Dyy - 2.0 * Wxy * s_xy);
    szz[p] += dt * lam * tr;
    sxy[p] = s_xy + dt * (G2 * Dxy + Wxy * (s_yy - s_xx));
  }
}

}  // namespace

void LinearElastic::update_stress(const StressUpdateView& v, double dt) {
  const std::size_t n = end_ - begin_;
  // Fixed contiguous chunks per thread, as the schedule(static) loop this replaces.
#pragma omp parallel num_threads(v.threads) if (v.threads > 1)
  {
    const std::size_t T = static_cast<std::size_t>(omp_get_num_threads());
    const std::size_t t = static_cast<std::size_t>(omp_get_thread_num());
    update_range(v, dt, begin_ + n * t / T, begin_ + n * (t + 1) / T, static_cast<int>(t));
  }
}

void LinearElastic::update_range(const StressUpdateView& v, double dt, std::size_t b, std::size_t e,
                                 int /*t*/) {
  jaumann_elastic(b, e, dt, lambda_, 2.0 * shear_modulus_, v.Lxx, v.Lxy, v.Lyx, v.Lyy, v.sxx, v.syy,
                  v.szz, v.sxy);
}

LinearElasticParameters read_linear_elastic(const core::Case& c) {
  return {c.number("solid.young_modulus"), c.number("solid.poisson_ratio"),
          c.number("solid.density")};
}

MaterialEntry linear_elastic_material() {
  auto declare = [](core::Field& solid, const SolidDefaults& d) {
    const LinearElasticParameters p;
    solid.number("young_modulus", "Pa", "E (linear_elastic)")
        .default_value(solid_default(d, "young_modulus", fmt::format("{}", p.young_modulus)))
        .greater_than(0);
    solid.number("poisson_ratio", "1", "ν (linear_elastic)")
        .default_value(solid_default(d, "poisson_ratio", fmt::format("{}", p.poisson_ratio)))
        .at_least(0)
        .less_than(0.5);
    solid.number("density", "kg/m^3", "grain density ρ_s")
        .default_value(solid_default(d, "density", fmt::format("{}", p.density)))
        .greater_than(0);
  };
  auto create = [](const core::Case& c) -> std::unique_ptr<SolidMaterial> {
    return std::make_unique<LinearElastic>(read_linear_elastic(c));
  };
  return {LinearElastic::material_name, declare, create};
}

}  // namespace granflow::mpm
