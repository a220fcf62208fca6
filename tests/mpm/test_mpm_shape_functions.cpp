// Shape functions: partition of unity, zero gradient sum, linear completeness (reproduce x and y
// exactly), for linear and GIMP on the Cartesian grid and linear on the polar grid.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "continuum/mpm/cartesian_grid.hpp"
#include "continuum/mpm/polar_grid.hpp"
#include "continuum/mpm/shape_functions_1d.hpp"

using namespace granflow::mpm;

namespace {
// Round-off of sums of O(1) weights and O(1/h) gradients.
constexpr double tol = 1e-12;

template <ShapeKind S, class G>
void check_consistency(const G& g, double x, double y, double lx, double ly) {
  Stencil s;
  ASSERT_TRUE(g.template stencil<S>(x, y, lx, ly, s)) << x << " " << y;
  double sumN = 0, sumdx = 0, sumdy = 0, rx = 0, ry = 0, gxx = 0, gxy = 0, gyx = 0, gyy = 0;
  for (int k = 0; k < s.count; ++k) {
    sumN += s.N[k];
    sumdx += s.dNdx[k];
    sumdy += s.dNdy[k];
    const double xn = g.node_x(s.node[k]), yn = g.node_y(s.node[k]);
    rx += s.N[k] * xn;
    ry += s.N[k] * yn;
    gxx += s.dNdx[k] * xn;
    gxy += s.dNdy[k] * xn;
    gyx += s.dNdx[k] * yn;
    gyy += s.dNdy[k] * yn;
    EXPECT_GE(s.N[k], -tol);
  }
  EXPECT_NEAR(sumN, 1.0, tol);
  EXPECT_NEAR(sumdx, 0.0, tol * 100);
  EXPECT_NEAR(sumdy, 0.0, tol * 100);
  // Linear completeness: Σ N x_a = x and Σ ∇N x_a = I.
  EXPECT_NEAR(rx, x, tol * 10);
  EXPECT_NEAR(ry, y, tol * 10);
  EXPECT_NEAR(gxx, 1.0, 1e-10);
  EXPECT_NEAR(gyy, 1.0, 1e-10);
  EXPECT_NEAR(gxy, 0.0, 1e-10);
  EXPECT_NEAR(gyx, 0.0, 1e-10);
}
}  // namespace

TEST(MpmShapeFunctions, LinearCartesianIsConsistent) {
  const CartesianGrid g(-1.0, 2.0, 0.1, 0.25, 20, 8);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> ux(-1.0, 1.0), uy(2.0, 4.0);
  for (int i = 0; i < 200; ++i) check_consistency<ShapeKind::linear>(g, ux(rng), uy(rng), 0, 0);
}

TEST(MpmShapeFunctions, GimpCartesianIsConsistentAwayFromEdges) {
  const CartesianGrid g(0.0, 0.0, 0.1, 0.1, 20, 20);
  std::mt19937 rng(5);
  // The point's domain (half-length 0.025) must stay inside the grid for completeness.
  std::uniform_real_distribution<double> u(0.03, 1.97);
  for (int i = 0; i < 200; ++i) check_consistency<ShapeKind::gimp>(g, u(rng), u(rng), 0.025, 0.025);
}

TEST(MpmShapeFunctions, GimpOneDimensionalMatchesItsIntegralDefinition) {
  // uGIMP is the hat function averaged over the particle domain [x - l, x + l]: compare with a
  // midpoint quadrature of the hat (error O(δ²) of the quadrature, δ = 2l/4000).
  const double h = 1.0, l = 0.25;
  for (double d : {-1.3, -1.1, -0.8, -0.3, -0.1, 0.0, 0.2, 0.74, 0.9, 1.2}) {
    const int n = 4000;
    double avg = 0;
    for (int k = 0; k < n; ++k) {
      const double x = d - l + (k + 0.5) * 2 * l / n;
      avg += linear_hat(x, h).N / n;
    }
    EXPECT_NEAR(gimp(d, h, l).N, avg, 1e-7) << d;
    // Gradient against a central difference of the value (O(ε²) with ε = 1e-6).
    const double eps = 1e-6;
    EXPECT_NEAR(gimp(d, h, l).dN, (gimp(d + eps, h, l).N - gimp(d - eps, h, l).N) / (2 * eps), 1e-6)
        << d;
  }
}

TEST(MpmShapeFunctions, LinearPolarIsConsistent) {
  const PolarGrid g(0.5, 1.5, 10, 48);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ur(0.52, 1.47), ut(0.0, 2 * 3.141592653589793);
  for (int i = 0; i < 300; ++i) {
    const double r = ur(rng), t = ut(rng);
    check_consistency<ShapeKind::linear>(g, r * std::cos(t), r * std::sin(t), 0, 0);
  }
}
