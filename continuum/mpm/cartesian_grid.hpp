// Logically structured Cartesian background grid of nx x ny square-or-rectangular cells
// (bilinear quads). A point is located in O(1) from its coordinates: i = floor((x - x0)/hx).
// Node numbering: node(i, j) = i + (nx + 1) j.
#pragma once

#include <algorithm>
#include <cmath>

#include "continuum/mpm/shape_functions_1d.hpp"
#include "continuum/mpm/stencil.hpp"

namespace granflow::mpm {

class CartesianGrid {
 public:
  CartesianGrid(double x0, double y0, double hx, double hy, int nx, int ny)
      : x0_(x0), y0_(y0), hx_(hx), hy_(hy), nx_(nx), ny_(ny) {}

  int nodes() const { return (nx_ + 1) * (ny_ + 1); }
  int cells_x() const { return nx_; }
  int cells_y() const { return ny_; }
  int node(int i, int j) const { return i + (nx_ + 1) * j; }
  int node_i(int n) const { return n % (nx_ + 1); }
  int node_j(int n) const { return n / (nx_ + 1); }
  double node_x(int n) const { return x0_ + hx_ * node_i(n); }
  double node_y(int n) const { return y0_ + hy_ * node_j(n); }
  double x0() const { return x0_; }
  double y0() const { return y0_; }
  double hx() const { return hx_; }
  double hy() const { return hy_; }
  double min_spacing() const { return std::min(hx_, hy_); }
  // Lumped nodal volume ∫ N_a dΩ over the grid (per unit thickness).
  double nodal_volume(int n) const {
    const int i = node_i(n), j = node_j(n);
    const double wx = (i == 0 || i == nx_) ? 0.5 : 1.0;
    const double wy = (j == 0 || j == ny_) ? 0.5 : 1.0;
    return wx * wy * hx_ * hy_;
  }
  // Angle of the node for (r, θ) velocity conditions: not defined on a Cartesian grid.
  double node_angle(int) const { return 0.0; }

  bool inside(double x, double y) const {
    return x >= x0_ && y >= y0_ && x <= x0_ + nx_ * hx_ && y <= y0_ + ny_ * hy_;
  }

  // Fill `s` for a point at (x, y); `lx`, `ly` are the GIMP half-lengths. Returns false when the
  // point is outside the grid. GIMP nodes that fall outside the grid are dropped (the point's
  // domain then crosses the grid edge, which the solver reports as a lost point).
  template <ShapeKind shape>
  bool stencil(double x, double y, double lx, double ly, Stencil& s) const {
    const double fx = (x - x0_) / hx_, fy = (y - y0_) / hy_;
    if (!(fx >= 0.0 && fy >= 0.0 && fx <= nx_ && fy <= ny_)) return false;
    if constexpr (shape == ShapeKind::linear) {
      const int i = std::min(static_cast<int>(fx), nx_ - 1);
      const int j = std::min(static_cast<int>(fy), ny_ - 1);
      const double xi = fx - i, eta = fy - j;  // local coordinates in [0, 1]
      const double Nx[2] = {1.0 - xi, xi}, Ny[2] = {1.0 - eta, eta};
      const double dx[2] = {-1.0 / hx_, 1.0 / hx_}, dy[2] = {-1.0 / hy_, 1.0 / hy_};
      s.count = 4;
      int k = 0;
      for (int b = 0; b < 2; ++b) {
        for (int a = 0; a < 2; ++a, ++k) {
          s.node[k] = node(i + a, j + b);
          s.N[k] = Nx[a] * Ny[b];
          s.dNdx[k] = dx[a] * Ny[b];
          s.dNdy[k] = Nx[a] * dy[b];
        }
      }
    } else {
      // The 3 nodes per direction with non-zero weight: round(f) - 1 .. round(f) + 1.
      const int i0 = static_cast<int>(std::floor(fx + 0.5)) - 1;
      const int j0 = static_cast<int>(std::floor(fy + 0.5)) - 1;
      HatValue wx[3], wy[3];
      for (int a = 0; a < 3; ++a) {
        wx[a] = gimp(x - (x0_ + (i0 + a) * hx_), hx_, lx);
        wy[a] = gimp(y - (y0_ + (j0 + a) * hy_), hy_, ly);
      }
      int k = 0;
      for (int b = 0; b < 3; ++b) {
        const int j = j0 + b;
        for (int a = 0; a < 3; ++a) {
          const int i = i0 + a;
          if (i < 0 || j < 0 || i > nx_ || j > ny_) continue;
          s.node[k] = node(i, j);
          s.N[k] = wx[a].N * wy[b].N;
          s.dNdx[k] = wx[a].dN * wy[b].N;
          s.dNdy[k] = wx[a].N * wy[b].dN;
          ++k;
        }
      }
      s.count = k;
    }
    return true;
  }

 private:
  double x0_, y0_, hx_, hy_;
  int nx_, ny_;
};

}  // namespace granflow::mpm
