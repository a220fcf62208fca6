#include "continuum/mpm/solver.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <optional>

namespace granflow::mpm {

namespace {
// Nodal accumulators of the first map, field-major (field k of node a at k * nodes + a). Solid
// fields first, so a dry run reduces only those.
enum Field : int { MS, PXS, PYS, FXS, FYS, NMS, ML, PXL, PYL, FXL, FYL, GLX, GLY, CD, NF };
constexpr int solid_fields = 6;
// Accumulators of the MUSL momentum remap (reuse the first fields of the same buffer).
enum RemapField : int { R_MS, R_PXS, R_PYS, R_ML, R_PXL, R_PYL };

constexpr double inf = std::numeric_limits<double>::infinity();

inline double sign(double v) { return v > 0.0 ? 1.0 : (v < 0.0 ? -1.0 : 0.0); }

// Thread t's fixed contiguous chunk [b, e) of n points (or nodes) among T threads.
inline void chunk(std::size_t n, int t, int T, std::size_t& b, std::size_t& e) {
  b = n * t / T;
  e = n * (t + 1) / T;
}
inline void node_share(int nn, int t, int T, int& b, int& e) {
  b = static_cast<int>(static_cast<long>(nn) * t / T);
  e = static_cast<int>(static_cast<long>(nn) * (t + 1) / T);
}

// The span [begin, end) of nodes a thread's scatter touched.
struct NodeSpan {
  int begin = std::numeric_limits<int>::max(), end = 0;
  template <class G>
  void add(const Stencil& st) {
    if constexpr (std::is_same_v<G, CartesianGrid>) {
      // Cartesian stencils list their nodes in increasing order (j outer, i inner).
      if (st.count == 0) return;
      begin = std::min(begin, st.node[0]);
      end = std::max(end, st.node[st.count - 1] + 1);
    } else {  // polar: the θ direction wraps around
      for (int k = 0; k < st.count; ++k) {
        begin = std::min(begin, st.node[k]);
        end = std::max(end, st.node[k] + 1);
      }
    }
  }
};
}  // namespace

double TimeStepLimits::critical() const { return std::min({wave, viscous, drag, conduction}); }

SolverFailure::SolverFailure(long s, std::string pt, std::string var, double v,
                             const std::string& why)
    : std::runtime_error(fmt::format("step {}: {} {} = {}: {}", s, pt, var, v, why)),
      step(s),
      point(std::move(pt)),
      variable(std::move(var)),
      value(v) {}

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
  }
}

int Solver::grid_nodes() const {
  return std::visit([](const auto& g) { return g.nodes(); }, grid_);
}

double Solver::node_angle(int n) const {
  return std::visit([n](const auto& g) { return g.node_angle(n); }, grid_);
}

int Solver::add_material(std::unique_ptr<SolidMaterial> material) {
  materials_.push_back(std::move(material));
  return static_cast<int>(materials_.size()) - 1;
}

void Solver::fix_velocity(Phase phase, int node, Frame frame, int component, double value,
                          double ramp_time) {
  if (node < 0 || node >= nn_ || component < 0 || component > 1) {
    throw std::invalid_argument("fix_velocity: node or component out of range");
  }
  if (frame == Frame::polar && !std::holds_alternative<PolarGrid>(grid_)) {
    throw std::invalid_argument("(r, θ) velocity conditions need a polar grid");
  }
  auto& c = conditions_[static_cast<int>(phase)];
  if (c.mask[node] != 0 && c.frame[node] != static_cast<std::uint8_t>(frame)) {
    throw std::invalid_argument("fix_velocity: a node's conditions must share one frame");
  }
  if (c.mask[node] == 0) c.list.push_back(node);
  c.mask[node] |= static_cast<std::uint8_t>(1u << component);
  c.frame[node] = static_cast<std::uint8_t>(frame);
  (component == 0 ? c.value0 : c.value1)[node] = value;
  c.ramp[node] = ramp_time;
}

void Solver::add_nodal_force(Phase phase, int node, double fx, double fy) {
  if (node < 0 || node >= nn_) throw std::invalid_argument("add_nodal_force: node out of range");
  nodal_forces_.push_back({static_cast<int>(phase), node, fx, fy});
}

void Solver::initialize() {
  // Automatic thread count: one thread per 10,000 points (at most OMP_NUM_THREADS); below that
  // the fork/join of the 3 parallel regions (and 4 barriers) per step costs more than it saves.
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
    StencilCache& c = cache_[phase];
    c.stride = 4;  // the cache serves the polar grid (linear shapes) only
    const std::size_t m = std::holds_alternative<PolarGrid>(grid_) ? n * c.stride : 0;
    c.count.assign(m > 0 ? n : 0, 0);
    c.node.assign(m, 0);
    c.N.assign(m, 0.0);
    c.dNdx.assign(m, 0.0);
    c.dNdy.assign(m, 0.0);
    c.valid = false;
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

TimeStepLimits Solver::compute_limits() const {
  TimeStepLimits lim{inf, inf, inf, inf};
  const double h = std::visit([](const auto& g) { return g.min_spacing(); }, grid_);
  const double s = options_.mass_scaling;
  const bool wet = liquid_.size() > 0;
  const double rho_w = liquid_options_.density, K = liquid_options_.bulk_modulus;
  double max_speed = 0;
  double rho_s_min = inf;
  for (const auto& m : materials_) {
    const double M = m->p_wave_modulus(), rho_s = m->grain_density();
    rho_s_min = std::min(rho_s_min, rho_s);
    for (std::size_t p = m->begin(); p < m->end(); ++p) {
      const double n = solid_.porosity[p];
      double c2 = M / ((1.0 - n) * rho_s);  // drained (dry) P wave
      if (wet) {  // undrained P wave of the mixture (Biot's fast wave, no relative motion)
        c2 = std::max(c2, (M + K / n) / ((1.0 - n) * rho_s + n * rho_w));
      }
      const double v = std::hypot(solid_.vx[p], solid_.vy[p]);
      max_speed = std::max(max_speed, std::sqrt(c2 / s) + v);
    }
  }
  double max_eta = 0, max_beta = 0, n_of_max_beta = 1;
  for (std::size_t p = 0; p < liquid_.size(); ++p) {
    const double v = std::hypot(liquid_.vx[p], liquid_.vy[p]);
    max_speed = std::max(max_speed, std::sqrt(K / (rho_w * s)) + v);  // sound in the liquid
    max_eta = std::max(max_eta, viscosity_at(1.0 - liquid_.porosity[p]));
    if (liquid_.drag[p] > max_beta) {
      max_beta = liquid_.drag[p];
      n_of_max_beta = liquid_.porosity[p];
    }
  }
  if (max_speed > 0) lim.wave = h / max_speed;
  // Explicit viscous diffusion in 2D: η dt / (ρ h²) <= 1/4.
  if (max_eta > 0) lim.viscous = 0.25 * h * h * rho_w * s / max_eta;
  // Explicit drag: two masses coupled by β, dt < 2 / (β (1/(n ρ_w) + 1/((1-n) ρ_s))).
  if (max_beta > 0 && options_.drag_integration == DragIntegration::explicit_euler &&
      n_of_max_beta < 1.0) {
    lim.drag =
        2.0 * s /
        (max_beta * (1.0 / (n_of_max_beta * rho_w) + 1.0 / ((1.0 - n_of_max_beta) * rho_s_min)));
  }
  // Explicit conduction in 2D: κ_T Δt / (C h²) <= 1/4 with C = (3/2) ρ_s (1 - n).
  double kappa_max = options_.temperature_conductivity;
  if (options_.material_conductivity)
    for (double k : point_conductivity_) kappa_max = std::max(kappa_max, k);
  if (kappa_max > 0) {
    double C = inf;
    for (std::size_t p = 0; p < solid_.size(); ++p) {
      C = std::min(C, 1.5 * solid_.mass[p] / solid_.volume[p]);
    }
    if (std::isfinite(C)) lim.conduction = 0.25 * h * h * C / kappa_max;
  }
  return lim;
}

void Solver::update_dt() {
  limits_ = compute_limits();
  const double critical = limits_.critical();
  if (options_.fixed_dt > 0) {
    dt_ = options_.fixed_dt;
  } else {
    if (!std::isfinite(critical)) {
      throw SolverFailure(step_, "all points", "dt", critical,
                          "no wave speed to set the time step (give a fixed dt)");
    }
    dt_ = options_.cfl_factor * critical;
  }
}

// The PIC part of the blend relaxes the point velocity towards the grid field: per step
// v ← f v + (1 − f) v_PIC, i.e. over a time t the point–grid difference of a mode the grid does
// not see decays as f^(t/Δt). With f fixed that is exp(t ln f / Δt): a rate ∝ 1/Δt, so a stiffer
// liquid (smaller Δt, K_w) means more numerical viscosity. With f = exp(−Δt/t_PIC) it decays as
// exp(−t/t_PIC) for any Δt (the exact integral of dv/dt = −(v − v_PIC)/t_PIC over one step).
double Solver::flip_fraction() const {
  return options_.pic_relaxation_time > 0.0 ? std::exp(-dt_ / options_.pic_relaxation_time)
                                            : options_.flip;
}

double Solver::viscosity_at(double nu) const {
  if (liquid_options_.viscosity_law == ViscosityLaw::constant) return liquid_options_.viscosity;
  return model::mixture_viscosity(liquid_options_.closure, std::max(nu, 0.0));
}

double Solver::drag_at(double n, long p) const {
  if (n >= 1.0 - 1e-12) return 0.0;  // no solid: nothing to drag against
  if (liquid_options_.drag_law == DragLaw::darcy) {
    // Darcy: n (v_L - v_S) = -(k_D/γ_w) ∇p  =>  β = n² γ_w / k_D
    return n * n * liquid_options_.density * liquid_options_.darcy_gravity /
           liquid_options_.hydraulic_conductivity;
  }
  if (forchheimer_) {
    // Ergun (1952) with its inertial term: -∇p = (η0/κ) q + c_F |q| q, q = n (u_L - u_S), so
    // β = η0 n / κ + c_F n² |u_L - u_S| (model::drag_coefficient_with_inertia), with the
    // relative speed of the last velocity-gradient pass (lagged by one step).
    return model::drag_coefficient_with_inertia(
        liquid_options_.closure, liquid_options_.grain_diameter, 1.0 - n, relative_speed_[p]);
  }
  return model::drag_coefficient(liquid_options_.closure, liquid_options_.grain_diameter, 1.0 - n);
}

// ---- the step ---------------------------------------------------------------------------------

void Solver::step() {
  if (!initialized_) throw std::logic_error("Solver::initialize() must be called before step()");
  std::visit(
      [&](const auto& g) {
        using G = std::decay_t<decltype(g)>;
        if constexpr (std::is_same_v<G, CartesianGrid>) {
          if (options_.shape == ShapeKind::gimp) {
            step_impl<G, ShapeKind::gimp>(g);
            return;
          }
        }
        step_impl<G, ShapeKind::linear>(g);
      },
      grid_);
}

template <class G, ShapeKind S>
void Solver::step_impl(const G& grid) {
  const bool wet = liquid_.size() > 0;
  const bool musl = options_.scheme == UpdateScheme::musl;
  const int T = threads_;
  for (auto& slot : slots_) slot.lost[0] = slot.lost[1] = -1;
  // The grid part of the step as ONE parallel region: every piece is split among the threads
  // (points in fixed contiguous chunks, nodes in fixed contiguous shares) and the pieces are
  // separated by barriers, instead of a fork/join per loop (each costs a futex wake-up of the
  // sleeping thread with OMP_WAIT_POLICY=passive). Lost points are found in the first map; every
  // thread reads the same flags after the first barrier and the region stops there.
  auto grid_part = [&](int t) {
    int b, e;
    node_share(nn_, t, T, b, e);
    map_first_part<G, S>(grid, t);
    if (T > 1) {
#pragma omp barrier
    }
    for (const auto& slot : slots_) {
      if (slot.lost[0] >= 0 || slot.lost[1] >= 0) return;
    }
    // No thread locates a point between this barrier and the next one, so the flag can be set
    // here by one thread without a race.
    if (t == 0) cache_[0].valid = cache_[1].valid = true;
    reduce_part(wet ? NF : solid_fields, t);
    solve_nodes(b, e);
    if (T > 1) {
#pragma omp barrier
    }
    update_points_part<G, S>(grid, t, musl);
    if (!musl) return;
    if (T > 1) {
#pragma omp barrier
    }
    reduce_part(wet ? 6 : 3, t);
    remap_nodes(b, e);
    if (T > 1) {
#pragma omp barrier
    }
    velocity_gradients_part<G, S>(grid, t, wet);
  };
  if (T == 1) {
    grid_part(0);
  } else {
#pragma omp parallel num_threads(T)
    grid_part(omp_get_thread_num());
  }
  throw_if_lost();
  cache_[0].valid = cache_[1].valid = true;
  const bool conduct = (options_.temperature_conductivity > 0 || options_.material_conductivity) &&
                       solid_.size() > 0;
  // Without conduction (which still needs the start-of-step positions) the points move in the
  // constitutive pass.
  constitutive_update(!conduct);
  if (conduct) {
    conduct_temperature<G, S>(grid);
    move_points();
  }
  cache_[0].valid = cache_[1].valid = false;  // the points moved: locate again next step
  time_ += dt_;
  ++step_;
  if (options_.dt_update_interval > 0 && step_ % options_.dt_update_interval == 0) update_dt();
}

double* Solver::scatter_buffer(int t, int fields) {
  if (threads_ == 1) {
    std::fill(acc_.begin(), acc_.begin() + static_cast<std::size_t>(fields) * nn_, 0.0);
    return acc_.data();
  }
  double* mine = scratch_.data() + static_cast<std::size_t>(NF) * nn_ * t;
  ThreadSlot& slot = slots_[t];
  for (int f = 0; f < slot.dirty_fields; ++f) {
    double* field = mine + static_cast<std::size_t>(f) * nn_;
    std::fill(field + slot.dirty_begin, field + slot.dirty_end, 0.0);
  }
  slot.dirty_fields = slot.dirty_begin = slot.dirty_end = 0;
  return mine;
}

void Solver::mark_dirty(int t, int fields, int begin, int end) {
  if (threads_ == 1) return;
  ThreadSlot& slot = slots_[t];
  slot.dirty_fields = begin < end ? fields : 0;
  slot.dirty_begin = begin < end ? begin : 0;
  slot.dirty_end = begin < end ? end : 0;
}

// Sum in thread order starting from 0.0, as a serial loop over the threads would: a given thread
// count reproduces itself bit for bit. A buffer is zero outside the span its thread dirtied, so
// only that span is read (a thread's chunk of points touches a band of the grid, not all of it).
void Solver::reduce_part(int fields, int t) {
  if (threads_ == 1) return;
  int b, e;
  node_share(nn_, t, threads_, b, e);
  const std::size_t stride = static_cast<std::size_t>(NF) * nn_;
  for (int f = 0; f < fields; ++f) {
    double* out = acc_.data() + static_cast<std::size_t>(f) * nn_;
    std::fill(out + b, out + e, 0.0);
    for (int u = 0; u < threads_; ++u) {
      const ThreadSlot& slot = slots_[u];
      if (f >= slot.dirty_fields) continue;
      const double* in = scratch_.data() + stride * u + static_cast<std::size_t>(f) * nn_;
      const int lo = std::max(b, slot.dirty_begin), hi = std::min(e, slot.dirty_end);
      for (int a = lo; a < hi; ++a) out[a] += in[a];
    }
  }
}

// Run `body(acc, t, T)` on every thread with its own zeroed accumulator of `fields` fields, then
// sum the per-thread accumulators into acc_ in thread order (deterministic for a thread count).
template <class Body>
void Solver::scatter(int fields, Body&& body) {
  if (threads_ == 1) {
    body(scatter_buffer(0, fields), 0, 1);
    return;
  }
#pragma omp parallel num_threads(threads_)
  {
    const int t = omp_get_thread_num();
    body(scatter_buffer(t, fields), t, threads_);
    mark_dirty(t, fields, 0, nn_);
#pragma omp barrier
    reduce_part(fields, t);
  }
}

template <class G, ShapeKind S>
inline bool Solver::locate(const G& grid, int phase, std::size_t p, Stencil& st) {
  const PointFields& pts = phase == 0 ? static_cast<const PointFields&>(solid_)
                                      : static_cast<const PointFields&>(liquid_);
  if constexpr (std::is_same_v<G, PolarGrid>) {
    StencilCache& c = cache_[phase];
    const std::size_t o = p * static_cast<std::size_t>(c.stride);
    if (c.valid) {
      st.count = c.count[p];
      for (int k = 0; k < st.count; ++k) {
        st.node[k] = c.node[o + k];
        st.N[k] = c.N[o + k];
        st.dNdx[k] = c.dNdx[o + k];
        st.dNdy[k] = c.dNdy[o + k];
      }
      return st.count > 0;
    }
    const bool inside = grid.template stencil<S>(pts.x[p], pts.y[p], 0.0, 0.0, st);
    c.count[p] = inside ? st.count : 0;
    for (int k = 0; inside && k < st.count; ++k) {
      c.node[o + k] = st.node[k];
      c.N[o + k] = st.N[k];
      c.dNdx[o + k] = st.dNdx[k];
      c.dNdy[o + k] = st.dNdy[k];
    }
    return inside;
  } else {
    // Cartesian: locating is a few flops, cheaper than reading a cache.
    return grid.template stencil<S>(pts.x[p], pts.y[p], options_.gimp_half_length_x,
                                    options_.gimp_half_length_y, st);
  }
}

template <class G, ShapeKind S>
void Solver::map_first_part(const G& grid, int t) {
  const bool wet = liquid_.size() > 0;
  const int nn = nn_, T = threads_;
  const int fields = wet ? NF : solid_fields;
  const double s = options_.mass_scaling, gx = options_.gravity_x, gy = options_.gravity_y;
  double* acc = scatter_buffer(t, fields);
  NodeSpan span;
  long* lost = slots_[t].lost;
  double* ms = acc + MS * nn;
  double* pxs = acc + PXS * nn;
  double* pys = acc + PYS * nn;
  double* fxs = acc + FXS * nn;
  double* fys = acc + FYS * nn;
  double* nms = acc + NMS * nn;
  std::size_t b, e;
  chunk(solid_.size(), t, T, b, e);
  const SolidPoints& sp = solid_;
  Stencil st{};
  for (std::size_t p = b; p < e; ++p) {
    if (!locate<G, S>(grid, 0, p, st)) {
      if (lost[0] < 0) lost[0] = static_cast<long>(p);
      continue;
    }
    if (T > 1) span.add<G>(st);
    const double m = sp.mass[p], mi = m * s, V = sp.volume[p];
    const double mvx = mi * sp.vx[p], mvy = mi * sp.vy[p], mn = m * sp.porosity[p];
    const double fx = m * gx + sp.fx_ext[p], fy = m * gy + sp.fy_ext[p];
    const double sxx = sp.sxx[p] * V, syy = sp.syy[p] * V, sxy = sp.sxy[p] * V;
    for (int k = 0; k < st.count; ++k) {
      const int a = st.node[k];
      const double N = st.N[k], dx = st.dNdx[k], dy = st.dNdy[k];
      ms[a] += N * mi;
      pxs[a] += N * mvx;
      pys[a] += N * mvy;
      // f_int = -∫ ∇N · σ' dV ; f_ext = N (m g + point load)
      fxs[a] += N * fx - (dx * sxx + dy * sxy);
      fys[a] += N * fy - (dx * sxy + dy * syy);
      nms[a] += N * mn;
    }
  }
  if (wet) {
    double* ml = acc + ML * nn;
    double* pxl = acc + PXL * nn;
    double* pyl = acc + PYL * nn;
    double* fxl = acc + FXL * nn;
    double* fyl = acc + FYL * nn;
    double* glx = acc + GLX * nn;
    double* gly = acc + GLY * nn;
    double* cd = acc + CD * nn;
    const LiquidPoints& lp = liquid_;
    chunk(lp.size(), t, T, b, e);
    for (std::size_t p = b; p < e; ++p) {
      if (!locate<G, S>(grid, 1, p, st)) {
        if (lost[1] < 0) lost[1] = static_cast<long>(p);
        continue;
      }
      if (T > 1) span.add<G>(st);
      const double m = lp.mass[p], mi = m * s, V = lp.volume[p];
      const double mvx = mi * lp.vx[p], mvy = mi * lp.vy[p];
      const double fx = m * gx + lp.fx_ext[p], fy = m * gy + lp.fy_ext[p];
      // Liquid stress σ_L = -p I + τ acting on the mixture volume V of the point.
      const double sxx = (lp.txx[p] - lp.pressure[p]) * V, syy = (lp.tyy[p] - lp.pressure[p]) * V,
                   sxy = lp.txy[p] * V;
      const double beta_V = lp.drag[p] * V;
      for (int k = 0; k < st.count; ++k) {
        const int a = st.node[k];
        const double N = st.N[k], dx = st.dNdx[k], dy = st.dNdy[k];
        ml[a] += N * mi;
        pxl[a] += N * mvx;
        pyl[a] += N * mvy;
        fxl[a] += N * fx;
        fyl[a] += N * fy;
        glx[a] -= dx * sxx + dy * sxy;
        gly[a] -= dx * sxy + dy * syy;
        cd[a] += N * beta_V;
      }
    }
  }
  mark_dirty(t, fields, span.begin, span.end);
}

template <class G, ShapeKind S>
void Solver::map_first(const G& grid) {
  const int fields = liquid_.size() > 0 ? NF : solid_fields;
  for (auto& slot : slots_) slot.lost[0] = slot.lost[1] = -1;
  if (threads_ == 1) {
    map_first_part<G, S>(grid, 0);
  } else {
#pragma omp parallel num_threads(threads_)
    {
      const int t = omp_get_thread_num();
      map_first_part<G, S>(grid, t);
#pragma omp barrier
      reduce_part(fields, t);
    }
  }
  throw_if_lost();
  cache_[0].valid = cache_[1].valid = true;  // stencils at the current positions
}

void Solver::throw_if_lost() const {
  // The lowest index over the threads (each slot holds the first of its chunk), solid first.
  for (int phase = 0; phase < 2; ++phase) {
    long first = -1;
    for (const auto& slot : slots_) {
      if (slot.lost[phase] >= 0 && (first < 0 || slot.lost[phase] < first))
        first = slot.lost[phase];
    }
    if (first >= 0) lost_point(static_cast<Phase>(phase), first);
  }
}

void Solver::lost_point(Phase phase, long index) const {
  const PointFields& p = phase == Phase::solid ? static_cast<const PointFields&>(solid_)
                                               : static_cast<const PointFields&>(liquid_);
  const double x = p.x[index], y = p.y[index];
  const bool finite = std::isfinite(x) && std::isfinite(y);
  throw SolverFailure(step_ + 1,
                      fmt::format("{} point {} at ({}, {})",
                                  phase == Phase::solid ? "solid" : "liquid", index, x, y),
                      "position", finite ? x : (std::isfinite(x) ? y : x),
                      finite ? "left the background grid (lost point)"
                             : "non-finite position (a NaN/Inf upstream: stress, pressure or "
                               "velocity)");
}

void Solver::solve_porosity_only() {
  const double s = options_.mass_scaling;
  for (int a = 0; a < nn_; ++a) {
    const double m = acc_[MS * nn_ + a] / s;
    porosity_[a] = m > mass_floor_ ? std::clamp(acc_[NMS * nn_ + a] / m, 0.0, 1.0) : 1.0;
  }
}

void Solver::solve_nodes(int begin, int end) {
  const bool wet = liquid_.size() > 0;
  const int nn = nn_;
  for (const auto& f : nodal_forces_) {
    if ((f.phase == 1 && !wet) || f.node < begin || f.node >= end) continue;
    acc_[(f.phase == 0 ? FXS : FXL) * nn + f.node] += f.fx;
    acc_[(f.phase == 0 ? FYS : FYL) * nn + f.node] += f.fy;
  }
  const double dt = dt_, s = options_.mass_scaling, alpha = options_.local_damping;
  const double floor = mass_floor_ * s;
  const bool implicit_drag = options_.drag_integration == DragIntegration::semi_implicit;
  double* A = acc_.data();
  NodeFields& out = nodes_;
  for (int a = begin; a < end; ++a) {
    const double ms = A[MS * nn + a];
    const double n = ms > floor ? std::clamp(A[NMS * nn + a] / (ms / s), 0.0, 1.0) : 1.0;
    porosity_[a] = n;
    out.porosity[a] = n;
    out.mass_solid[a] = ms / s;
    double fxs = A[FXS * nn + a], fys = A[FYS * nn + a];
    const double vxs0 = ms > floor ? A[PXS * nn + a] / ms : 0.0;
    const double vys0 = ms > floor ? A[PYS * nn + a] / ms : 0.0;
    if (!wet) {
      if (alpha > 0) {  // Cundall local damping: f -= α |f| sign(v)
        fxs -= alpha * std::fabs(fxs) * sign(vxs0);
        fys -= alpha * std::fabs(fys) * sign(vys0);
      }
      if (ms > floor) {
        out.vx_solid[a] = vxs0 + dt * fxs / ms;
        out.vy_solid[a] = vys0 + dt * fys / ms;
        asx_[a] = fxs / ms;
        asy_[a] = fys / ms;
      } else {
        out.vx_solid[a] = out.vy_solid[a] = asx_[a] = asy_[a] = 0.0;
      }
      continue;
    }
    const double ml = A[ML * nn + a];
    out.mass_liquid[a] = ml / s;
    const double vxl0 = ml > floor ? A[PXL * nn + a] / ml : 0.0;
    const double vyl0 = ml > floor ? A[PYL * nn + a] / ml : 0.0;
    double fxl = A[FXL * nn + a], fyl = A[FYL * nn + a];
    // Liquid-stress force shared by volume fraction: n to the liquid, (1 - n) to the solid
    // (this carries the buoyancy/interaction term p ∇n; see docs/mpm.md).
    const double glx = A[GLX * nn + a], gly = A[GLY * nn + a];
    if (ms > floor) {
      fxl += n * glx;
      fyl += n * gly;
      fxs += (1.0 - n) * glx;
      fys += (1.0 - n) * gly;
    } else {
      fxl += glx;
      fyl += gly;
    }
    if (alpha > 0) {
      fxs -= alpha * std::fabs(fxs) * sign(vxs0);
      fys -= alpha * std::fabs(fys) * sign(vys0);
      fxl -= alpha * std::fabs(fxl) * sign(vxl0);
      fyl -= alpha * std::fabs(fyl) * sign(vyl0);
    }
    double vxs, vys, vxl, vyl;
    const double C = A[CD * nn + a];
    if (ms > floor && ml > floor && C > 0) {
      if (implicit_drag) {
        // Backward Euler in the drag only: with P = m v + dt f per phase, the relative velocity
        // w = v_L - v_S solves w (1 + dt C (1/m_L + 1/m_S)) = P_L/m_L - P_S/m_S, and the total
        // momentum P_L + P_S is kept exactly.
        const double Psx = ms * vxs0 + dt * fxs, Psy = ms * vys0 + dt * fys;
        const double Plx = ml * vxl0 + dt * fxl, Ply = ml * vyl0 + dt * fyl;
        const double k = 1.0 / (1.0 + dt * C * (1.0 / ml + 1.0 / ms));
        const double wx = (Plx / ml - Psx / ms) * k, wy = (Ply / ml - Psy / ms) * k;
        vxs = (Psx + Plx - ml * wx) / (ms + ml);
        vys = (Psy + Ply - ml * wy) / (ms + ml);
        vxl = vxs + wx;
        vyl = vys + wy;
      } else {
        const double dx = C * (vxl0 - vxs0), dy = C * (vyl0 - vys0);
        vxs = vxs0 + dt * (fxs + dx) / ms;
        vys = vys0 + dt * (fys + dy) / ms;
        vxl = vxl0 + dt * (fxl - dx) / ml;
        vyl = vyl0 + dt * (fyl - dy) / ml;
      }
    } else {
      vxs = ms > floor ? vxs0 + dt * fxs / ms : 0.0;
      vys = ms > floor ? vys0 + dt * fys / ms : 0.0;
      vxl = ml > floor ? vxl0 + dt * fxl / ml : 0.0;
      vyl = ml > floor ? vyl0 + dt * fyl / ml : 0.0;
    }
    out.vx_solid[a] = vxs;
    out.vy_solid[a] = vys;
    out.vx_liquid[a] = vxl;
    out.vy_liquid[a] = vyl;
    asx_[a] = (vxs - vxs0) / dt;
    asy_[a] = (vys - vys0) / dt;
    alx_[a] = (vxl - vxl0) / dt;
    aly_[a] = (vyl - vyl0) / dt;
  }
  // Velocity conditions at t + dt; the acceleration follows the prescribed velocity.
  for (int phase = 0; phase < (wet ? 2 : 1); ++phase) {
    double* vx = phase == 0 ? out.vx_solid.data() : out.vx_liquid.data();
    double* vy = phase == 0 ? out.vy_solid.data() : out.vy_liquid.data();
    double* ax = phase == 0 ? asx_.data() : alx_.data();
    double* ay = phase == 0 ? asy_.data() : aly_.data();
    const int fm = phase == 0 ? MS : ML, fpx = phase == 0 ? PXS : PXL, fpy = phase == 0 ? PYS : PYL;
    apply_conditions(static_cast<Phase>(phase), vx, vy, begin, end);
    for (int a : conditions_[phase].list) {
      if (a < begin || a >= end) continue;
      const double m = A[fm * nn + a];
      const double v0x = m > floor ? A[fpx * nn + a] / m : 0.0;
      const double v0y = m > floor ? A[fpy * nn + a] / m : 0.0;
      ax[a] = (vx[a] - v0x) / dt;
      ay[a] = (vy[a] - v0y) / dt;
    }
  }
}

void Solver::apply_conditions(Phase phase, double* vx, double* vy, int begin, int end) const {
  const auto& c = conditions_[static_cast<int>(phase)];
  const double t = time_ + dt_;
  for (int a : c.list) {
    if (a < begin || a >= end) continue;
    const double f = c.ramp[a] > 0 ? std::min(1.0, t / c.ramp[a]) : 1.0;
    if (c.frame[a] == static_cast<std::uint8_t>(Frame::xy)) {
      if (c.mask[a] & 1u) vx[a] = f * c.value0[a];
      if (c.mask[a] & 2u) vy[a] = f * c.value1[a];
    } else {
      const double th = node_angle(a), cs = std::cos(th), sn = std::sin(th);
      double vr = vx[a] * cs + vy[a] * sn, vt = -vx[a] * sn + vy[a] * cs;
      if (c.mask[a] & 1u) vr = f * c.value0[a];
      if (c.mask[a] & 2u) vt = f * c.value1[a];
      vx[a] = vr * cs - vt * sn;
      vy[a] = vr * sn + vt * cs;
    }
  }
}

// G2P; with `remap` (MUSL) the updated momentum m v of each point is mapped back to the nodes in
// the same pass (it needs nothing but the point's own new velocity).
template <class G, ShapeKind S>
void Solver::update_points_part(const G& grid, int t, bool remap) {
  const double dt = dt_, flip = flip_fraction(), s = options_.mass_scaling;
  const bool usl = options_.scheme == UpdateScheme::usl;
  const bool wet = liquid_.size() > 0;
  const int nn = nn_, T = threads_;
  const int fields = wet ? 6 : 3;
  double* acc = remap ? scatter_buffer(t, fields) : nullptr;
  NodeSpan span;
  auto g2p = [&](PointFields& pts, const double* vx, const double* vy, const double* ax,
                 const double* ay, bool extras, double* m_, double* px_, double* py_) {
    const int phase = &pts == static_cast<PointFields*>(&liquid_) ? 1 : 0;
    double* dx = displacement_x_[phase].data();
    double* dy = displacement_y_[phase].data();
    std::size_t b, e;
    chunk(pts.size(), t, T, b, e);
    Stencil st{};
    for (std::size_t p = b; p < e; ++p) {
      if (!locate<G, S>(grid, phase, p, st)) continue;  // reported by the first map
      double vpx = 0, vpy = 0, apx = 0, apy = 0, Lxx = 0, Lxy = 0, Lyx = 0, Lyy = 0;
      double div_s = 0, n_at = 0, wx = 0, wy = 0;
      for (int k = 0; k < st.count; ++k) {
        const int a = st.node[k];
        const double N = st.N[k];
        vpx += N * vx[a];
        vpy += N * vy[a];
        apx += N * ax[a];
        apy += N * ay[a];
        if (usl) {
          Lxx += st.dNdx[k] * vx[a];
          Lxy += st.dNdy[k] * vx[a];
          Lyx += st.dNdx[k] * vy[a];
          Lyy += st.dNdy[k] * vy[a];
          if (extras) {
            div_s += st.dNdx[k] * nodes_.vx_solid[a] + st.dNdy[k] * nodes_.vy_solid[a];
            n_at += N * porosity_[a];
            if (forchheimer_) {
              wx += N * (vx[a] - nodes_.vx_solid[a]);
              wy += N * (vy[a] - nodes_.vy_solid[a]);
            }
          }
        }
      }
      // FLIP/PIC blend: v <- flip (v + dt a) + (1 - flip) v_PIC; x <- x + dt v_PIC
      const double vx_new = flip * (pts.vx[p] + dt * apx) + (1.0 - flip) * vpx;
      const double vy_new = flip * (pts.vy[p] + dt * apy) + (1.0 - flip) * vpy;
      pts.vx[p] = vx_new;
      pts.vy[p] = vy_new;
      // Applied at the end of the step (move_points): every grid operation of the step uses
      // the shape functions of the start-of-step configuration.
      dx[p] = dt * vpx;
      dy[p] = dt * vpy;
      if (usl) {
        store_gradient(pts, p, Lxx, Lxy, Lyx, Lyy, extras, div_s, n_at, st.node[0]);
        if (extras && forchheimer_) relative_speed_[p] = std::hypot(wx, wy);
      }
      if (remap) {  // MUSL: m_a = Σ N m, (m v)_a = Σ N m v_new
        if (T > 1) span.add<G>(st);
        const double mi = pts.mass[p] * s, mvx = mi * vx_new, mvy = mi * vy_new;
        for (int k = 0; k < st.count; ++k) {
          const int a = st.node[k];
          m_[a] += st.N[k] * mi;
          px_[a] += st.N[k] * mvx;
          py_[a] += st.N[k] * mvy;
        }
      }
    }
  };
  double* none = nullptr;
  g2p(solid_, nodes_.vx_solid.data(), nodes_.vy_solid.data(), asx_.data(), asy_.data(), false,
      remap ? acc + R_MS * nn : none, remap ? acc + R_PXS * nn : none,
      remap ? acc + R_PYS * nn : none);
  if (wet) {
    g2p(liquid_, nodes_.vx_liquid.data(), nodes_.vy_liquid.data(), alx_.data(), aly_.data(), true,
        remap ? acc + R_ML * nn : none, remap ? acc + R_PXL * nn : none,
        remap ? acc + R_PYL * nn : none);
  }
  if (remap) mark_dirty(t, fields, span.begin, span.end);
}

void Solver::remap_nodes(int begin, int end) {
  const bool wet = liquid_.size() > 0;
  const int nn = nn_;
  const double floor = mass_floor_ * options_.mass_scaling;
  const double* A = acc_.data();
  NodeFields& out = nodes_;
  for (int a = begin; a < end; ++a) {
    const double ms = A[R_MS * nn + a];
    out.vx_solid[a] = ms > floor ? A[R_PXS * nn + a] / ms : 0.0;
    out.vy_solid[a] = ms > floor ? A[R_PYS * nn + a] / ms : 0.0;
    if (wet) {
      const double ml = A[R_ML * nn + a];
      out.vx_liquid[a] = ml > floor ? A[R_PXL * nn + a] / ml : 0.0;
      out.vy_liquid[a] = ml > floor ? A[R_PYL * nn + a] / ml : 0.0;
    }
  }
  apply_conditions(Phase::solid, out.vx_solid.data(), out.vy_solid.data(), begin, end);
  if (wet) {
    apply_conditions(Phase::liquid, out.vx_liquid.data(), out.vy_liquid.data(), begin, end);
  }
}

inline void Solver::store_gradient(PointFields& pts, long p, double Lxx, double Lxy, double Lyx,
                                   double Lyy, bool extras, double div_s, double n_at,
                                   int first_node) {
  pts.Lxx[p] = Lxx;
  pts.Lxy[p] = Lxy;
  pts.Lyx[p] = Lyx;
  pts.Lyy[p] = Lyy;
  if (extras) {
    div_solid_[p] = div_s;
    liquid_cell_[p] = first_node;
    liquid_.porosity[p] = std::clamp(n_at, 1e-3, 1.0);  // floor: a point never sees n = 0
  }
}

template <class G, ShapeKind S>
void Solver::velocity_gradients_part(const G& grid, int t, bool liquid_extras) {
  auto grad = [&](PointFields& pts, const double* vx, const double* vy, bool extras) {
    const int phase = &pts == static_cast<PointFields*>(&liquid_) ? 1 : 0;
    std::size_t b, e;
    chunk(pts.size(), t, threads_, b, e);
    Stencil st{};
    for (std::size_t p = b; p < e; ++p) {
      if (!locate<G, S>(grid, phase, p, st)) continue;
      double Lxx = 0, Lxy = 0, Lyx = 0, Lyy = 0, div_s = 0, n_at = 0, wx = 0, wy = 0;
      for (int k = 0; k < st.count; ++k) {
        const int a = st.node[k];
        Lxx += st.dNdx[k] * vx[a];
        Lxy += st.dNdy[k] * vx[a];
        Lyx += st.dNdx[k] * vy[a];
        Lyy += st.dNdy[k] * vy[a];
        if (extras) {
          div_s += st.dNdx[k] * nodes_.vx_solid[a] + st.dNdy[k] * nodes_.vy_solid[a];
          n_at += st.N[k] * porosity_[a];
          if (forchheimer_) {
            wx += st.N[k] * (vx[a] - nodes_.vx_solid[a]);
            wy += st.N[k] * (vy[a] - nodes_.vy_solid[a]);
          }
        }
      }
      store_gradient(pts, static_cast<long>(p), Lxx, Lxy, Lyx, Lyy, extras, div_s, n_at,
                     st.node[0]);
      if (extras && forchheimer_) relative_speed_[p] = std::hypot(wx, wy);
    }
  };
  grad(solid_, nodes_.vx_solid.data(), nodes_.vy_solid.data(), false);
  if (liquid_.size() > 0) {
    grad(liquid_, nodes_.vx_liquid.data(), nodes_.vy_liquid.data(), liquid_extras);
  }
}

template <class G, ShapeKind S>
void Solver::velocity_gradients(const G& grid, bool liquid_extras) {
  if (threads_ == 1) {
    velocity_gradients_part<G, S>(grid, 0, liquid_extras);
  } else {
#pragma omp parallel num_threads(threads_)
    velocity_gradients_part<G, S>(grid, omp_get_thread_num(), liquid_extras);
  }
  cache_[0].valid = cache_[1].valid = true;
}

template <class G, ShapeKind S>
void Solver::conduct_temperature(const G& grid) {
  const int nn = nn_;
  const double kappa = options_.temperature_conductivity, dt = dt_;
  SolidPoints& sp = solid_;
  scatter(2, [&](double* acc, int t, int T) {
    std::size_t b, e;
    chunk(sp.size(), t, T, b, e);
    Stencil st{};
    for (std::size_t p = b; p < e; ++p) {
      if (!locate<G, S>(grid, 0, p, st)) continue;  // caught in the next map
      const double c = 1.5 * sp.mass[p], cT = c * sp.temperature[p];
      for (int k = 0; k < st.count; ++k) {
        acc[st.node[k]] += st.N[k] * c;
        acc[nn + st.node[k]] += st.N[k] * cT;
      }
    }
  });
  cache_[0].valid = true;
  std::vector<double>& A = acc_;
  std::vector<double>& nodal_T = nodal_temperature_;
  std::vector<double>& capacity = heat_capacity_;
  for (int a = 0; a < nn; ++a) {
    capacity[a] = A[a];
    nodal_T[a] = A[a] > 0 ? A[nn + a] / A[a] : 0.0;
  }
  const long np = static_cast<long>(sp.size());
#pragma omp parallel num_threads(threads_) if (threads_ > 1)
  {
    Stencil st{};
#pragma omp for schedule(static)
    for (long p = 0; p < np; ++p) {
      if (!locate<G, S>(grid, 0, p, st)) continue;
      double gx = 0, gy = 0;
      for (int k = 0; k < st.count; ++k) {
        gx += st.dNdx[k] * nodal_T[st.node[k]];
        gy += st.dNdy[k] * nodal_T[st.node[k]];
      }
      temperature_gradient_x_[p] = gx;
      temperature_gradient_y_[p] = gy;
    }
  }
  scatter(1, [&](double* acc, int t, int T) {
    std::size_t b, e;
    chunk(sp.size(), t, T, b, e);
    Stencil st{};
    for (std::size_t p = b; p < e; ++p) {
      if (!locate<G, S>(grid, 0, p, st)) continue;
      const double kappa_p = options_.material_conductivity ? point_conductivity_[p] : kappa;
      const double qx = kappa_p * temperature_gradient_x_[p] * sp.volume[p];
      const double qy = kappa_p * temperature_gradient_y_[p] * sp.volume[p];
      for (int k = 0; k < st.count; ++k) acc[st.node[k]] -= st.dNdx[k] * qx + st.dNdy[k] * qy;
    }
  });
  for (int a = 0; a < nn; ++a) A[a] = capacity[a] > 0 ? dt * A[a] / capacity[a] : 0.0;  // ΔT_a
  long negative = -1;
#pragma omp parallel num_threads(threads_) if (threads_ > 1) reduction(max : negative)
  {
    Stencil st{};
#pragma omp for schedule(static)
    for (long p = 0; p < np; ++p) {
      if (!locate<G, S>(grid, 0, p, st)) continue;
      // Remap of the nodal change ΔT_a to the points. Heating: N_a ΔT_a (additive). Cooling:
      // each point gives up its share in proportion to its own T, N_a ΔT_a T_p / T_a, with T_a the
      // capacity-weighted nodal T. Both conserve the energy of node a exactly
      // (Σ_p c_p N_a ΔT_a T_p / T_a = ΔT_a C_a), and a cooling point keeps T_p ≥ 0 whenever the
      // nodal update keeps T_a + ΔT_a ≥ 0 (the explicit conduction limit), which the additive form
      // does not guarantee for a cold point next to hot ones.
      const double Tp = sp.temperature[p];
      double dT = 0;
      for (int k = 0; k < st.count; ++k) {
        const int a = st.node[k];
        const double dTa = A[a];
        if (dTa >= 0.0)
          dT += st.N[k] * dTa;
        else if (nodal_T[a] > 0.0)
          dT += st.N[k] * dTa * (Tp / nodal_T[a]);
      }
      sp.temperature[p] = Tp + dT;
      if (!(sp.temperature[p] >= 0.0)) negative = std::max(negative, p);
    }
  }
  if (negative >= 0) {
    throw SolverFailure(step_ + 1, fmt::format("solid point {}", negative), "temperature",
                        sp.temperature[negative], "negative or non-finite granular temperature");
  }
}

// Relaxation of the pore pressure towards its nodal average (numerics.pressure_relaxation_time
// t_p), applied to the start-of-step p with the start-of-step stencils:
//   p_a = Σ_q N_a(x_q) V_q p_q / Σ_q N_a(x_q) V_q,   p̃_p = Σ_a N_a(x_p) p_a,
//   p_p ← p_p − (1 − exp(−Δt/t_p)) (p_p − p̃_p) − mean,
// the volume-weighted mean of the change removed (Σ V Δp = 0, the mean pore pressure is kept).
// A pressure alternating from cell to cell has p̃ = 0 and decays as exp(−t/t_p); it is a
// near-zero-energy mode of the cell-constant rate (its nodal forces nearly cancel), which
// nothing else restrains. A smooth p changes by O(h² ∇²p): a diffusivity ~ h²/t_p, negligible
// against the physical one of a saturated sand, (κ/η0)(K_w/n) (docs/mpm.md).
template <class PointValue>
std::pair<double, double> Solver::liquid_volume_sums(PointValue&& value) {
  auto part = [&](int t) {
    std::size_t b, e;
    chunk(liquid_.size(), t, threads_, b, e);
    double weighted = 0.0, volume = 0.0;
    for (std::size_t p = b; p < e; ++p) {
      const std::optional<double> x = value(p);
      if (!x) continue;
      weighted += liquid_.volume[p] * *x;
      volume += liquid_.volume[p];
    }
    slots_[t].sum[0] = weighted;
    slots_[t].sum[1] = volume;
  };
  if (threads_ == 1) {
    part(0);
  } else {
#pragma omp parallel num_threads(threads_)
    part(omp_get_thread_num());
  }
  double weighted = 0.0, volume = 0.0;
  for (const auto& slot : slots_) {
    weighted += slot.sum[0];
    volume += slot.sum[1];
  }
  return {weighted, volume};
}

template <class G>
void Solver::relax_pressure(const G& grid) {
  const int nn = nn_;
  LiquidPoints& lp = liquid_;
  const long np = static_cast<long>(lp.size());
  scatter(2, [&](double* acc, int t, int T) {
    std::size_t b, e;
    chunk(lp.size(), t, T, b, e);
    Stencil st{};
    for (std::size_t p = b; p < e; ++p) {
      if (!locate<G, ShapeKind::linear>(grid, 1, p, st)) continue;
      const double V = lp.volume[p], Vp = V * lp.pressure[p];
      for (int k = 0; k < st.count; ++k) {
        acc[st.node[k]] += st.N[k] * Vp;
        acc[nn + st.node[k]] += st.N[k] * V;
      }
    }
  });
  const double alpha = 1.0 - std::exp(-dt_ / options_.pressure_relaxation_time);
  double* change = pressure_change_.data();
  const auto [sum, volume] = liquid_volume_sums([&](std::size_t p) -> std::optional<double> {
    Stencil st{};
    change[p] = 0.0;
    if (!locate<G, ShapeKind::linear>(grid, 1, p, st)) return std::nullopt;
    double avg = 0.0, w = 0.0;
    for (int k = 0; k < st.count; ++k) {
      const int a = st.node[k];
      if (acc_[nn + a] > 0.0) {
        avg += st.N[k] * acc_[a] / acc_[nn + a];
        w += st.N[k];
      }
    }
    if (w > 0.0) change[p] = -alpha * (lp.pressure[p] - avg / w);
    return change[p];
  });
  const double mean = volume > 0.0 ? sum / volume : 0.0;
#pragma omp parallel for schedule(static) num_threads(threads_) if (threads_ > 1)
  for (long p = 0; p < np; ++p) lp.pressure[p] += change[p] - mean;
}

void Solver::move_points() {
#pragma omp parallel num_threads(threads_) if (threads_ > 1)
  for (int phase = 0; phase < 2; ++phase) {
    PointFields& pts =
        phase == 0 ? static_cast<PointFields&>(solid_) : static_cast<PointFields&>(liquid_);
    const long n = static_cast<long>(pts.size());
    const double* dx = displacement_x_[phase].data();
    const double* dy = displacement_y_[phase].data();
#pragma omp for schedule(static) nowait
    for (long p = 0; p < n; ++p) {
      pts.x[p] += dx[p];
      pts.y[p] += dy[p];
    }
  }
}

void Solver::refresh_liquid_state() {
  // Volume, viscous stress and drag of the liquid points from p, n and L (no time increment).
  const double K = liquid_options_.bulk_modulus, rho0 = liquid_options_.density;
  for (std::size_t p = 0; p < liquid_.size(); ++p) {
    const double n = liquid_.porosity[p];
    liquid_.volume[p] = liquid_.mass[p] / (n * rho0 * std::exp(liquid_.pressure[p] / K));
    liquid_.drag[p] = drag_at(n, static_cast<long>(p));
  }
}

void Solver::constitutive_update(bool move) {
  const double dt = dt_;
  // Solid: one call per material over its range, then volume and porosity.
  StressUpdateView view{solid_.Lxx.data(),
                        solid_.Lxy.data(),
                        solid_.Lyx.data(),
                        solid_.Lyy.data(),
                        solid_.porosity.data(),
                        solid_.temperature.data(),
                        solid_.sxx.data(),
                        solid_.syy.data(),
                        solid_.szz.data(),
                        solid_.sxy.data(),
                        threads_,
                        options_.material_conductivity ? point_conductivity_.data() : nullptr,
                        solid_.x.data(),
                        solid_.y.data(),
                        solid_.volume.data()};
  for (auto& m : materials_) m->update_stress(view, dt);
  const long ns = static_cast<long>(solid_.size());
  const long nl = static_cast<long>(liquid_.size());
  const double K = liquid_options_.bulk_modulus, rho0 = liquid_options_.density;
  const bool viscous = liquid_options_.viscosity > 0.0;
  double* rate = volumetric_rate_.data();
  // The pore pressure needs the volumetric rate of all liquid points first only when it is
  // cell-averaged or its mean removed; otherwise each point uses its own, in the same pass.
  const bool rate_pass = options_.liquid_volumetric_smoothing || options_.closed_domain ||
                         options_.pressure_relaxation_time > 0.0;
  // Per point; true when the point holds a non-finite or non-positive value.
  auto solid_point = [&](long p) {
    // dV/V = tr(D) dt (plane strain); grains incompressible: n = 1 - V_s / V.
    solid_.volume[p] *= 1.0 + dt * (solid_.Lxx[p] + solid_.Lyy[p]);
    solid_.porosity[p] = 1.0 - solid_.solid_volume[p] / solid_.volume[p];
    const double check = solid_.sxx[p] + solid_.syy[p] + solid_.sxy[p] + solid_.vx[p] +
                         solid_.vy[p] + solid_.x[p] + solid_.y[p];
    if (move) {
      solid_.x[p] += displacement_x_[0][p];
      solid_.y[p] += displacement_y_[0][p];
    }
    return !std::isfinite(check) || !(solid_.volume[p] > 0.0);
  };
  // Volumetric rate of the mixture seen by the liquid: n tr(D_L) + (1 - n) tr(D_S).
  auto liquid_rate = [&](long p) {
    const double n = liquid_.porosity[p];
    rate[p] = n * (liquid_.Lxx[p] + liquid_.Lyy[p]) + (1.0 - n) * div_solid_[p];
  };
  auto liquid_point = [&](long p) {
    const double n = liquid_.porosity[p];
    const double tr_l = liquid_.Lxx[p] + liquid_.Lyy[p];
    // Storage equation of the double-point formulation (incompressible grains):
    //   dp = -(K_w / n) [ n tr(D_L) + (1 - n) tr(D_S) ] dt
    liquid_.pressure[p] -= dt * (K / n) * rate[p];
    // Mixture volume the point stands for: V = m / (n ρ_w), ρ_w = ρ_w0 exp(p / K_w).
    liquid_.volume[p] = liquid_.mass[p] / (n * rho0 * std::exp(liquid_.pressure[p] / K));
    if (viscous) {
      const double eta = viscosity_at(1.0 - n);
      const double third = tr_l / 3.0;
      liquid_.txx[p] = 2.0 * eta * (liquid_.Lxx[p] - third);
      liquid_.tyy[p] = 2.0 * eta * (liquid_.Lyy[p] - third);
      liquid_.tzz[p] = -2.0 * eta * third;
      liquid_.txy[p] = eta * (liquid_.Lxy[p] + liquid_.Lyx[p]);
    }
    liquid_.drag[p] = drag_at(n, static_cast<long>(p));
    const double check = liquid_.pressure[p] + liquid_.txy[p] + liquid_.vx[p] + liquid_.vy[p] +
                         liquid_.x[p] + liquid_.y[p];
    if (move) {
      liquid_.x[p] += displacement_x_[1][p];
      liquid_.y[p] += displacement_y_[1][p];
    }
    return !std::isfinite(check);
  };
  long bad_solid = -1, bad_liquid = -1;
  // One parallel region for both phases (no barrier between the loops: they share nothing).
#pragma omp parallel num_threads(threads_) if (threads_ > 1) reduction(max : bad_solid, bad_liquid)
  {
#pragma omp for schedule(static) nowait
    for (long p = 0; p < ns; ++p) {
      if (solid_point(p)) bad_solid = std::max(bad_solid, p);
    }
#pragma omp for schedule(static) nowait
    for (long p = 0; p < nl; ++p) {
      liquid_rate(p);
      if (!rate_pass && liquid_point(p)) bad_liquid = std::max(bad_liquid, p);
    }
  }
  if (nl > 0 && rate_pass) {
    const int nn = nn_;
    if (options_.liquid_volumetric_smoothing) {
      // Cell average of the volumetric rate (volume-weighted over the liquid points of each
      // cell, cells keyed by their first node): removes the checkerboard pressure modes of
      // equal-order velocity/pressure interpolation (Anura3D's strain smoothing; Mast et al.
      // 2012).
      scatter(2, [&](double* acc, int t, int T) {
        std::size_t b, e;
        chunk(static_cast<std::size_t>(nl), t, T, b, e);
        for (std::size_t p = b; p < e; ++p) {
          acc[liquid_cell_[p]] += liquid_.volume[p] * rate[p];
          acc[nn + liquid_cell_[p]] += liquid_.volume[p];
        }
      });
    }
    // The cell sums live in acc_ only until the next scatter: relax_pressure scatters its own
    // nodal sums into acc_, so every point takes its cell-averaged rate into its own slot of
    // `rate` (volumetric_rate_) before that.
    bool smoothed = !options_.liquid_volumetric_smoothing;
    auto smooth = [&](long p) { rate[p] = acc_[liquid_cell_[p]] / acc_[nn + liquid_cell_[p]]; };
    double mean_rate = 0.0;
    if (options_.closed_domain) {
      // Volume-weighted mean rate (smoothing the rate of each point on the way).
      const auto [rate_volume, volume] =
          liquid_volume_sums([&](std::size_t p) -> std::optional<double> {
            if (!smoothed) smooth(static_cast<long>(p));
            return rate[p];
          });
      smoothed = true;
      mean_rate = rate_volume / volume;
    }
    if (options_.pressure_relaxation_time > 0.0) {
      if (!smoothed) {
#pragma omp parallel for schedule(static) num_threads(threads_) if (threads_ > 1)
        for (long p = 0; p < nl; ++p) smooth(p);
        smoothed = true;
      }
      std::visit([&](const auto& g) { relax_pressure<std::decay_t<decltype(g)>>(g); }, grid_);
    }
#pragma omp parallel for schedule(static) num_threads(threads_) if (threads_ > 1) \
    reduction(max                                                                 \
              : bad_liquid)
    for (long p = 0; p < nl; ++p) {
      if (options_.closed_domain) {
        rate[p] -= mean_rate;
      } else if (!smoothed) {
        smooth(p);
      }
      if (liquid_point(p)) bad_liquid = std::max(bad_liquid, p);
    }
    if (options_.liquid_volumetric_smoothing && bad_liquid < 0) cell_constant_pressure();
  }
  if (bad_solid >= 0) {
    const long p = bad_solid;
    const bool bad_volume = !(solid_.volume[p] > 0);
    const bool bad_stress = !std::isfinite(solid_.sxx[p] + solid_.syy[p] + solid_.sxy[p]);
    const char* var = bad_volume ? "volume" : bad_stress ? "stress" : "velocity/position";
    const double val = bad_volume ? solid_.volume[p] : bad_stress ? solid_.sxx[p] : solid_.vx[p];
    throw SolverFailure(step_ + 1, fmt::format("solid point {}", p), var, val,
                        "non-finite or non-positive value");
  }
  if (bad_liquid >= 0) {
    throw SolverFailure(step_ + 1, fmt::format("liquid point {}", bad_liquid), "pressure",
                        liquid_.pressure[bad_liquid], "non-finite value");
  }
}

// The pressure work of the internal force, -Σ_p V_p p_p tr(D)_p, and the storage equation driven
// by the cell-averaged rate, dp_p = -(K_w/n) <tr D>_cell dt, are adjoint (the stored energy
// Σ V p²/2K_w changes by exactly the pressure work) only when p is uniform within each cell:
//   Σ_{p∈c} V_p p_p <tr D>_c = p_c Σ_{p∈c} V_p tr(D)_p   iff   p_p = p_c.
// A within-cell spread of p (round-off, points that crossed a cell face) is invisible to the
// smoothed rate but drives the nodes, so the discrete operator is no longer skew-adjoint; on the
// polar grid in Couette flow an azimuthal mode of wavenumber about 0.45 × cells_theta grew from
// round-off with an e-folding time of 0.17 s (10 × 64 cells) and reached 0.3 V at 7 s. Making the
// pressure constant per cell after each update (its volume-weighted mean; the cell-constant
// pressure of the Q1-P0 element, Hughes 2000 ch. 4, carried by the points as in the strain
// smoothing of Mast et al. 2012) restores the adjoint pair: the mode stays at round-off.
void Solver::cell_constant_pressure() {
  const long nl = static_cast<long>(liquid_.size());
  const int nn = nn_;
  scatter(2, [&](double* acc, int t, int T) {
    std::size_t b, e;
    chunk(static_cast<std::size_t>(nl), t, T, b, e);
    for (std::size_t p = b; p < e; ++p) {
      acc[liquid_cell_[p]] += liquid_.volume[p] * liquid_.pressure[p];
      acc[nn + liquid_cell_[p]] += liquid_.volume[p];
    }
  });
  const double K = liquid_options_.bulk_modulus, rho0 = liquid_options_.density;
#pragma omp parallel for schedule(static) num_threads(threads_) if (threads_ > 1)
  for (long p = 0; p < nl; ++p) {
    liquid_.pressure[p] = acc_[liquid_cell_[p]] / acc_[nn + liquid_cell_[p]];
    // V = m / (n ρ_w), ρ_w = ρ_w0 exp(p / K_w), with the cell's pressure.
    liquid_.volume[p] =
        liquid_.mass[p] / (liquid_.porosity[p] * rho0 * std::exp(liquid_.pressure[p] / K));
  }
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
