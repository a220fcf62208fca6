#include "continuum/mpm/linear_elastic.hpp"

#include <fmt/format.h>

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

void LinearElastic::update_stress(const StressUpdateView& v, double dt) {
  const double lam = lambda_, G2 = 2.0 * shear_modulus_;
#pragma omp parallel for schedule(static) num_threads(v.threads) if (v.threads > 1)
  for (std::size_t p = begin_; p < end_; ++p) {
    const double Dxx = v.Lxx[p], Dyy = v.Lyy[p], Dxy = 0.5 * (v.Lxy[p] + v.Lyx[p]);
    const double Wxy = 0.5 * (v.Lxy[p] - v.Lyx[p]);  // W = [[0, Wxy], [-Wxy, 0]]
    const double tr = Dxx + Dyy;
    const double sxx = v.sxx[p], syy = v.syy[p], sxy = v.sxy[p];
    // (W σ - σ W): xx = 2 Wxy σxy, yy = -2 Wxy σxy, xy = Wxy (σyy - σxx)
    v.sxx[p] = sxx + dt * (lam * tr + G2 * Dxx + 2.0 * Wxy * sxy);
    v.syy[p] = syy + dt * (lam * tr + G2 * Dyy - 2.0 * Wxy * sxy);
    v.szz[p] += dt * lam * tr;
    v.sxy[p] = sxy + dt * (G2 * Dxy + Wxy * (syy - sxx));
  }
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
