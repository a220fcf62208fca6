// Explicit two-phase double-point MPM in 2D plane strain (docs/mpm.md has the algorithm, the
// equations and their sources). Solid points carry the effective stress σ' of a registered
// material; liquid points carry the pore pressure p of a compressible liquid (bulk modulus K_w)
// and a viscous stress 2 η(ν) dev D_L. Momentum is balanced per phase on the nodes, with drag and
// the pressure-gradient (buoyancy) interaction split by the nodal porosity. A run with no liquid
// points runs the same code and skips every liquid loop.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "continuum/model/closures.hpp"
#include "continuum/mpm/cartesian_grid.hpp"
#include "continuum/mpm/material_points.hpp"
#include "continuum/mpm/polar_grid.hpp"
#include "continuum/mpm/solid_material.hpp"
#include "core/numerical_failure.hpp"

namespace granflow::mpm {

enum class UpdateScheme { usl, musl };  // stress update last / modified USL (Sulsky et al. 1995)
enum class DragIntegration { semi_implicit, explicit_euler };
enum class DragLaw { darcy, closure };          // β = n² ρ_w g / k_D, or model::drag_coefficient
enum class ViscosityLaw { constant, mixture };  // η0, or model::mixture_viscosity(ν)
enum class Phase { solid, liquid };
enum class Frame { xy, polar };  // velocity conditions in (x, y) or (r, θ) components

struct LiquidOptions {
  double density = 1000.0;      // ρ_w at p = 0, kg/m³
  double bulk_modulus = 2.2e9;  // K_w, Pa (a reduced value is a reported modelling choice)
  double viscosity = 0.0;       // η0, Pa s (Newtonian part; 0 = inviscid)
  ViscosityLaw viscosity_law = ViscosityLaw::constant;
  DragLaw drag_law = DragLaw::darcy;
  double hydraulic_conductivity = 1e-3;  // k_D for the Darcy law, m/s
  double darcy_gravity = 9.81;           // g in γ_w = ρ_w g of the Darcy law, m/s²
  model::LiquidParameters closure;       // for DragLaw::closure / ViscosityLaw::mixture
  double grain_diameter = 1e-3;          // d of the closures, m
};

struct SolverOptions {
  ShapeKind shape = ShapeKind::linear;
  UpdateScheme scheme = UpdateScheme::musl;
  double flip = 1.0;  // FLIP fraction of the point velocity update (1 FLIP, 0 PIC)
  // PIC relaxation time t_PIC, s (> 0 replaces `flip`, which must then stay 1): the per-step
  // FLIP fraction is exp(−Δt/t_PIC), so the points relax towards the grid field at the rate
  // 1/t_PIC per unit TIME whatever Δt is (docs/mpm.md, "FLIP/PIC blend").
  double pic_relaxation_time = 0.0;
  double local_damping = 0.0;               // Cundall local damping coefficient α in [0, 1)
  double gravity_x = 0.0, gravity_y = 0.0;  // m/s²
  double cfl_factor = 0.5;                  // dt = factor x min(critical steps)
  double fixed_dt = 0.0;                    // > 0: use this dt (the critical one is still reported)
  double mass_scaling = 1.0;  // inertial masses x this factor (gravity keeps the true mass)
  DragIntegration drag_integration = DragIntegration::semi_implicit;
  double gimp_half_length_x = 0.0, gimp_half_length_y = 0.0;  // GIMP particle half-sizes, m
  // Conduction of the granular temperature among solid points (seed section 5): constant
  // conductivity κ_T of q = -κ_T ∇T, kg/(m s); 0 = T only carried (unless the next option).
  double temperature_conductivity = 0.0;
  // Conduct T with the conductivity each material reports per point (StressUpdateView::
  // conductivity; the multi-regime material: ρ_p d f4 T^½) instead of the constant above.
  bool material_conductivity = false;
  bool liquid_volumetric_smoothing = false;  // cell-averaged rate, cell-constant p (linear)
  // t_p, s (> 0: on; linear shapes): the pore pressure relaxes towards its nodal average at the
  // rate 1/t_p, which removes the cell-to-cell checkerboard of p (Solver::relax_pressure).
  double pressure_relaxation_time = 0.0;
  // Closed rigid container (every boundary impermeable and fixed normally, e.g. the rheometer):
  // ∫ div(mixture flux) dV = 0 exactly, so the volume-weighted mean of the liquid points'
  // volumetric rate, which point quadrature leaves non-zero, is removed before dp is formed.
  bool closed_domain = false;
  long dt_update_interval = 50;  // recompute the critical step every so many steps
  int threads = 0;               // 0: OpenMP default
};

// Critical time steps (before the CFL factor) of each mechanism, s; +inf when absent.
struct TimeStepLimits {
  double wave = 0, viscous = 0, drag = 0, conduction = 0;
  double critical() const;
};

using Grid = std::variant<CartesianGrid, PolarGrid>;

// Nodal fields of the last step (for output and tests).
struct NodeFields {
  std::vector<double> mass_solid, mass_liquid;  // true (unscaled) nodal masses, kg per m
  std::vector<double> vx_solid, vy_solid, vx_liquid, vy_liquid;  // m/s
  std::vector<double> porosity;
};

class Solver {
 public:
  Solver(Grid grid, SolverOptions options, LiquidOptions liquid = {});

  const Grid& grid() const { return grid_; }
  const SolverOptions& options() const { return options_; }
  const LiquidOptions& liquid_options() const { return liquid_options_; }
  SolidPoints& solid() { return solid_; }
  LiquidPoints& liquid() { return liquid_; }
  const SolidPoints& solid() const { return solid_; }
  const LiquidPoints& liquid() const { return liquid_; }

  // Materials: solid points with material index k must be contiguous; initialize() checks it.
  int add_material(std::unique_ptr<SolidMaterial> material);
  const SolidMaterial& material(int k) const { return *materials_[k]; }
  int materials() const { return static_cast<int>(materials_.size()); }
  std::vector<std::pair<std::string, std::vector<double>*>> material_state(int k) {
    return materials_[k]->state();
  }

  // Prescribe a velocity component (0: x or r, 1: y or θ) of a phase at a node, reaching
  // `value` linearly over `ramp_time` (0: at once).
  void fix_velocity(Phase phase, int node, Frame frame, int component, double value,
                    double ramp_time = 0.0);

  // A constant force on a node of a phase (N per m thickness): tractions on grid-aligned
  // boundaries (traction x tributary length), valid while the surface stays on that grid line.
  void add_nodal_force(Phase phase, int node, double fx, double fy);

  // After the points are filled: checks, material ranges, porosity, drag, the time step.
  // (Moving points by hand between initialize() and the first step needs another initialize():
  // the points' stencils are cached.)
  void initialize();
  void step();
  void run_steps(long n) {
    for (long i = 0; i < n; ++i) step();
  }

  double dt() const { return dt_; }
  // FLIP fraction of the next step's point velocity update: `flip`, or exp(−Δt/t_PIC).
  double flip_fraction() const;
  double time() const { return time_; }
  long steps() const { return step_; }
  const TimeStepLimits& limits() const { return limits_; }
  const NodeFields& nodes() const { return nodes_; }
  int threads() const { return threads_; }

  // Diagnostics.
  double total_mass(Phase phase) const;
  void total_momentum(Phase phase, double& px, double& py) const;
  int grid_nodes() const;

  // Restart: the state that is not in the point arrays.
  void set_clock(double time, long step, double dt) {
    time_ = time;
    step_ = step;
    dt_ = dt;
    cache_[0].valid = cache_[1].valid = false;  // positions were restored
  }

 private:
  // Defined by concern: solver.cpp (construction, initialize, diagnostics), solver_maps.cpp (the
  // step, P2G/G2P), solver_nodes.cpp (nodal balance, velocity conditions), solver_constitutive.cpp
  // (stresses, storage equation, pressure smoothing), solver_temperature.cpp, solver_time_step.cpp,
  // solver_reduction.cpp; the templates more than one of them use are in solver_internal.hpp.
  template <class G, ShapeKind S>
  void step_impl(const G& grid);
  // The grid part of a step is one parallel region; each piece below is run by thread t on its
  // share (points: a fixed contiguous chunk per thread; nodes: a fixed contiguous share), the
  // pieces separated by barriers (docs/mpm.md, "Threads").
  template <class G, ShapeKind S>
  void map_first_part(const G& grid, int t);  // P2G of mass, momentum, forces, porosity, drag
  template <class G, ShapeKind S>
  void update_points_part(const G& grid, int t, bool remap);  // G2P (+ P2G of m v for MUSL)
  template <class G, ShapeKind S>
  void velocity_gradients_part(const G& grid, int t, bool liquid_extras);
  void solve_nodes(int begin, int end);  // nodal momentum balance on nodes [begin, end)
  void remap_nodes(int begin, int end);  // MUSL nodal velocities on nodes [begin, end)
  // Whole-grid versions (own parallel region) for initialize().
  template <class G, ShapeKind S>
  void map_first(const G& grid);
  template <class G, ShapeKind S>
  void velocity_gradients(const G& grid, bool liquid_extras);
  // Store point p's velocity gradient and, for liquid points (`extras`), the solid divergence
  // tr(D_S) and the porosity interpolated there (shared by the USL G2P and velocity_gradients).
  void store_gradient(PointFields& pts, long p, double Lxx, double Lxy, double Lyx, double Lyy,
                      bool extras, double div_s, double n_at, int first_node);
  // Stress, volume, porosity, pore pressure and the finite checks; with `move`, also the
  // positions (x += Δx of the step) in the same pass. In pieces (solver_constitutive.cpp):
  // constitutive_points on every thread (inside the step's parallel region when
  // materials_in_step_region), then finish_constitutive.
  void constitutive_update(bool move);
  void constitutive_points(int t, bool move, bool materials);
  void finish_constitutive(bool move, bool materials);
  void liquid_smoothing_part(int t, bool move);
  bool liquid_smoothing_in_region() const;
  StressUpdateView stress_view();
  bool materials_in_step_region() const;
  bool liquid_rate_pass() const;
  struct LiquidPass;
  template <class G, ShapeKind S>
  void conduct_temperature(const G& grid);
  template <class G, ShapeKind S>
  long conduct_part(const G& grid, int t);
  void throw_if_negative_temperature(long negative) const;
  // Scatter with per-thread node buffers in its own parallel region (conduction, the cell-averaged
  // rate, the pressure relaxation, the cell-constant pressure).
  template <class Body>
  void scatter(int fields, Body&& body);
  // Thread t's node accumulator for `fields` fields, all zero: acc_ itself on one thread, else
  // its buffer in scratch_ (only the span it dirtied last time is cleared). With more than one
  // thread, acc_ is also zeroed on the thread's share of the nodes (node_share): a thread may add
  // a point whose whole stencil lies in its own share straight into acc_ (owner_writes), since
  // no other thread writes there before the reduction.
  double* scatter_buffer(int t, int fields);
  // [begin, end) and [0, wrap_end) of thread t's buffer hold its scatter (the second: the polar
  // grid's first rays, reached across the θ = 0 seam; 0 = none)
  void mark_dirty(int t, int fields, int begin, int end, int wrap_end = 0);
  // acc_ on thread t's share of the nodes += the per-thread buffers, in thread order.
  void reduce_part(int fields, int t);
  // The stencil of point p of a phase (0 solid, 1 liquid) at the start of the step; on the polar
  // grid (a closed-form location, dearer than the Cartesian one) located once per step, then
  // cached.
  template <class G, ShapeKind S>
  bool locate(const G& grid, int phase, std::size_t p, Stencil& st);
  // Linear shapes on either grid (solver_quad.cpp): the same three pieces on fixed 2 x 2
  // stencils held as two rows of two adjacent nodes, each row one packed vector; the points of
  // the thread's chunk are located once per step (locate_cells) and kept in cells_ (Cartesian)
  // or cache_ (polar).
  template <class G>
  void map_first_quad(const G& grid, int t);
  template <class G>
  void update_points_quad(const G& grid, int t, bool remap);
  template <class G>
  void velocity_gradients_quad(const G& grid, int t, bool liquid_extras);
  // Locate points [b, e) of a phase into cells_ in one vectorised pass (outside: node -1).
  void locate_cells(const CartesianGrid& grid, int phase, std::size_t b, std::size_t e);
  // Polar: locate points [b, e) of a phase into cache_ (outside: node[0] = -1).
  void locate_cells(const PolarGrid& grid, int phase, std::size_t b, std::size_t e);
  void solve_porosity_only();
  void refresh_liquid_state();
  template <class G>
  void relax_pressure(const G& grid);  // pore pressure towards its nodal average (t_p)
  void store_start_nodes();       // nodal fields of the start, for output before the first step
  void cell_constant_pressure();  // liquid p ← its cell mean (with the smoothed rate)
  // Σ_p V_p x_p and Σ_p V_p over the liquid points whose value(p) gives an x_p (per-point work
  // may happen inside value); fixed chunks per thread added in thread order, so the result is
  // reproducible for a thread count (unlike an OpenMP reduction's arrival order).
  template <class PointValue>
  std::pair<double, double> liquid_volume_sums(PointValue&& value);
  void move_points();                      // x += Δx of the step, at its end
  void move_points_part(int t);            // the same for thread t's chunks
  void throw_if_lost() const;              // a point that the last map found outside the grid
  double viscosity_at(double nu) const;    // η(ν)
  double drag_at(double n, long p) const;  // β(n) of liquid point p (and |u_L - u_S| if Ergun)
  void apply_conditions(Phase phase, double* vx, double* vy, int begin, int end) const;
  TimeStepLimits compute_limits() const;
  void update_dt();
  double node_angle(int n) const;
  [[noreturn]] void lost_point(Phase phase, long index) const;

  Grid grid_;
  SolverOptions options_;
  LiquidOptions liquid_options_;
  SolidPoints solid_;
  LiquidPoints liquid_;
  std::vector<std::unique_ptr<SolidMaterial>> materials_;

  struct Conditions {
    std::vector<std::uint8_t> mask;  // bit c: component c fixed
    std::vector<std::uint8_t> frame;
    std::vector<double> value0, value1, ramp;
    std::vector<double> cos, sin;  // cos θ, sin θ of a node with an (r, θ) condition
    std::vector<int> list;         // nodes with a condition
  } conditions_[2];

  struct NodalForce {
    int phase, node;
    double fx, fy;
  };
  std::vector<NodalForce> nodal_forces_;

  // Every grid operation of a step uses the shape functions of the start-of-step configuration
  // (Sulsky, Zhou & Schreyer 1995; Nairn 2003): the point displacements of the step are kept
  // here and applied at its end. On the polar grid the stencils are also cached for the step.
  std::vector<double> displacement_x_[2], displacement_y_[2];
  // Cartesian grid, linear shapes: the cell of each point (node index of its lower-left corner,
  // -1 outside the grid) and its local coordinates ξ, η in [0, 1], for the step's grid part.
  struct CellCache {
    std::vector<int> node;
    std::vector<double> xi, eta;
    double inv_hx = 0, inv_hy = 0;
  } cells_[2];
  // Polar grid: the stencil of each point (node[0] = -1: outside the grid) and its sector at the
  // last location (the first guess of the next).
  struct StencilCache {
    std::vector<QuadStencil> quad;
    std::vector<int> sector;
    bool valid = false;
  } cache_[2];

  int nn_ = 0;
  int threads_ = 1;
  std::vector<double> acc_;      // reduced nodal accumulators, field-major
  std::vector<double> scratch_;  // per-thread accumulators (threads > 1)
  // Per-thread bookkeeping of the parallel step, one cache line each (no false sharing).
  struct alignas(64) ThreadSlot {
    // non-zero part of its buffer: [dirty_begin, dirty_end) and [0, dirty_wrap_end) (disjoint)
    int dirty_fields = 0, dirty_begin = 0, dirty_end = 0, dirty_wrap_end = 0;
    long lost[2] = {-1, -1};  // first point of its chunk, per phase, found outside the grid
    long bad[2] = {-1, -1};   // last point of its chunk, per phase, with a non-finite value
    long cold = -1;           // last point of its chunk whose conducted T is negative
    double sum[2] = {0, 0};   // partial sums of a reduction over its chunk
  };
  std::vector<ThreadSlot> slots_;
  // nodal solution
  std::vector<double> asx_, asy_, alx_, aly_, porosity_;
  std::vector<double> div_solid_;       // tr(D_S) at the liquid points
  bool forchheimer_ = false;            // Ergun's inertial drag term is active
  std::vector<double> relative_speed_;  // |u_L - u_S| at the liquid points (Ergun only)
  std::vector<double> volumetric_rate_;
  std::vector<double> pressure_change_;  // Δp of relax_pressure per liquid point
  std::vector<int> liquid_cell_;         // first node of the cell holding each liquid point
  std::vector<double> temperature_gradient_x_, temperature_gradient_y_;
  std::vector<double> point_conductivity_;  // κ_T per solid point (material_conductivity)
  std::vector<double> nodal_temperature_, heat_capacity_;  // T_a and C_a = Σ N (3/2) m of the nodes
  NodeFields nodes_;

  double dt_ = 0, time_ = 0;
  long step_ = 0;
  TimeStepLimits limits_;
  double mass_floor_ = 0;
  bool initialized_ = false;
};

}  // namespace granflow::mpm
