// Logically structured polar background grid: a full annulus r0 <= r <= r1 (an O-grid, periodic
// in θ) of nr x nθ straight-edged bilinear quads with nodes at (r_i, θ_j). A point is located in
// O(1): its sector j from its angle, then i and its isoparametric coordinates (ξ, η) in closed
// form from the bilinear map of the cell's isosceles trapezoid (stencil()); a point between an
// arc and the chord of its quad belongs to the radial neighbour. Node numbering:
// node(i, j) = i + (nr+1) j. Linear (Q4) shape functions only.
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
        dt_(2.0 * std::numbers::pi / ntheta),
        inv_dt_(ntheta / (2.0 * std::numbers::pi)),
        half_cos_(std::cos(0.5 * dt_)),
        half_sin_(std::sin(0.5 * dt_)),
        inv_half_cos_(1.0 / half_cos_),
        inv_dr_(1.0 / dr_),
        half_cot_(0.5 * half_cos_ / half_sin_) {
    x_.resize(nodes());
    y_.resize(nodes());
    ray_x_.resize(nt_ + 1);
    ray_y_.resize(nt_ + 1);
    bisector_x_.resize(nt_);
    bisector_y_.resize(nt_);
    for (int j = 0; j <= nt_; ++j) {
      ray_x_[j] = std::cos((j % nt_) * dt_);
      ray_y_[j] = std::sin((j % nt_) * dt_);
    }
    for (int j = 0; j < nt_; ++j) {
      bisector_x_[j] = std::cos((j + 0.5) * dt_);
      bisector_y_[j] = std::sin((j + 0.5) * dt_);
    }
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

  // The cell of a point and its isoparametric coordinates in closed form. Cell (i, j) is the
  // isosceles trapezoid of the nodes at radii r_i, r_i+1 and angles θ_j, θ_j+1: in the frame
  // turned by its bisector angle φ_j = (j + 1/2) Δθ, with c = cos(Δθ/2), s = sin(Δθ/2), the
  // bilinear map of its corners (r c, ∓r s) is
  //   x' = (r_i + ξ Δr) c,   y' = (r_i + ξ Δr) s (2η − 1),
  // so ξ = (x'/c − r_i)/Δr (the chords are the lines x' = r c) and η = (y' c/(x' s) + 1)/2; its
  // Jacobian ∂(x', y')/∂(ξ, η) = [[Δr c, 0], [Δr s (2η − 1), 2 (r_i + ξ Δr) s]], turned back by
  // φ_j. The sector j is the one with e_j × x >= 0 > e_j+1 × x (e_j the unit vector of the radial
  // line θ_j): each point has exactly one, whatever the first guess, which comes from a
  // polynomial atan2 (error ~1e-5 rad against Δθ >= 2π/10⁴ here; a wrong guess moves by one
  // sector). The same map Newton's method solved before (to round-off), without atan2, hypot or
  // the iteration.
  template <ShapeKind shape>
  bool stencil(double x, double y, double /*lx*/, double /*ly*/, Stencil& s) const {
    static_assert(shape == ShapeKind::linear, "PolarGrid supports linear shape functions only");
    if (!(x == x) || !(y == y)) return false;
    int j = std::min(static_cast<int>(approximate_angle(x, y) * inv_dt_), nt_ - 1);
    j = canonical_sector(x, y, j);
    const double bc = bisector_x_[j], bs = bisector_y_[j];
    const double xp = bc * x + bs * y, yp = -bs * x + bc * y;  // cell frame
    const double u = (xp * inv_half_cos_ - r0_) * inv_dr_;
    if (!(xp > 0.0)) return false;
    const int i = std::clamp(static_cast<int>(std::floor(u)), 0, nr_ - 1);
    double xi = u - i;
    constexpr double slack = 1e-9;  // round-off on a cell edge
    if (xi < -slack || xi > 1.0 + slack) return false;
    xi = std::clamp(xi, 0.0, 1.0);
    const double eta = std::clamp(0.5 * (yp * half_cos_ / (xp * half_sin_) + 1.0), 0.0, 1.0);
    // Jacobian in the cell frame, then turned by φ_j: J = R(φ_j) J'
    const double a_xi = dr_ * half_cos_, b_xi = dr_ * half_sin_ * (2.0 * eta - 1.0);
    const double b_eta = 2.0 * (node_radius(i) + xi * dr_) * half_sin_;
    Jac J;
    J.xx = bc * a_xi - bs * b_xi;
    J.yx = bs * a_xi + bc * b_xi;
    J.xy = -bs * b_eta;
    J.yy = bc * b_eta;
    const double inv_det = 1.0 / (J.xx * J.yy - J.xy * J.yx);
    const double N[4] = {(1 - xi) * (1 - eta), xi * (1 - eta), xi * eta, (1 - xi) * eta};
    const double dxi[4] = {-(1 - eta), (1 - eta), eta, -eta};
    const double deta[4] = {-(1 - xi), -xi, xi, (1 - xi)};
    const int row = nr_ + 1;
    const int n0 = i + row * j, n1 = i + row * (j + 1 < nt_ ? j + 1 : 0);
    const int nodes_of[4] = {n0, n0 + 1, n1 + 1, n1};
    s.count = 4;
    for (int a = 0; a < 4; ++a) {
      s.node[a] = nodes_of[a];
      s.N[a] = N[a];
      // ∇N = J^{-T} ∇_ξ N
      s.dNdx[a] = (J.yy * dxi[a] - J.yx * deta[a]) * inv_det;
      s.dNdy[a] = (-J.xy * dxi[a] + J.xx * deta[a]) * inv_det;
    }
    return true;
  }

  // The same cell and functions as stencil(), as the two rows of a QuadStencil: nodes (i, j),
  // (i+1, j) and (i, j+1), (i+1, j+1). `sector` is the first guess of j (the point's sector at
  // its last location; outside [0, nθ): none, the polynomial angle is used) and receives the
  // point's sector. One division instead of stencil()'s three: on the point r_i + ξ Δr = x'/c,
  // so with d = 2 (r_i + ξ Δr) s = 2 x' s/c and a = Δr c the cell-frame Jacobian
  // J' = [[a, 0], [b, d]], b = Δr s (2η − 1), has
  //   J'^-T = [[1/a, −b/(a d)], [0, 1/d]],   1/d = (c/(2 s)) / x',   η = ((c/s) y'/x' + 1)/2,
  // and ∇N = R(φ_j) J'^-T ∇_ξη N (R(φ_j) J' = J of stencil(); R is orthogonal, so J^-T = R J'^-T).
  bool quad(double x, double y, int& sector, QuadStencil& q) const {
    if (!(x == x) || !(y == y)) return false;
    int j = sector >= 0 && sector < nt_
                ? sector
                : std::min(static_cast<int>(approximate_angle(x, y) * inv_dt_), nt_ - 1);
    j = canonical_sector(x, y, j);
    const double bc = bisector_x_[j], bs = bisector_y_[j];
    const double xp = bc * x + bs * y, yp = -bs * x + bc * y;  // cell frame
    if (!(xp > 0.0)) return false;
    const double u = (xp * inv_half_cos_ - r0_) * inv_dr_;
    // the truncation toward zero equals floor(u) for u >= 0, and for u < 0 both clamp to 0
    // (no floor: without SSE4.1 it is a sequence of bit operations on the critical path)
    const int i = std::clamp(static_cast<int>(u), 0, nr_ - 1);
    double xi = u - i;
    constexpr double slack = 1e-9;  // round-off on a cell edge
    if (xi < -slack || xi > 1.0 + slack) return false;
    xi = std::clamp(xi, 0.0, 1.0);
    sector = j;
    const double inv_xp = 1.0 / xp;
    const double eta = std::clamp(yp * inv_xp * half_cot_ + 0.5, 0.0, 1.0);
    const double inv_a = inv_dr_ * inv_half_cos_, inv_d = inv_xp * half_cot_;
    const double b_inv_ad = dr_ * half_sin_ * (2.0 * eta - 1.0) * inv_a * inv_d;  // b/(a d)
    const int row = nr_ + 1;
    q.node[0] = i + row * j;
    q.node[1] = i + row * (j + 1 < nt_ ? j + 1 : 0);
    // N_a and ∂N_a/∂ξ, ∂N_a/∂η of the nodes (i, j), (i+1, j), (i, j+1), (i+1, j+1), written out
    // as scalars (arrays of them were packed into vectors through the stack by GCC 12, a
    // store-forwarding stall per point)
    const double mxi = 1 - xi, meta = 1 - eta;
    q.N[0] = mxi * meta;
    q.N[1] = xi * meta;
    q.N[2] = mxi * eta;
    q.N[3] = xi * eta;
    gradient(q, 0, -meta, -mxi, inv_a, inv_d, b_inv_ad, bc, bs);
    gradient(q, 1, meta, -xi, inv_a, inv_d, b_inv_ad, bc, bs);
    gradient(q, 2, -eta, mxi, inv_a, inv_d, b_inv_ad, bc, bs);
    gradient(q, 3, eta, xi, inv_a, inv_d, b_inv_ad, bc, bs);
    return true;
  }

 private:
  // ∇N_a = R(φ_j) ∇'N_a, ∇'N_a = (dξ/a − b/(a d) dη, dη/d) of quad() from dξ = ∂N_a/∂ξ, dη =
  // ∂N_a/∂η
  static void gradient(QuadStencil& q, int a, double dxi, double deta, double inv_a, double inv_d,
                       double b_inv_ad, double bc, double bs) {
    const double gx = inv_a * dxi - b_inv_ad * deta, gy = inv_d * deta;
    q.dNdx[a] = bc * gx - bs * gy;
    q.dNdy[a] = bs * gx + bc * gy;
  }

  // The canonical sector of (x, y) from a guess j: e_j × x >= 0 and e_j+1 × x < 0 (unique: the
  // test of ray j+1 is the same expression for sectors j and j+1).
  int canonical_sector(double x, double y, int j) const {
    for (int k = 0; k < nt_ && ray_x_[j] * y - ray_y_[j] * x < 0.0; ++k)
      j = j > 0 ? j - 1 : nt_ - 1;
    for (int k = 0; k < nt_ && ray_x_[j + 1] * y - ray_y_[j + 1] * x >= 0.0; ++k)
      j = j + 1 < nt_ ? j + 1 : 0;
    return j;
  }

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

  // θ in [0, 2π) to about 1e-5 rad: atan of the octant's ratio a in [0, 1] by the polynomial
  // a (c1 + a² (c3 + a² (c5 + a² (c7 + a² c9)))) of Abramowitz & Stegun 4.4.49 (|error| <= 1e-5),
  // then the octant's reflections. Only the first guess of the sector (see stencil()).
  static double approximate_angle(double x, double y) {
    const double ax = std::abs(x), ay = std::abs(y);
    const double hi = std::max(ax, ay), lo = std::min(ax, ay);
    const double a = hi > 0.0 ? lo / hi : 0.0, a2 = a * a;
    double t =
        a * (0.9998660 + a2 * (-0.3302995 + a2 * (0.1801410 + a2 * (-0.0851330 + a2 * 0.0208351))));
    if (ay > ax) t = 0.5 * std::numbers::pi - t;
    if (x < 0.0) t = std::numbers::pi - t;
    if (y < 0.0) t = 2.0 * std::numbers::pi - t;
    return t >= 2.0 * std::numbers::pi ? 0.0 : t;
  }

  double r0_, r1_;
  int nr_, nt_;
  double dr_, dt_;
  double inv_dt_, half_cos_, half_sin_, inv_half_cos_, inv_dr_;
  double half_cot_;  // cot(Δθ/2)/2
  std::vector<double> x_, y_;
  // unit vectors of the radial lines θ_j (j = 0..nθ, the last = the first) and of the cells'
  // bisectors φ_j
  std::vector<double> ray_x_, ray_y_, bisector_x_, bisector_y_;
};

}  // namespace granflow::mpm
