// Logically structured polar background grid: a full annulus r0 <= r <= r1 (an O-grid, periodic
// in θ) of nr x nθ straight-edged bilinear quads with nodes at (r_i, θ_j). A point is located in
// O(1) from its own polar coordinates (i from r, j from θ), then its isoparametric coordinates
// (ξ, η) in that quad are found by Newton's method on the bilinear map; a point between an arc and
// the chord of its quad moves to the radial neighbour. Node numbering: node(i, j) = i + (nr+1) j.
// Linear (Q4) shape functions only.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "continuum/mpm/stencil.hpp"

namespace granflow::mpm {

class PolarGrid {
 public:
  PolarGrid(double r0, double r1, int nr, int ntheta)
      : r0_(r0),
        r1_(r1),
        nr_(nr),
        nt_(ntheta),
        dr_((r1 - r0) / nr),
        dt_(2.0 * std::numbers::pi / ntheta) {
    x_.resize(nodes());
    y_.resize(nodes());
    for (int j = 0; j < nt_; ++j) {
      for (int i = 0; i <= nr_; ++i) {
        x_[node(i, j)] = node_radius(i) * std::cos(j * dt_);
        y_[node(i, j)] = node_radius(i) * std::sin(j * dt_);
      }
    }
  }

  int nodes() const { return (nr_ + 1) * nt_; }
  int cells_r() const { return nr_; }
  int cells_theta() const { return nt_; }
  int node(int i, int j) const { return i + (nr_ + 1) * (((j % nt_) + nt_) % nt_); }
  int node_i(int n) const { return n % (nr_ + 1); }
  int node_j(int n) const { return n / (nr_ + 1); }
  double node_radius(int i) const { return r0_ + dr_ * i; }
  double node_x(int n) const { return x_[n]; }
  double node_y(int n) const { return y_[n]; }
  double node_angle(int n) const { return node_j(n) * dt_; }
  double inner_radius() const { return r0_; }
  double outer_radius() const { return r1_; }
  double dr() const { return dr_; }
  double dtheta() const { return dt_; }
  // Shortest cell edge: dr or the inner chord 2 r0 sin(dθ/2).
  double min_spacing() const { return std::min(dr_, 2.0 * r0_ * std::sin(0.5 * dt_)); }

  // Position of isoparametric point (ξ, η) ∈ [0,1]² of cell (i, j), and the Jacobian determinant.
  void map(int i, int j, double xi, double eta, double& x, double& y, double& detJ) const {
    double c[4][2];
    corners(i, j, c);
    Jac J = jacobian(c, xi, eta);
    x = (1 - xi) * (1 - eta) * c[0][0] + xi * (1 - eta) * c[1][0] + xi * eta * c[2][0] +
        (1 - xi) * eta * c[3][0];
    y = (1 - xi) * (1 - eta) * c[0][1] + xi * (1 - eta) * c[1][1] + xi * eta * c[2][1] +
        (1 - xi) * eta * c[3][1];
    detJ = J.xx * J.yy - J.xy * J.yx;
  }

  template <ShapeKind shape>
  bool stencil(double x, double y, double /*lx*/, double /*ly*/, Stencil& s) const {
    static_assert(shape == ShapeKind::linear, "PolarGrid supports linear shape functions only");
    const double r = std::hypot(x, y);
    double theta = std::atan2(y, x);
    if (theta < 0.0) theta += 2.0 * std::numbers::pi;
    if (!(r == r)) return false;
    int j = std::min(static_cast<int>(theta / dt_), nt_ - 1);
    int i = std::clamp(static_cast<int>(std::floor((r - r0_) / dr_)), 0, nr_ - 1);
    double xi = (r - node_radius(i)) / dr_, eta = theta / dt_ - j;
    double c[4][2];
    for (int attempt = 0; attempt < 2; ++attempt) {
      corners(i, j, c);
      // Newton on x(ξ, η) = (x, y); the start (polar fractions) is within the chord sagitta.
      for (int it = 0; it < 4; ++it) {
        const Jac J = jacobian(c, xi, eta);
        const double rx = (1 - xi) * (1 - eta) * c[0][0] + xi * (1 - eta) * c[1][0] +
                          xi * eta * c[2][0] + (1 - xi) * eta * c[3][0] - x;
        const double ry = (1 - xi) * (1 - eta) * c[0][1] + xi * (1 - eta) * c[1][1] +
                          xi * eta * c[2][1] + (1 - xi) * eta * c[3][1] - y;
        const double det = J.xx * J.yy - J.xy * J.yx;
        xi -= (J.yy * rx - J.xy * ry) / det;
        eta -= (-J.yx * rx + J.xx * ry) / det;
      }
      if (xi < 0.0 && i > 0) {
        --i;
        xi += 1.0;
      } else if (xi > 1.0 && i < nr_ - 1) {
        ++i;
        xi -= 1.0;
      } else {
        break;
      }
    }
    constexpr double slack = 1e-9;  // round-off of the Newton solve on a cell edge
    if (xi < -slack || xi > 1.0 + slack) return false;
    xi = std::clamp(xi, 0.0, 1.0);
    eta = std::clamp(eta, 0.0, 1.0);
    const Jac J = jacobian(c, xi, eta);
    const double det = J.xx * J.yy - J.xy * J.yx;
    const double N[4] = {(1 - xi) * (1 - eta), xi * (1 - eta), xi * eta, (1 - xi) * eta};
    const double dxi[4] = {-(1 - eta), (1 - eta), eta, -eta};
    const double deta[4] = {-(1 - xi), -xi, xi, (1 - xi)};
    const int nodes_of[4] = {node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)};
    s.count = 4;
    for (int a = 0; a < 4; ++a) {
      s.node[a] = nodes_of[a];
      s.N[a] = N[a];
      // ∇N = J^{-T} ∇_ξ N
      s.dNdx[a] = (J.yy * dxi[a] - J.yx * deta[a]) / det;
      s.dNdy[a] = (-J.xy * dxi[a] + J.xx * deta[a]) / det;
    }
    return true;
  }

 private:
  struct Jac {
    double xx, xy, yx, yy;  // ∂x/∂ξ, ∂x/∂η, ∂y/∂ξ, ∂y/∂η
  };
  void corners(int i, int j, double c[4][2]) const {
    const int n[4] = {node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)};
    for (int a = 0; a < 4; ++a) {
      c[a][0] = x_[n[a]];
      c[a][1] = y_[n[a]];
    }
  }
  static Jac jacobian(const double c[4][2], double xi, double eta) {
    Jac J;
    J.xx = -(1 - eta) * c[0][0] + (1 - eta) * c[1][0] + eta * c[2][0] - eta * c[3][0];
    J.yx = -(1 - eta) * c[0][1] + (1 - eta) * c[1][1] + eta * c[2][1] - eta * c[3][1];
    J.xy = -(1 - xi) * c[0][0] - xi * c[1][0] + xi * c[2][0] + (1 - xi) * c[3][0];
    J.yy = -(1 - xi) * c[0][1] - xi * c[1][1] + xi * c[2][1] + (1 - xi) * c[3][1];
    return J;
  }

  double r0_, r1_;
  int nr_, nt_;
  double dr_, dt_;
  std::vector<double> x_, y_;
};

}  // namespace granflow::mpm
