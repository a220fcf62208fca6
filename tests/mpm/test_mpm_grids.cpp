// Grid location: the O(1) locate of each grid finds the cell that contains the point, and the
// point is reproduced by the isoparametric map of that cell.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "continuum/mpm/cartesian_grid.hpp"
#include "continuum/mpm/polar_grid.hpp"

using namespace granflow::mpm;

TEST(MpmGrids, CartesianLocateFindsTheCellNodes) {
  const CartesianGrid g(0.0, 0.0, 0.5, 0.25, 4, 8);
  Stencil s;
  ASSERT_TRUE(g.stencil<ShapeKind::linear>(1.2, 0.6, 0, 0, s));
  // Cell (2, 2): nodes (2,2), (3,2), (2,3), (3,3).
  EXPECT_EQ(s.node[0], g.node(2, 2));
  EXPECT_EQ(s.node[3], g.node(3, 3));
  EXPECT_FALSE(g.stencil<ShapeKind::linear>(2.1, 0.6, 0, 0, s));
  EXPECT_FALSE(g.stencil<ShapeKind::linear>(1.0, -0.01, 0, 0, s));
  // The far edge belongs to the last cell.
  EXPECT_TRUE(g.stencil<ShapeKind::linear>(2.0, 2.0, 0, 0, s));
  double vol = 0;
  for (int n = 0; n < g.nodes(); ++n) vol += g.nodal_volume(n);
  EXPECT_NEAR(vol, 2.0 * 2.0, 1e-12);  // lumped volumes add up to the grid area
}

TEST(MpmGrids, PolarLocateReproducesMappedPoints) {
  const PolarGrid g(1.0, 2.0, 5, 16);  // coarse in θ: large chord sagitta
  for (int j = 0; j < g.cells_theta(); ++j) {
    for (int i = 0; i < g.cells_r(); ++i) {
      for (double xi : {0.01, 0.5, 0.99}) {
        for (double eta : {0.02, 0.5, 0.97}) {
          double x, y, detJ;
          g.map(i, j, xi, eta, x, y, detJ);
          EXPECT_GT(detJ, 0.0);
          Stencil s;
          ASSERT_TRUE(g.stencil<ShapeKind::linear>(x, y, 0, 0, s));
          // The stencil nodes are the cell's corners with the bilinear weights.
          EXPECT_EQ(s.node[0], g.node(i, j));
          EXPECT_NEAR(s.N[0], (1 - xi) * (1 - eta), 1e-10);
          EXPECT_NEAR(s.N[2], xi * eta, 1e-10);
        }
      }
    }
  }
}

TEST(MpmGrids, PolarPointBetweenArcAndChordGoesToTheOuterCell) {
  const PolarGrid g(1.0, 2.0, 5, 8);
  // On the ray through the middle of cell θ-index 0, just inside radius 1.2 (node ring 1): it
  // lies outside the chord of ring 1, i.e. in radial cell 1, not 0.
  const double t = 0.5 * g.dtheta(), r = 1.2 - 1e-3;
  Stencil s;
  ASSERT_TRUE(g.stencil<ShapeKind::linear>(r * std::cos(t), r * std::sin(t), 0, 0, s));
  EXPECT_EQ(s.node[0], g.node(1, 0));
  // Outside the outer polygon and inside the inner one: not in the grid.
  EXPECT_FALSE(g.stencil<ShapeKind::linear>(2.0 - 1e-4, 0.0 + 2.0 * std::sin(t), 0, 0, s));
  EXPECT_FALSE(g.stencil<ShapeKind::linear>(0.5, 0.0, 0, 0, s));
  // Periodic wrap: the last cell's outer nodes are the first ring's.
  ASSERT_TRUE(g.stencil<ShapeKind::linear>(1.5 * std::cos(-0.01), 1.5 * std::sin(-0.01), 0, 0, s));
  EXPECT_EQ(s.node[2], g.node(g.node_i(s.node[2]), 0));
}
