// The Solver's construction, its initialization from the filled points and the diagnostics. The
// rest of the class, by concern: solver_maps.cpp (the step and its particle-grid maps),
// solver_nodes.cpp (nodal balance and velocity conditions), solver_constitutive.cpp (point update:
// stresses, storage equation, pressure smoothing), solver_temperature.cpp (conduction of T),
// solver_time_step.cpp (critical steps, Δt), solver_reduction.cpp (per-thread accumulators).
#include "continuum/mpm/solver.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <type_traits>

#include "continuum/mpm/solver_internal.hpp"

namespace granflow::mpm {

using namespace solver_internal;

Solver::Solver(Grid grid, SolverOptions options, LiquidOptions liquid)
    : grid_(std::move(grid)), options_(options), liquid_options_(liquid) {
  if (options_.shape == ShapeKind::gimp && std::holds_alternative<PolarGrid>(grid_)) {
    throw std::invalid_argument("GIMP shape functions need a Cartesian grid");
  }
  if (options_.shape == ShapeKind::gimp) {
    const auto& g = std::get<CartesianGrid>(grid_);
    if (!(options_.gimp_half_length_x > 0 && options_.gimp_half_length_x <= 0.5 * g.hx() &&
          options_.gimp_half_length_y > 0 && options_.gimp_half_length_y <= 0.5 * g.hy())) {
      throw std::invalid_argument("GIMP half-lengths must be in (0, h/2]");
    }
  }
  if (options_.liquid_volumetric_smoothing && options_.shape != ShapeKind::linear) {
    throw std::invalid_argument("liquid volumetric smoothing needs linear shape functions");
  }
  if (!(options_.pressure_relaxation_time >= 0.0) ||
      (options_.pressure_relaxation_time > 0.0 && options_.shape != ShapeKind::linear)) {
    throw std::invalid_argument("pressure relaxation time must be >= 0 (linear shapes only)");
  }
  if (!(options_.flip >= 0.0 && options_.flip <= 1.0)) {
    throw std::invalid_argument("flip fraction must be in [0, 1]");
  }
  if (!(options_.pic_relaxation_time >= 0.0)) {
    throw std::invalid_argument("PIC relaxation time must be >= 0");
  }
  if (options_.pic_relaxation_time > 0.0 && options_.flip != 1.0) {
    throw std::invalid_argument(
        "give either a per-step flip fraction or a PIC relaxation time, not both");
  }
  if (!(options_.local_damping >= 0.0 && options_.local_damping < 1.0)) {
    throw std::invalid_argument("local damping must be in [0, 1)");
  }
  if (!(options_.mass_scaling >= 1.0)) throw std::invalid_argument("mass scaling must be >= 1");
  nn_ = grid_nodes();
  for (auto& c : conditions_) {
    c.mask.assign(nn_, 0);
    c.frame.assign(nn_, 0);
    c.value0.assign(nn_, 0.0);
    c.value1.assign(nn_, 0.0);
    c.ramp.assign(nn_, 0.0);
    c.cos.assign(nn_, 1.0);
    c.sin.assign(nn_, 0.0);
  }
}

int Solver::grid_nodes() const {
  return std::visit([](const auto& g) { return g.nodes(); }, grid_);
}

int Solver::add_material(std::unique_ptr<SolidMaterial> material) {
  materials_.push_back(std::move(material));
  return static_cast<int>(materials_.size()) - 1;
}

void Solver::initialize() {
  // Automatic thread count: one thread per 10,000 points (at most OMP_NUM_THREADS); below that
  // the fork/join of a step's parallel regions (and their barriers) costs more than it saves.
  const long points = static_cast<long>(solid_.size() + liquid_.size());
  threads_ = options_.threads > 0
                 ? options_.threads
                 : static_cast<int>(
                       std::clamp(points / 10000L, 1L, static_cast<long>(omp_get_max_threads())));
  acc_.assign(static_cast<std::size_t>(NF) * nn_, 0.0);
  if (threads_ > 1) scratch_.assign(static_cast<std::size_t>(NF) * nn_ * threads_, 0.0);
  slots_.assign(threads_, ThreadSlot{});
  for (auto* v : {&asx_, &asy_, &alx_, &aly_}) v->assign(nn_, 0.0);
  porosity_.assign(nn_, 1.0);
  for (int phase = 0; phase < 2; ++phase) {
    const std::size_t n = phase == 0 ? solid_.size() : liquid_.size();
    displacement_x_[phase].assign(n, 0.0);
    displacement_y_[phase].assign(n, 0.0);
    StencilCache& c = cache_[phase];  // the polar grid's only
    const std::size_t m = std::holds_alternative<PolarGrid>(grid_) ? n : 0;
    c.quad.assign(m, QuadStencil{{-1, -1}, {}, {}, {}});
    c.sector.assign(m, -1);
    c.valid = false;
    CellCache& q = cells_[phase];
    const auto* cartesian = std::get_if<CartesianGrid>(&grid_);
    const std::size_t cells = cartesian && options_.shape == ShapeKind::linear ? n : 0;
    q.node.assign(cells, -1);
    q.xi.assign(cells, 0.0);
    q.eta.assign(cells, 0.0);
    q.inv_hx = cartesian ? 1.0 / cartesian->hx() : 0.0;
    q.inv_hy = cartesian ? 1.0 / cartesian->hy() : 0.0;
  }
  for (auto* v : {&nodes_.mass_solid, &nodes_.mass_liquid, &nodes_.vx_solid, &nodes_.vy_solid,
                  &nodes_.vx_liquid, &nodes_.vy_liquid}) {
    v->assign(nn_, 0.0);
  }
  nodes_.porosity.assign(nn_, 1.0);
  div_solid_.assign(liquid_.size(), 0.0);
  // Ergun's inertial drag needs |u_L - u_S| at the liquid points; nothing is stored without it.
  forchheimer_ = liquid_options_.drag_law == DragLaw::closure &&
                 liquid_options_.closure.permeability == model::PermeabilityKind::ergun;
  relative_speed_.assign(forchheimer_ ? liquid_.size() : 0, 0.0);
  volumetric_rate_.assign(liquid_.size(), 0.0);
  pressure_change_.assign(options_.pressure_relaxation_time > 0.0 ? liquid_.size() : 0, 0.0);
  point_conductivity_.assign(options_.material_conductivity ? solid_.size() : 0, 0.0);
  if (options_.temperature_conductivity > 0 || options_.material_conductivity) {
    nodal_temperature_.assign(nn_, 0.0);
    heat_capacity_.assign(nn_, 0.0);
    temperature_gradient_x_.assign(solid_.size(), 0.0);
    temperature_gradient_y_.assign(solid_.size(), 0.0);
  }
  liquid_cell_.assign(liquid_.size(), 0);

  // Material ranges: contiguous runs of the same index.
  const std::size_t ns = solid_.size();
  if (ns > 0 && materials_.empty()) throw std::invalid_argument("solid points but no material");
  std::vector<std::size_t> first(materials_.size(), ns), last(materials_.size(), 0);
  for (std::size_t p = 0; p < ns; ++p) {
    const int k = solid_.material[p];
    if (k < 0 || k >= materials()) throw std::invalid_argument("solid point with bad material");
    first[k] = std::min(first[k], p);
    last[k] = std::max(last[k], p + 1);
  }
  for (int k = 0; k < materials(); ++k) {
    if (first[k] >= last[k]) {
      materials_[k]->attach(0, 0);
      continue;
    }
    for (std::size_t p = first[k]; p < last[k]; ++p) {
      if (solid_.material[p] != k) {
        throw std::invalid_argument("solid points of one material must be contiguous");
      }
    }
    materials_[k]->attach(first[k], last[k]);
  }
  double max_mass = 0;
  for (double m : solid_.mass) max_mass = std::max(max_mass, m);
  for (double m : liquid_.mass) max_mass = std::max(max_mass, m);
  mass_floor_ = 1e-12 * max_mass;  // nodes lighter than this carry no velocity (round-off)
  // Porosity of solid points from their solid volume; drag of liquid points from the nodes.
  for (std::size_t p = 0; p < ns; ++p) {
    solid_.porosity[p] = 1.0 - solid_.solid_volume[p] / solid_.volume[p];
  }
  initialized_ = true;
  // One porosity map so that the liquid points see n (and β) before the first step.
  if (liquid_.size() > 0) {
    std::visit(
        [&](const auto& g) {
          using G = std::decay_t<decltype(g)>;
          if constexpr (std::is_same_v<G, CartesianGrid>) {
            if (options_.shape == ShapeKind::gimp) {
              map_first<G, ShapeKind::gimp>(g);
              solve_porosity_only();
              velocity_gradients<G, ShapeKind::gimp>(g, true);
              return;
            }
          }
          map_first<G, ShapeKind::linear>(g);
          solve_porosity_only();
          velocity_gradients<G, ShapeKind::linear>(g, true);
        },
        grid_);
    refresh_liquid_state();
  }
  store_start_nodes();
  update_dt();
}

// The nodal fields of the start (masses, porosity, velocities under the velocity conditions),
// so that output before the first step shows the projected state rather than empty nodes. The
// step recomputes all of them before it uses any.
void Solver::store_start_nodes() {
  if (liquid_.size() == 0) {  // a wet run was mapped above already
    std::visit(
        [&](const auto& g) {
          using G = std::decay_t<decltype(g)>;
          if constexpr (std::is_same_v<G, CartesianGrid>) {
            if (options_.shape == ShapeKind::gimp) return map_first<G, ShapeKind::gimp>(g);
          }
          map_first<G, ShapeKind::linear>(g);
        },
        grid_);
  }
  const double s = options_.mass_scaling;
  const double* A = acc_.data();
  const int nn = nn_;
  const bool wet = liquid_.size() > 0;
  for (int a = 0; a < nn; ++a) {
    const double ms = A[MS * nn + a];
    nodes_.mass_solid[a] = ms / s;
    nodes_.porosity[a] =
        ms / s > mass_floor_ ? std::clamp(A[NMS * nn + a] / (ms / s), 0.0, 1.0) : 1.0;
    nodes_.vx_solid[a] = ms / s > mass_floor_ ? A[PXS * nn + a] / ms : 0.0;
    nodes_.vy_solid[a] = ms / s > mass_floor_ ? A[PYS * nn + a] / ms : 0.0;
    if (wet) {
      const double ml = A[ML * nn + a];
      nodes_.mass_liquid[a] = ml / s;
      nodes_.vx_liquid[a] = ml / s > mass_floor_ ? A[PXL * nn + a] / ml : 0.0;
      nodes_.vy_liquid[a] = ml / s > mass_floor_ ? A[PYL * nn + a] / ml : 0.0;
    }
  }
  apply_conditions(Phase::solid, nodes_.vx_solid.data(), nodes_.vy_solid.data(), 0, nn);
  if (wet) apply_conditions(Phase::liquid, nodes_.vx_liquid.data(), nodes_.vy_liquid.data(), 0, nn);
}

double Solver::total_mass(Phase phase) const {
  const auto& m = phase == Phase::solid ? solid_.mass : liquid_.mass;
  double sum = 0;
  for (double v : m) sum += v;
  return sum;
}

void Solver::total_momentum(Phase phase, double& px, double& py) const {
  const PointFields& p = phase == Phase::solid ? static_cast<const PointFields&>(solid_)
                                               : static_cast<const PointFields&>(liquid_);
  px = py = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    px += p.mass[i] * p.vx[i];
    py += p.mass[i] * p.vy[i];
  }
}

}  // namespace granflow::mpm
