// Order of convergence of the stress update with the step size. The model is driven along a
// straight strain path (compression with lateral extension and a shear component; straight so
// that every N describes the same loading path and only the integration error differs) split
// into N equal increments, each integrated with ONE modified-Euler sub-step (fixed_substeps = 1:
// no error control) plus drift correction. The error against a reference with 2^15 increments
// must fall at least like h^0.9 (a first-order-or-better explicit scheme); the measured order is
// printed. The adaptive default must keep the global error of one single update near STOL.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "continuum/model/force_chains/force_chain_model.hpp"
#include "tests/force_chains/strain_drivers.hpp"

namespace fc = granflow::model::force_chains;
using fc::testing::diag;

namespace {
Eigen::Matrix3d path_increment(double t0, double t1) {
  // ε(t) for t in [0,1]: triaxial-like compression with a shear component (2 % axial strain)
  auto eps = [](double t) {
    Eigen::Matrix3d e = diag(0.02 * t, -0.006 * t, -0.004 * t);
    e(0, 1) = e(1, 0) = 0.004 * t;
    return e;
  };
  return eps(t1) - eps(t0);
}

fc::ForceChainState run(const fc::ForceChainModel& model, int n) {
  auto s = model.isotropic_state(80e3, 0.66);
  for (int i = 0; i < n; ++i) {
    const auto info = model.update(s, path_increment(double(i) / n, double(i + 1) / n), 1e-3, 0.0);
    EXPECT_TRUE(info.plastic || i > 0);
  }
  return s;
}
}  // namespace

TEST(ForceChainsConvergence, StressUpdateConvergesWithStepSize) {
  fc::ForceChainParameters par;
  par.fixed_substeps = 1;
  const fc::ForceChainModel model(par);
  const auto reference = run(model, 1 << 15);
  ASSERT_FALSE(reference.fluidized);
  std::vector<double> h, err;
  for (int n = 32; n <= 512; n *= 2) {
    const auto s = run(model, n);
    h.push_back(1.0 / n);
    err.push_back((s.stress - reference.stress).norm() / reference.stress.norm());
    std::printf("N = %4d  relative stress error = %.3e\n", n, err.back());
  }
  // least-squares slope of log(err) against log(h)
  double mx = 0, my = 0;
  for (size_t i = 0; i < h.size(); ++i) mx += std::log(h[i]), my += std::log(err[i]);
  mx /= h.size();
  my /= h.size();
  double sxy = 0, sxx = 0;
  for (size_t i = 0; i < h.size(); ++i) {
    sxy += (std::log(h[i]) - mx) * (std::log(err[i]) - my);
    sxx += (std::log(h[i]) - mx) * (std::log(h[i]) - mx);
  }
  const double order = sxy / sxx;
  std::printf("measured order of convergence: %.2f\n", order);
  EXPECT_GE(order, 0.9);
  // the adaptive default (STOL = 1e-5) integrates the whole path in ONE update with a global
  // relative error below STOL (local error control per sub-step; measured ~3.5e-6)
  const fc::ForceChainModel adaptive{fc::ForceChainParameters{}};
  const auto s = run(adaptive, 1);
  const double err_adaptive = (s.stress - reference.stress).norm() / reference.stress.norm();
  std::printf("adaptive, one update: relative error = %.3e\n", err_adaptive);
  EXPECT_LT(err_adaptive, adaptive.parameters().stress_tolerance);
}
