// The nodes a material point talks to, with shape-function values and gradients: the only thing
// the particle loops see of the grid. Fixed capacity (3 x 3 nodes for GIMP), no allocation.
#pragma once

namespace granflow::mpm {

// Shape-function family of the background grid.
//  linear: bilinear (isoparametric Q4) functions of the cell holding the point, 4 nodes.
//  gimp:   uniform GIMP (Bardenhagen & Kober 2004, Eq. 35 with a fixed particle domain), tensor
//          product of 1D functions, 3 x 3 nodes; Cartesian grids only.
enum class ShapeKind { linear, gimp };

struct Stencil {
  static constexpr int capacity = 9;
  int count = 0;
  int node[capacity];
  double N[capacity];
  double dNdx[capacity];
  double dNdy[capacity];
};

// A linear-shape stencil of fixed width: the 2 x 2 nodes of a quad cell as two rows of two
// adjacent nodes, (node[r], node[r] + 1) for r = 0, 1; entry 2 r + a of N, dNdx, dNdy belongs to
// node node[r] + a. Both structured grids number their nodes so that this holds (the polar grid:
// i radial, fastest).
struct QuadStencil {
  int node[2];
  double N[4];
  double dNdx[4];
  double dNdy[4];
};

}  // namespace granflow::mpm
