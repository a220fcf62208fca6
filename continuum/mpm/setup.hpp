// Filling regions with material points (regular sub-cell layouts) and applying loads.
#pragma once

#include "continuum/mpm/solver.hpp"

namespace granflow::mpm {

// A rectangle [x0, x1] x [y0, y1] filled with nx x ny points on a regular lattice (point at the
// centre of each sub-rectangle).
struct Rectangle {
  double x0, y0, x1, y1;
  int nx, ny;
};

// Solid points of material `material` with porosity n: V_s = (1 - n) V, m = ρ_s V_s. Initial
// effective stress (tension-positive) sxx, syy, szz. Returns the index of the first new point.
std::size_t add_solid_rectangle(Solver& solver, const Rectangle& r, int material, double porosity,
                                double sxx = 0, double syy = 0, double szz = 0);
// Liquid points of a saturated region of porosity n at pore pressure p:
// m = n ρ_w0 exp(p / K_w) V.
std::size_t add_liquid_rectangle(Solver& solver, const Rectangle& r, double porosity,
                                 double pressure = 0);

// Every cell of a polar grid between radial cells [i0, i1) filled with nr x nt points per cell at
// isoparametric sub-cell centres, each with volume detJ x (1/(nr nt)).
std::size_t add_liquid_annulus(Solver& solver, const PolarGrid& grid, int i0, int i1, int nr,
                               int nt, double porosity, double pressure = 0);
std::size_t add_solid_annulus(Solver& solver, const PolarGrid& grid, int i0, int i1, int nr, int nt,
                              int material, double porosity);

// Uniform traction t (N/m² per unit thickness, vector) on the points of [first, last) of a phase
// whose y lies within `band` of y_surface: each gets t x (its share of the surface length).
void apply_surface_traction(PointFields& points, std::size_t first, std::size_t last,
                            double y_surface, double band, double surface_length, double tx,
                            double ty);

}  // namespace granflow::mpm
