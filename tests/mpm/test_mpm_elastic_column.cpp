// Elastic column under gravity on a fixed base with roller sides, brought to rest with local
// damping: the vertical stress at the points against σ_yy = -ρ g (H - y0) and the horizontal one
// against the oedometric K0 = ν/(1-ν) ratio; linear (MUSL, USL) and GIMP shape functions.
#include <gtest/gtest.h>

#include <cstdio>

#include "continuum/mpm/problems.hpp"

using namespace granflow::mpm;

namespace {
ColumnError run(ShapeKind shape, UpdateScheme scheme, double cell) {
  ColumnSpec c;
  c.cell = cell;
  c.options.shape = shape;
  c.options.scheme = scheme;
  c.options.local_damping = 0.3;
  c.options.threads = 1;
  auto s = make_elastic_column(c);
  // 1.5 s = 10 periods of the column's first mode (4 H / c_p = 0.154 s): at rest with α = 0.3.
  while (s->time() < 1.5) s->step();
  const ColumnError e = column_error(*s, c);
  std::printf("shape %d scheme %d h %.3f: RMS sigma_yy error / (rho g H) = %.3e, sigma_xx %.3e\n",
              static_cast<int>(shape), static_cast<int>(scheme), cell, e.vertical_stress,
              e.horizontal_stress);
  return e;
}
}  // namespace

TEST(MpmElasticColumn, LinearMuslStressMatchesTheWeightAbove) {
  const ColumnError e = run(ShapeKind::linear, UpdateScheme::musl, 0.05);
  // Linear shape functions give a cell-wise constant stress: the error at the points is about
  // ρ g h / 4 relative to ρ g H = h / (4 H) = 1.25 % RMS for h = H/20. Bound 2 %.
  EXPECT_LT(e.vertical_stress, 0.02);
  EXPECT_LT(e.horizontal_stress, 0.02);
}

TEST(MpmElasticColumn, UslAndGimpAgreeAndRefine) {
  const ColumnError usl = run(ShapeKind::linear, UpdateScheme::usl, 0.05);
  const ColumnError gimp = run(ShapeKind::gimp, UpdateScheme::musl, 0.05);
  const ColumnError gimp_fine = run(ShapeKind::gimp, UpdateScheme::musl, 0.025);
  EXPECT_LT(usl.vertical_stress, 0.02);  // same bound as MUSL: same spatial discretization
  EXPECT_LT(gimp.vertical_stress, 0.02);
  // Halving h halves the error of the cell-wise stress field (first order at the points).
  EXPECT_LT(gimp_fine.vertical_stress, 0.7 * gimp.vertical_stress);
}
