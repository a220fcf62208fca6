#include "continuum/mpm/material_points.hpp"

namespace granflow::mpm {

namespace {
void resize_common(PointFields& p, std::size_t n) {
  for (auto* v : {&p.x, &p.y, &p.vx, &p.vy, &p.mass, &p.volume, &p.fx_ext, &p.fy_ext, &p.Lxx,
                  &p.Lxy, &p.Lyx, &p.Lyy}) {
    v->resize(n, 0.0);
  }
}
}  // namespace

void SolidPoints::resize(std::size_t n) {
  resize_common(*this, n);
  for (auto* v : {&sxx, &syy, &szz, &sxy, &solid_volume, &porosity, &temperature, &x0, &y0}) {
    v->resize(n, 0.0);
  }
  material.resize(n, 0);
}

void LiquidPoints::resize(std::size_t n) {
  resize_common(*this, n);
  for (auto* v : {&pressure, &txx, &tyy, &tzz, &txy, &porosity, &drag, &x0, &y0}) {
    v->resize(n, 0.0);
  }
  porosity.assign(n, 1.0);
}

}  // namespace granflow::mpm
