// The two geometries of the `mpm` problems, each declared in a schema and read from a case in one
// place: a box (a layer or column of width x height on a Cartesian grid, empty rows above it:
// terzaghi, elastic_column) and an annulus on the polar O-grid (couette, rheometer). The problems
// give their own defaults. Internal to the kind.
#pragma once

#include "core/case.hpp"
#include "core/schema.hpp"

namespace granflow::mpm::kind {

struct BoxDefaults {
  const char* width;
  const char* height;
  const char* cell;
  const char* what;  // "layer" or "column", in the key descriptions
};
// `geometry`: width, height, cell (sweepable), points_per_cell, empty_rows.
void box_geometry(core::Schema& s, const BoxDefaults& d);
// Fills width, height, cell, points_per_cell, empty_rows of a ColumnSpec or TerzaghiSpec.
template <class Spec>
void read_box(const core::Case& c, Spec& spec) {
  spec.width = c.number("geometry.width");
  spec.height = c.number("geometry.height");
  spec.cell = c.number("geometry.cell");
  spec.points_per_cell = static_cast<int>(c.integer("geometry.points_per_cell"));
  spec.empty_rows = static_cast<int>(c.integer("geometry.empty_rows"));
}
// The box's cross-field check: the cell divides the height and the width.
void check_box(const core::Case& c);

struct AnnulusDefaults {
  const char* inner_radius;
  const char* outer_radius;
  const char* cells_r;
  const char* cells_theta;
  const char* inner_wall;  // what the inner and outer walls are, in the key descriptions
  const char* outer_wall;
  double min_cells_r;
  bool sweepable_points;  // points_per_cell may be swept
};
// `geometry`: inner_radius, outer_radius, cells_r, cells_theta (sweepable), points_per_cell.
void annulus_geometry(core::Schema& s, const AnnulusDefaults& d);
// Fills inner_radius, outer_radius, cells_r, cells_theta, points_per_cell of a CouetteSpec or
// RheometerSpec.
template <class Spec>
void read_annulus(const core::Case& c, Spec& spec) {
  spec.inner_radius = c.number("geometry.inner_radius");
  spec.outer_radius = c.number("geometry.outer_radius");
  spec.cells_r = static_cast<int>(c.integer("geometry.cells_r"));
  spec.cells_theta = static_cast<int>(c.integer("geometry.cells_theta"));
  spec.points_per_cell = static_cast<int>(c.integer("geometry.points_per_cell"));
}
// The annulus's cross-field check: outer_radius > inner_radius, linear shape functions.
void check_annulus(const core::Case& c);

}  // namespace granflow::mpm::kind
