// The box and annulus geometries of the `mpm` problems (kind_geometry.hpp).
#include "continuum/mpm/kind_geometry.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace granflow::mpm::kind {

namespace {
bool multiple(double length, double cell) {
  const double k = length / cell;
  return std::fabs(k - std::round(k)) < 1e-9 * std::max(1.0, k) && std::round(k) >= 1;
}

// A length (m, > 0) with the problem's default.
core::Field& length(core::Field& g, const char* key, const std::string& doc, const char* value) {
  return g.number(key, "m", doc).default_value(value).greater_than(0);
}
}  // namespace

void box_geometry(core::Schema& s, const BoxDefaults& d) {
  auto& g = s.section("geometry", fmt::format("{} and background grid", d.what));
  length(g, "width", fmt::format("{} width (a multiple of the cell size)", d.what), d.width);
  length(g, "height", fmt::format("{} height H", d.what), d.height);
  length(g, "cell", "square cell size h", d.cell).sweepable();
  g.integer("points_per_cell", "material points per cell and direction (each phase)")
      .default_value("2")
      .at_least(1);
  g.integer("empty_rows", fmt::format("empty grid rows above the {} (expelled liquid)", d.what))
      .default_value("2")
      .at_least(1);
}

void check_box(const core::Case& c) {
  if (!multiple(c.number("geometry.height"), c.number("geometry.cell")))
    c.fail("geometry.cell", "a cell size that divides geometry.height");
  if (!multiple(c.number("geometry.width"), c.number("geometry.cell")))
    c.fail("geometry.width", "a multiple of geometry.cell");
}

void annulus_geometry(core::Schema& s, const AnnulusDefaults& d) {
  auto& g = s.section("geometry", "annulus and polar grid");
  length(g, "inner_radius", fmt::format("R_in ({})", d.inner_wall), d.inner_radius);
  length(g, "outer_radius", fmt::format("R_out ({})", d.outer_wall), d.outer_radius);
  g.integer("cells_r", "radial cells").default_value(d.cells_r).at_least(d.min_cells_r).sweepable();
  g.integer("cells_theta", "tangential cells").default_value(d.cells_theta).at_least(8).sweepable();
  auto& points = g.integer("points_per_cell", "points per cell and direction (each phase)");
  points.default_value("2").at_least(1);
  if (d.sweepable_points) points.sweepable();
}

void check_annulus(const core::Case& c) {
  if (c.string("numerics.shape") != "linear")
    c.fail("numerics.shape", "linear (the polar grid has linear shape functions only)");
  if (!(c.number("geometry.outer_radius") > c.number("geometry.inner_radius")))
    c.fail("geometry.outer_radius", "a value > geometry.inner_radius");
}

}  // namespace granflow::mpm::kind
