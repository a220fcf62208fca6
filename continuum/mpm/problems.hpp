// The verification and benchmark problems, built from a few numbers so that the tests, the `mpm`
// case kind and the benchmark all run exactly the same set-up.
#pragma once

#include <memory>

#include "continuum/mpm/solver.hpp"

namespace granflow::mpm {

// Elastic column on a fixed base with roller sides, under gravity (MPM-1 with the benchmark's
// numbers). Oedometric: σ_yy = -ρ g (H - y0), σ_xx = σ_zz = ν/(1-ν) σ_yy at rest.
struct ColumnSpec {
  double width = 0.2, height = 1.0, cell = 0.05;
  int points_per_cell = 2;  // per direction
  int empty_rows = 2;       // grid rows above the column
  double density = 2000.0, young_modulus = 1.0e6, poisson_ratio = 0.3, gravity = 9.81;
  SolverOptions options;
};
// The solid is `material` (from the case's `solid.material`), or when none is given the linear
// elastic material of the spec's E, ν and ρ (the exact solution's constants).
std::unique_ptr<Solver> make_elastic_column(const ColumnSpec& spec,
                                            std::unique_ptr<SolidMaterial> material = nullptr);
struct ColumnError {
  double vertical_stress = 0;    // RMS |σ_yy - σ_yy,exact| / (ρ g H) over the points
  double horizontal_stress = 0;  // RMS |σ_xx - σ_xx,exact| / (ρ g H)
  double base_stress = 0;        // mean σ_yy of the bottom row of points, Pa
};
ColumnError column_error(const Solver& solver, const ColumnSpec& spec);

// Terzaghi consolidation column (1D; MPM-2 with the benchmark's numbers): drained top, impermeable
// fixed base, roller sides, total load q on top as nodal tractions on the solid. One liquid point
// per solid point. With `undrained_start` the run starts from the undrained state at t = 0+
// (p = p0, σ'_yy = -(q - p0) everywhere), the initial condition of Terzaghi's solution;
// otherwise the load is applied suddenly to an unstressed column (waves, the benchmark).
struct TerzaghiSpec {
  double width = 0.1, height = 1.0, cell = 0.1;
  int points_per_cell = 2;
  int empty_rows = 2;
  double young_modulus = 1.0e7, poisson_ratio = 0.0, porosity = 0.3;
  double grain_density = 2650.0, liquid_density = 1000.0, bulk_modulus = 1.0e8;
  double hydraulic_conductivity = 1.0e-3, gravity_for_darcy = 9.81;
  // Drag from the granflow closure (model::drag_coefficient, β = η0 n / κ(ν)) instead of Darcy's
  // k_D; the analytic solution then uses the equivalent k_D = n γ_w κ / η0.
  bool closure_drag = false;
  double grain_diameter = 1e-3;
  model::LiquidParameters closure;
  double load = 1.0e4;
  double gravity = 0.0;  // m/s² (0 for Terzaghi; > 0 for the hydrostatic/buoyancy check)
  bool undrained_start = true;
  SolverOptions options;
};
// The skeleton is `material`, or the linear elastic one of the spec (as make_elastic_column).
std::unique_ptr<Solver> make_terzaghi(const TerzaghiSpec& spec,
                                      std::unique_ptr<SolidMaterial> material = nullptr);
struct TerzaghiConstants {
  double constrained_modulus, p0, cv, final_settlement;
  double hydraulic_conductivity;  // k_D (given, or equivalent to the closure drag)
};
TerzaghiConstants terzaghi_constants(const TerzaghiSpec& spec);
// RMS of (p - p_exact) over the liquid points inside the layer, divided by p0.
double terzaghi_pressure_error(const Solver& solver, const TerzaghiSpec& spec);
// Saturated column at rest under gravity (load 0): RMS errors against the hydrostatic pore
// pressure p = ρ_w g (H - y) and the buoyant effective stress σ'_yy = -(1-n)(ρ_s-ρ_w) g (H - y0),
// both divided by ρ_w g H.
void hydrostatic_error(const Solver& solver, const TerzaghiSpec& spec, double& pressure,
                       double& effective_stress);
// Mean settlement of the top row of solid points, m (positive down), and its exact value.
void terzaghi_settlement(const Solver& solver, const TerzaghiSpec& spec, double& computed,
                         double& exact);

// Couette flow of the liquid alone in an annulus (polar O-grid): inner wall fixed, outer wall at
// v_θ = V; Newtonian viscosity η; compressible liquid of bulk modulus K.
struct CouetteSpec {
  double inner_radius = 1.0, outer_radius = 2.0;
  int cells_r = 10, cells_theta = 64;
  int points_per_cell = 2;
  double density = 1000.0, viscosity = 1000.0, bulk_modulus = 1.0e6, wall_velocity = 1.0;
  SolverOptions options;
};
std::unique_ptr<Solver> make_couette(const CouetteSpec& spec);
// RMS of (v_θ - v_θ,exact) at the interior grid nodes, divided by V; also the RMS radial
// velocity / V.
void couette_error(const Solver& solver, const CouetteSpec& spec, double& tangential,
                   double& radial);
// Same for given nodal velocities (e.g. averaged over a time window to remove acoustic ringing).
void couette_error(const Solver& solver, const CouetteSpec& spec,
                   const std::vector<double>& vx_node, const std::vector<double>& vy_node,
                   double& tangential, double& radial);

}  // namespace granflow::mpm
