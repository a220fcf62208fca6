// The local T^½ update (continuum/multi_regime/granular_temperature_update.hpp) against an
// independent path: a fine classical Runge-Kutta integration of the same ODE.
#include <gtest/gtest.h>

#include <cmath>

#include "continuum/multi_regime/granular_temperature_update.hpp"

using granflow::continuum::advance_sqrt_temperature;
using granflow::continuum::RiccatiCoefficients;
using granflow::continuum::steady_sqrt_temperature;

namespace {
double rk4(double s, const RiccatiCoefficients& k, double dt, int n) {
  auto f = [&](double x) { return k.a - k.c * x - k.b * x * x; };
  const double h = dt / n;
  for (int i = 0; i < n; ++i) {
    const double k1 = f(s), k2 = f(s + 0.5 * h * k1), k3 = f(s + 0.5 * h * k2), k4 = f(s + h * k3);
    s += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  return s;
}
}  // namespace

TEST(TemperatureUpdate, ExactSolutionMatchesFineRungeKutta) {
  // heating from cold, cooling from hot, with and without the linear (Λ) sink, and a negative c
  // (compaction heating); RK4 with 1e5 sub-steps has error ~1e-15 relative here.
  const RiccatiCoefficients cases[] = {
      {2.0, 3.0, 0.0}, {2.0, 3.0, 5.0}, {0.5, 1.0, -0.7}, {0.0, 2.0, 1.0}, {1.0, 0.0, 2.0}};
  for (const auto& k : cases)
    for (double s0 : {0.0, 0.1, 3.0})
      for (double dt : {1e-3, 0.1, 2.0}) {
        const double exact = advance_sqrt_temperature(s0, k, dt);
        const double reference = rk4(s0, k, dt, 100000);
        EXPECT_NEAR(exact, reference, 1e-10 * std::max(1.0, reference))
            << "a=" << k.a << " b=" << k.b << " c=" << k.c << " s0=" << s0 << " dt=" << dt;
      }
}

TEST(TemperatureUpdate, NonNegativeAndConvergentForHugeSteps) {
  const RiccatiCoefficients k{1e-3, 1e4, 1e2};
  const double s_star = steady_sqrt_temperature(k);
  EXPECT_NEAR(k.a - k.c * s_star - k.b * s_star * s_star, 0.0, 1e-15);
  for (double s0 : {0.0, 1e-9, 1.0, 1e3})
    for (double dt : {1e-6, 1.0, 1e6, 1e30}) {
      const double s = advance_sqrt_temperature(s0, k, dt);
      EXPECT_GE(s, 0.0);
      EXPECT_TRUE(std::isfinite(s));
      // s moves monotonically towards s* and never overshoots it
      EXPECT_LE(std::abs(s - s_star), std::abs(s0 - s_star) * (1 + 1e-12));
    }
  EXPECT_NEAR(advance_sqrt_temperature(0.5, k, 1e30), s_star, 1e-15);
}
