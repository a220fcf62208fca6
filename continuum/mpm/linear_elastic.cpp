#include "continuum/mpm/linear_elastic.hpp"

#include <stdexcept>

namespace granflow::mpm {

LinearElastic::LinearElastic(double E, double nu, double rho_s) : grain_density_(rho_s) {
  if (!(E > 0.0) || !(nu > -1.0 && nu < 0.5) || !(rho_s > 0.0)) {
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

}  // namespace granflow::mpm
