#include "continuum/mpm/setup.hpp"

#include <cmath>
#include <stdexcept>

#include "continuum/model/exp_near_zero.hpp"

namespace granflow::mpm {

namespace {
template <class Points>
std::size_t grow(Points& pts, std::size_t added) {
  const std::size_t first = pts.size();
  pts.resize(first + added);
  return first;
}
}  // namespace

std::size_t add_solid_rectangle(Solver& solver, const Rectangle& r, int material, double porosity,
                                double sxx, double syy, double szz) {
  if (material < 0 || material >= solver.materials()) throw std::invalid_argument("bad material");
  SolidPoints& s = solver.solid();
  const std::size_t first = grow(s, static_cast<std::size_t>(r.nx) * r.ny);
  const double dx = (r.x1 - r.x0) / r.nx, dy = (r.y1 - r.y0) / r.ny, V = dx * dy;
  const double rho_s = solver.material(material).grain_density();
  std::size_t p = first;
  for (int j = 0; j < r.ny; ++j) {
    for (int i = 0; i < r.nx; ++i, ++p) {
      s.x[p] = s.x0[p] = r.x0 + (i + 0.5) * dx;
      s.y[p] = s.y0[p] = r.y0 + (j + 0.5) * dy;
      s.volume[p] = V;
      s.solid_volume[p] = (1.0 - porosity) * V;
      s.porosity[p] = porosity;
      s.mass[p] = rho_s * s.solid_volume[p];
      s.sxx[p] = sxx;
      s.syy[p] = syy;
      s.szz[p] = szz;
      s.material[p] = material;
    }
  }
  return first;
}

std::size_t add_liquid_rectangle(Solver& solver, const Rectangle& r, double porosity,
                                 double pressure) {
  LiquidPoints& l = solver.liquid();
  const std::size_t first = grow(l, static_cast<std::size_t>(r.nx) * r.ny);
  const double dx = (r.x1 - r.x0) / r.nx, dy = (r.y1 - r.y0) / r.ny, V = dx * dy;
  const auto& o = solver.liquid_options();
  const double rho = o.density * model::exp_near_zero(pressure / o.bulk_modulus);  // as the steps
  std::size_t p = first;
  for (int j = 0; j < r.ny; ++j) {
    for (int i = 0; i < r.nx; ++i, ++p) {
      l.x[p] = l.x0[p] = r.x0 + (i + 0.5) * dx;
      l.y[p] = l.y0[p] = r.y0 + (j + 0.5) * dy;
      l.volume[p] = V;
      l.porosity[p] = porosity;
      l.mass[p] = porosity * rho * V;
      l.pressure[p] = pressure;
    }
  }
  return first;
}

namespace {
template <class Points, class Fill>
std::size_t fill_annulus(Points& pts, const PolarGrid& g, int i0, int i1, int nr, int nt,
                         Fill fill) {
  const std::size_t per_cell = static_cast<std::size_t>(nr) * nt;
  const std::size_t first = grow(pts, per_cell * (i1 - i0) * g.cells_theta());
  std::size_t p = first;
  for (int j = 0; j < g.cells_theta(); ++j) {
    for (int i = i0; i < i1; ++i) {
      for (int b = 0; b < nt; ++b) {
        for (int a = 0; a < nr; ++a, ++p) {
          double x, y, detJ;
          g.map(i, j, (a + 0.5) / nr, (b + 0.5) / nt, x, y, detJ);
          pts.x[p] = pts.x0[p] = x;
          pts.y[p] = pts.y0[p] = y;
          // Midpoint rule on each sub-square: exact for the bilinear map's linear detJ.
          fill(p, detJ / static_cast<double>(per_cell));
        }
      }
    }
  }
  return first;
}
}  // namespace

std::size_t add_liquid_annulus(Solver& solver, const PolarGrid& grid, int i0, int i1, int nr,
                               int nt, double porosity, double pressure) {
  LiquidPoints& l = solver.liquid();
  const auto& o = solver.liquid_options();
  const double rho = o.density * model::exp_near_zero(pressure / o.bulk_modulus);  // as the steps
  return fill_annulus(l, grid, i0, i1, nr, nt, [&](std::size_t p, double V) {
    l.volume[p] = V;
    l.porosity[p] = porosity;
    l.mass[p] = porosity * rho * V;
    l.pressure[p] = pressure;
  });
}

std::size_t add_solid_annulus(Solver& solver, const PolarGrid& grid, int i0, int i1, int nr, int nt,
                              int material, double porosity) {
  SolidPoints& s = solver.solid();
  const double rho_s = solver.material(material).grain_density();
  return fill_annulus(s, grid, i0, i1, nr, nt, [&](std::size_t p, double V) {
    s.volume[p] = V;
    s.solid_volume[p] = (1.0 - porosity) * V;
    s.porosity[p] = porosity;
    s.mass[p] = rho_s * s.solid_volume[p];
    s.material[p] = material;
  });
}

void apply_surface_traction(PointFields& pts, std::size_t first, std::size_t last, double y_surface,
                            double band, double surface_length, double tx, double ty) {
  std::size_t count = 0;
  for (std::size_t p = first; p < last; ++p) count += std::fabs(pts.y[p] - y_surface) < band;
  if (count == 0) throw std::invalid_argument("no point near the loaded surface");
  const double share = surface_length / static_cast<double>(count);
  for (std::size_t p = first; p < last; ++p) {
    if (std::fabs(pts.y[p] - y_surface) < band) {
      pts.fx_ext[p] += tx * share;
      pts.fy_ext[p] += ty * share;
    }
  }
}

}  // namespace granflow::mpm
