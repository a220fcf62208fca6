// Test fixture shared by tests/mpm: a free two-phase block (18 × 18 points per phase on a
// 20 × 20 Cartesian grid of 0.1 m cells, porosity 0.4, linear elastic skeleton) with non-uniform
// solid velocity and stress and a non-uniform pore pressure, so that every term of the momentum
// balance (internal, pressure, drag, gravity) is active. The caller sets the liquid velocity and
// anything else it needs, then calls initialize().
#pragma once

#include <cmath>
#include <memory>

#include "continuum/mpm/linear_elastic.hpp"
#include "continuum/mpm/setup.hpp"
#include "continuum/mpm/solver.hpp"

namespace granflow::mpm::testing {

inline std::unique_ptr<Solver> two_phase_block(const SolverOptions& options) {
  LiquidOptions l;
  l.bulk_modulus = 1e7;
  l.viscosity = 0.5;
  l.hydraulic_conductivity = 1e-4;
  auto s = std::make_unique<Solver>(CartesianGrid(0, 0, 0.1, 0.1, 20, 20), options, l);
  const int mat = s->add_material(std::make_unique<LinearElastic>(1e6, 0.25, 2650.0));
  const Rectangle r{0.55, 0.55, 1.45, 1.45, 18, 18};
  add_solid_rectangle(*s, r, mat, 0.4);
  add_liquid_rectangle(*s, r, 0.4);
  SolidPoints& sp = s->solid();
  for (std::size_t p = 0; p < sp.size(); ++p) {
    sp.vx[p] = 0.2 * std::sin(3 * sp.y[p]);
    sp.vy[p] = -0.1 * std::cos(2 * sp.x[p]);
    sp.sxx[p] = -1e3 * sp.x[p];
    sp.sxy[p] = 5e2 * sp.y[p];
  }
  LiquidPoints& lp = s->liquid();
  for (std::size_t p = 0; p < lp.size(); ++p) {
    lp.vy[p] = 0.1;
    lp.pressure[p] = 2e3 * lp.y[p];
  }
  return s;
}

}  // namespace granflow::mpm::testing
