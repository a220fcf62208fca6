#include "continuum/mpm/problems.hpp"

#include <cmath>

#include "continuum/mpm/analytic.hpp"
#include "continuum/mpm/linear_elastic.hpp"
#include "continuum/mpm/setup.hpp"

namespace granflow::mpm {

namespace {
int cells(double length, double h) { return static_cast<int>(std::lround(length / h)); }

// Roller sides (v_x = 0 on x = 0 and x = W) and a fixed base (v = 0 on y = 0) for one phase.
void box_conditions(Solver& s, const CartesianGrid& g, Phase phase) {
  for (int n = 0; n < g.nodes(); ++n) {
    const int i = g.node_i(n), j = g.node_j(n);
    if (i == 0 || i == g.cells_x()) s.fix_velocity(phase, n, Frame::xy, 0, 0.0);
    if (j == 0) {
      s.fix_velocity(phase, n, Frame::xy, 0, 0.0);
      s.fix_velocity(phase, n, Frame::xy, 1, 0.0);
    }
  }
}
}  // namespace

std::unique_ptr<Solver> make_elastic_column(const ColumnSpec& c,
                                            std::unique_ptr<SolidMaterial> material) {
  const int nx = cells(c.width, c.cell), ny = cells(c.height, c.cell);
  CartesianGrid g(0.0, 0.0, c.cell, c.cell, nx, ny + c.empty_rows);
  SolverOptions o = c.options;
  o.gravity_x = 0.0;
  o.gravity_y = -c.gravity;
  if (o.shape == ShapeKind::gimp) {
    o.gimp_half_length_x = o.gimp_half_length_y = 0.5 * c.cell / c.points_per_cell;
  }
  auto s = std::make_unique<Solver>(g, o);
  if (!material)
    material = std::make_unique<LinearElastic>(c.young_modulus, c.poisson_ratio, c.density);
  const int mat = s->add_material(std::move(material));
  add_solid_rectangle(
      *s, {0.0, 0.0, c.width, c.height, nx * c.points_per_cell, ny * c.points_per_cell}, mat, 0.0);
  box_conditions(*s, g, Phase::solid);
  s->initialize();
  return s;
}

ColumnError column_error(const Solver& solver, const ColumnSpec& c) {
  const SolidPoints& p = solver.solid();
  const double scale = c.density * c.gravity * c.height;
  const double k0 = c.poisson_ratio / (1.0 - c.poisson_ratio);
  const double dy = c.cell / c.points_per_cell;
  double ey = 0, ex = 0, base = 0;
  int nb = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    // Exact at rest: the weight of the material above the point's initial height.
    const double syy = analytic::column_vertical_stress(p.y0[i], c.height, c.density, c.gravity);
    ey += (p.syy[i] - syy) * (p.syy[i] - syy);
    ex += (p.sxx[i] - k0 * syy) * (p.sxx[i] - k0 * syy);
    if (p.y0[i] < dy) {
      base += p.syy[i];
      ++nb;
    }
  }
  const double n = static_cast<double>(p.size());
  return {std::sqrt(ey / n) / scale, std::sqrt(ex / n) / scale, nb ? base / nb : 0.0};
}

TerzaghiConstants terzaghi_constants(const TerzaghiSpec& t) {
  const double E = t.young_modulus, nu = t.poisson_ratio;
  const double M = E * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu));
  TerzaghiConstants k;
  k.constrained_modulus = M;
  k.p0 = analytic::undrained_pressure(t.load, M, t.porosity, t.bulk_modulus);
  k.hydraulic_conductivity = t.hydraulic_conductivity;
  if (t.closure_drag) {
    // β_closure = η0 n / κ (seed Eq. 25) equals the Darcy n² γ_w / k_D for k_D = n γ_w κ / η0.
    const double kappa = model::permeability(t.closure, t.grain_diameter, 1.0 - t.porosity);
    k.hydraulic_conductivity =
        t.porosity * t.liquid_density * t.gravity_for_darcy * kappa / t.closure.viscosity;
  }
  k.cv = analytic::consolidation_coefficient(k.hydraulic_conductivity,
                                             t.liquid_density * t.gravity_for_darcy, M, t.porosity,
                                             t.bulk_modulus);
  k.final_settlement = k.p0 * t.height / M;
  return k;
}

std::unique_ptr<Solver> make_terzaghi(const TerzaghiSpec& t,
                                      std::unique_ptr<SolidMaterial> material) {
  const int nx = cells(t.width, t.cell), ny = cells(t.height, t.cell);
  CartesianGrid g(0.0, 0.0, t.cell, t.cell, nx, ny + t.empty_rows);
  SolverOptions o = t.options;
  if (o.shape == ShapeKind::gimp) {
    o.gimp_half_length_x = o.gimp_half_length_y = 0.5 * t.cell / t.points_per_cell;
  }
  o.gravity_x = 0.0;
  o.gravity_y = -t.gravity;
  LiquidOptions l;
  l.density = t.liquid_density;
  l.bulk_modulus = t.bulk_modulus;
  l.drag_law = t.closure_drag ? DragLaw::closure : DragLaw::darcy;
  l.hydraulic_conductivity = t.hydraulic_conductivity;
  l.closure = t.closure;
  l.closure.density = t.liquid_density;
  l.closure.bulk_modulus = t.bulk_modulus;
  l.grain_diameter = t.grain_diameter;
  l.darcy_gravity = t.gravity_for_darcy;
  auto s = std::make_unique<Solver>(g, o, l);
  if (!material)
    material = std::make_unique<LinearElastic>(t.young_modulus, t.poisson_ratio, t.grain_density);
  const int mat = s->add_material(std::move(material));
  const TerzaghiConstants k = terzaghi_constants(t);
  const Rectangle r{0.0, 0.0, t.width, t.height, nx * t.points_per_cell, ny * t.points_per_cell};
  const double p0 = t.undrained_start ? k.p0 : 0.0;
  const double syy = -(t.undrained_start ? t.load - k.p0 : 0.0);
  const double k0 = t.poisson_ratio / (1.0 - t.poisson_ratio);
  add_solid_rectangle(*s, r, mat, t.porosity, k0 * syy, syy, k0 * syy);
  add_liquid_rectangle(*s, r, t.porosity, p0);
  box_conditions(*s, g, Phase::solid);
  box_conditions(*s, g, Phase::liquid);
  // Load q on the top surface y = H: nodal forces q x tributary length on the solid.
  for (int i = 0; i <= nx && t.load != 0.0; ++i) {
    const double share = (i == 0 || i == nx) ? 0.5 * t.cell : t.cell;
    s->add_nodal_force(Phase::solid, g.node(i, ny), 0.0, -t.load * share);
  }
  s->initialize();
  return s;
}

double terzaghi_pressure_error(const Solver& solver, const TerzaghiSpec& t) {
  const TerzaghiConstants k = terzaghi_constants(t);
  const LiquidPoints& l = solver.liquid();
  double e = 0;
  int n = 0;
  for (std::size_t i = 0; i < l.size(); ++i) {
    const double depth = t.height - l.y[i];
    if (depth < 0.0) continue;  // expelled liquid above the layer
    const double pa = analytic::terzaghi_pressure(depth, solver.time(), t.height, k.cv, k.p0);
    e += (l.pressure[i] - pa) * (l.pressure[i] - pa);
    ++n;
  }
  return n ? std::sqrt(e / n) / k.p0 : 0.0;
}

void hydrostatic_error(const Solver& solver, const TerzaghiSpec& t, double& pressure,
                       double& effective_stress) {
  const double scale = t.liquid_density * t.gravity * t.height;
  double ep = 0, es = 0;
  int np = 0;
  for (std::size_t i = 0; i < solver.liquid().size(); ++i) {
    const double y = solver.liquid().y[i];
    if (y > t.height) continue;  // liquid above the surface (none at rest)
    const double pa = t.liquid_density * t.gravity * (t.height - y);
    ep += (solver.liquid().pressure[i] - pa) * (solver.liquid().pressure[i] - pa);
    ++np;
  }
  const SolidPoints& s = solver.solid();
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double sa =
        -(1 - t.porosity) * (t.grain_density - t.liquid_density) * t.gravity * (t.height - s.y0[i]);
    es += (s.syy[i] - sa) * (s.syy[i] - sa);
  }
  pressure = std::sqrt(ep / std::max(np, 1)) / scale;
  effective_stress = std::sqrt(es / std::max<std::size_t>(s.size(), 1)) / scale;
}

void terzaghi_settlement(const Solver& solver, const TerzaghiSpec& t, double& computed,
                         double& exact) {
  const TerzaghiConstants k = terzaghi_constants(t);
  const SolidPoints& s = solver.solid();
  const double dy = t.cell / t.points_per_cell;
  computed = exact = 0;
  int n = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.y0[i] < t.height - dy) continue;
    computed += s.y0[i] - s.y[i];
    exact += analytic::terzaghi_displacement(t.height - s.y0[i], solver.time(), t.height, k.cv,
                                             k.p0, k.constrained_modulus);
    ++n;
  }
  computed /= n;
  exact /= n;
}

std::unique_ptr<Solver> make_couette(const CouetteSpec& c) {
  PolarGrid g(c.inner_radius, c.outer_radius, c.cells_r, c.cells_theta);
  LiquidOptions l;
  l.density = c.density;
  l.bulk_modulus = c.bulk_modulus;
  l.viscosity = c.viscosity;
  l.viscosity_law = ViscosityLaw::constant;
  SolverOptions o = c.options;
  o.shape = ShapeKind::linear;
  auto s = std::make_unique<Solver>(g, o, l);
  add_liquid_annulus(*s, g, 0, c.cells_r, c.points_per_cell, c.points_per_cell, 1.0);
  for (int j = 0; j < c.cells_theta; ++j) {
    const int inner = g.node(0, j), outer = g.node(c.cells_r, j);
    s->fix_velocity(Phase::liquid, inner, Frame::polar, 0, 0.0);
    s->fix_velocity(Phase::liquid, inner, Frame::polar, 1, 0.0);
    s->fix_velocity(Phase::liquid, outer, Frame::polar, 0, 0.0);
    s->fix_velocity(Phase::liquid, outer, Frame::polar, 1, c.wall_velocity);
  }
  s->initialize();
  return s;
}

void couette_error(const Solver& solver, const CouetteSpec& c, double& tangential, double& radial) {
  couette_error(solver, c, solver.nodes().vx_liquid, solver.nodes().vy_liquid, tangential, radial);
}

void couette_error(const Solver& solver, const CouetteSpec& c, const std::vector<double>& vx_node,
                   const std::vector<double>& vy_node, double& tangential, double& radial) {
  // The grid velocity (MUSL: mass-weighted projection of the point velocities, then the wall
  // conditions) at the interior nodes: the continuum field of the method, free of the FLIP
  // null-space noise that single points carry.
  const auto& g = std::get<PolarGrid>(solver.grid());
  double et = 0, er = 0;
  int n = 0;
  for (int a = 0; a < g.nodes(); ++a) {
    const int i = g.node_i(a);
    if (i == 0 || i == g.cells_r()) continue;
    const double th = g.node_angle(a), cs = std::cos(th), sn = std::sin(th);
    const double vx = vx_node[a], vy = vy_node[a];
    const double vr = vx * cs + vy * sn, vt = -vx * sn + vy * cs;
    const double va = analytic::couette_velocity(g.node_radius(i), c.inner_radius, c.outer_radius,
                                                 c.wall_velocity);
    et += (vt - va) * (vt - va);
    er += vr * vr;
    ++n;
  }
  tangential = std::sqrt(et / n) / c.wall_velocity;
  radial = std::sqrt(er / n) / c.wall_velocity;
}

}  // namespace granflow::mpm
