#include "continuum/mpm/mpm_kind.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "continuum/model/closures.hpp"
#include "continuum/mpm/analytic.hpp"
#include "continuum/mpm/checkpoint.hpp"
#include "continuum/mpm/field_writer.hpp"
#include "continuum/mpm/problems.hpp"
#include "continuum/mpm/restart.hpp"
#include "continuum/mpm/rheometer.hpp"
#include "continuum/multi_regime/model_sections.hpp"
#include "core/interrupt.hpp"

namespace granflow::mpm {

namespace {

// ---- schema -------------------------------------------------------------------------------------

struct NumericsDefaults {
  const char* local_damping = "0.0";
  const char* smoothing = "false";
};

void add_numerics(core::Schema& s, NumericsDefaults d) {
  auto& n = s.section("numerics", "MPM algorithm choices (docs/mpm.md)");
  n.choice("shape", {"linear", "gimp"}, "shape functions (gimp: Cartesian grids only)")
      .default_value("linear");
  n.choice("scheme", {"musl", "usl"}, "update scheme: modified USL or USL").default_value("musl");
  n.number("flip", "1",
           "FLIP fraction of each step's point velocity update (1 FLIP, 0 PIC); 1 when neither "
           "it nor pic_relaxation_time is given")
      .at_least(0)
      .at_most(1);
  n.number("pic_relaxation_time", "s",
           "PIC relaxation time t_PIC instead of flip: per-step FLIP fraction exp(−Δt/t_PIC), "
           "so the PIC damping per unit time does not depend on Δt (docs/mpm.md)")
      .greater_than(0);
  n.number("local_damping", "1", "Cundall local damping coefficient α")
      .default_value(d.local_damping)
      .at_least(0)
      .less_than(1);
  n.number("cfl_factor", "1", "Δt = factor × critical step (CFL over both phases, viscous, drag)")
      .default_value("0.5")
      .greater_than(0)
      .at_most(1);
  n.number("time_step", "s", "fixed Δt (0: from the critical step); the critical one is reported")
      .default_value("0")
      .at_least(0);
  n.number("mass_scaling", "1", "inertial masses × this factor (a reported modelling choice)")
      .default_value("1")
      .at_least(1);
  n.choice("drag_integration", {"semi_implicit", "explicit"},
           "nodal drag: backward Euler in the drag (stable for any β) or explicit Euler "
           "(then Δt also obeys the drag time scale)")
      .default_value("semi_implicit");
  n.boolean("liquid_volumetric_smoothing",
            "cell-averaged volumetric rate and cell-constant liquid pressure (linear shapes)")
      .default_value(d.smoothing);
  n.number("pressure_relaxation_time", "s",
           "t_p: the pore pressure relaxes towards its nodal average at the rate 1/t_p (removes "
           "the cell-to-cell checkerboard of p; 0 = off; linear shapes; docs/mpm.md)")
      .default_value("0")
      .at_least(0);
  n.integer("threads", "OpenMP threads (0: one per 10,000 points, at most OMP_NUM_THREADS)")
      .default_value("0")
      .at_least(0);
  auto& o = s.section("output", "field files and checkpoint");
  o.integer("frames", "HDF5+XDMF field outputs evenly spaced in time, plus t = 0 (0: none)")
      .default_value("10")
      .at_least(0);
  o.boolean("checkpoint", "write checkpoint.h5 (all point arrays and the clock) at the end")
      .default_value("false");
  o.string("restart_from", "checkpoint file to continue from (same case)");
}

core::Schema terzaghi_schema() {
  core::Schema s = core::kind_header(
      "mpm", "terzaghi",
      "Terzaghi 1D consolidation with the two-phase double-point MPM: drained top, impermeable "
      "base, pore pressure isochrones and settlement against the analytic series.");
  auto& g = s.section("geometry", "layer and background grid");
  g.number("height", "m", "layer height H").default_value("1.0").greater_than(0);
  g.number("width", "m", "column width (a multiple of the cell size)")
      .default_value("0.1")
      .greater_than(0);
  g.number("cell", "m", "square cell size h").default_value("0.1").greater_than(0).sweepable();
  g.integer("points_per_cell", "material points per cell and direction (each phase)")
      .default_value("2")
      .at_least(1);
  g.integer("empty_rows", "empty grid rows above the layer (expelled liquid)")
      .default_value("2")
      .at_least(1);
  auto& m = s.section("solid", "solid skeleton (solid points)");
  m.choice("material", {"linear_elastic"}, "constitutive model of the solid points")
      .default_value("linear_elastic");
  m.number("young_modulus", "Pa", "E").default_value("1.0e7").greater_than(0);
  m.number("poisson_ratio", "1", "ν").default_value("0.0").at_least(0).less_than(0.5);
  m.number("porosity", "1", "n").default_value("0.3").greater_than(0).less_than(1);
  m.number("density", "kg/m^3", "grain density ρ_s").default_value("2650").greater_than(0);
  auto& l = s.section("liquid", "pore liquid (liquid points)");
  l.number("density", "kg/m^3", "ρ_w").default_value("1000").greater_than(0);
  l.number("bulk_modulus", "Pa", "K_w (2.2e9 for water; a reduced value is a reported choice)")
      .default_value("1.0e8")
      .greater_than(0);
  l.number("hydraulic_conductivity", "m/s", "Darcy k_D: β = n² ρ_w g / k_D")
      .default_value("1.0e-3")
      .greater_than(0);
  l.number("darcy_gravity", "m/s^2", "g in γ_w = ρ_w g of k_D")
      .default_value("9.81")
      .greater_than(0);
  l.choice("drag_law", {"darcy", "closure"},
           "darcy: β = n² γ_w / k_D; closure: β = η0 n / κ(ν) of model::drag_coefficient (the "
           "REV/DEM closure; the analytic check uses the equivalent k_D = n γ_w κ / η0)")
      .default_value("darcy");
  l.number("viscosity", "Pa s", "η0 (closure drag)").default_value("1.0e-3").greater_than(0);
  l.number("grain_diameter", "m", "d of the permeability closure")
      .default_value("1.0e-3")
      .greater_than(0);
  l.choice("permeability", model::permeability_names(),
           "permeability closure (docs/model/closures.md)")
      .default_value("seed_eq26");
  l.number("sphericity", "1", "A of seed Eq. 26").default_value("1.0").greater_than(0);
  auto& ld = s.section("loading", "surface load");
  ld.number("load", "Pa", "total-stress load q on the top").default_value("1.0e4").greater_than(0);
  ld.boolean("undrained_start",
             "start from the undrained state at t = 0+ (Terzaghi's initial condition); false: "
             "sudden load on an unstressed column")
      .default_value("true");
  auto& r = s.section("run", "duration and checks");
  r.number_list("isochrones", "1",
                "time factors T_v = c_v t / H² of the checked isochrones; the "
                "run ends at the last")
      .default_value("[0.05, 0.2, 0.5]")
      .greater_than(0);
  add_numerics(s, {});
  return s;
}

core::Schema couette_schema() {
  core::Schema s = core::kind_header(
      "mpm", "couette",
      "Couette flow of a Newtonian liquid alone between two cylinders on the polar O-grid: the "
      "steady v_θ = A r + B / r.");
  auto& g = s.section("geometry", "annulus and polar grid");
  g.number("inner_radius", "m", "R1 (fixed wall)").default_value("1.0").greater_than(0);
  g.number("outer_radius", "m", "R2 (moving wall)").default_value("2.0").greater_than(0);
  g.integer("cells_r", "radial cells").default_value("10").at_least(1).sweepable();
  g.integer("cells_theta", "tangential cells").default_value("64").at_least(8).sweepable();
  g.integer("points_per_cell", "points per cell and direction").default_value("2").at_least(1);
  auto& l = s.section("liquid", "liquid points");
  l.number("density", "kg/m^3", "ρ_w").default_value("1000").greater_than(0);
  l.number("viscosity", "Pa s", "Newtonian viscosity η0").default_value("1000").greater_than(0);
  l.number("bulk_modulus", "Pa", "K_w (reduced: a reported choice)")
      .default_value("1.0e6")
      .greater_than(0);
  auto& ld = s.section("loading", "wall motion");
  ld.number("wall_velocity", "m/s", "v_θ of the outer wall").default_value("1.0").greater_than(0);
  auto& r = s.section("run", "duration and checks");
  r.number("end_time", "s", "simulated time").default_value("2.0").greater_than(0);
  r.number("average_from", "s", "grid velocity averaged from this time to the end")
      .default_value("1.5")
      .at_least(0);
  add_numerics(s, {"0.0", "true"});
  return s;
}

core::Schema column_schema() {
  core::Schema s = core::kind_header(
      "mpm", "elastic_column",
      "Elastic column under gravity on a fixed base with roller sides, brought to rest with local "
      "damping: σ_yy = -ρ g (H - y) at the points.");
  auto& g = s.section("geometry", "column and grid");
  g.number("width", "m", "column width").default_value("0.2").greater_than(0);
  g.number("height", "m", "column height H").default_value("1.0").greater_than(0);
  g.number("cell", "m", "square cell size h").default_value("0.05").greater_than(0).sweepable();
  g.integer("points_per_cell", "points per cell and direction").default_value("2").at_least(1);
  g.integer("empty_rows", "empty grid rows above").default_value("2").at_least(1);
  auto& m = s.section("solid", "solid points");
  m.choice("material", {"linear_elastic"}, "constitutive model").default_value("linear_elastic");
  m.number("young_modulus", "Pa", "E").default_value("1.0e6").greater_than(0);
  m.number("poisson_ratio", "1", "ν").default_value("0.3").at_least(0).less_than(0.5);
  m.number("density", "kg/m^3", "ρ").default_value("2000").greater_than(0);
  auto& ld = s.section("loading", "body force");
  ld.number("gravity", "m/s^2", "g").default_value("9.81").greater_than(0);
  auto& r = s.section("run", "duration");
  r.number("end_time", "s", "simulated time").default_value("1.5").greater_than(0);
  add_numerics(s, {"0.3", "false"});
  return s;
}

// ---- reading
// -------------------------------------------------------------------------------------

SolverOptions read_options(const core::Case& c) {
  SolverOptions o;
  o.shape = c.string("numerics.shape") == "gimp" ? ShapeKind::gimp : ShapeKind::linear;
  o.scheme = c.string("numerics.scheme") == "usl" ? UpdateScheme::usl : UpdateScheme::musl;
  if (c.has("numerics.flip")) o.flip = c.number("numerics.flip");
  if (c.has("numerics.pic_relaxation_time"))
    o.pic_relaxation_time = c.number("numerics.pic_relaxation_time");
  o.local_damping = c.number("numerics.local_damping");
  o.cfl_factor = c.number("numerics.cfl_factor");
  o.fixed_dt = c.number("numerics.time_step");
  o.mass_scaling = c.number("numerics.mass_scaling");
  o.drag_integration = c.string("numerics.drag_integration") == "explicit"
                           ? DragIntegration::explicit_euler
                           : DragIntegration::semi_implicit;
  o.liquid_volumetric_smoothing = c.boolean("numerics.liquid_volumetric_smoothing");
  o.pressure_relaxation_time = c.number("numerics.pressure_relaxation_time");
  o.threads = static_cast<int>(c.integer("numerics.threads"));
  return o;
}

void check_common(const core::Case& c) {
  if (c.has("numerics.flip") && c.has("numerics.pic_relaxation_time"))
    c.fail("numerics.pic_relaxation_time",
           "either numerics.flip (per step) or numerics.pic_relaxation_time (per unit time), "
           "not both");
  if (c.boolean("numerics.liquid_volumetric_smoothing") && c.string("numerics.shape") == "gimp")
    c.fail("numerics.liquid_volumetric_smoothing", "false with gimp (cell averaging needs linear)");
  if (c.number("numerics.pressure_relaxation_time") > 0 && c.string("numerics.shape") == "gimp")
    c.fail("numerics.pressure_relaxation_time", "0 with gimp (nodal averaging with linear shapes)");
}

bool multiple(double length, double cell) {
  const double k = length / cell;
  return std::fabs(k - std::round(k)) < 1e-9 * std::max(1.0, k) && std::round(k) >= 1;
}

void check_terzaghi(const core::Case& c) {
  check_common(c);
  if (!multiple(c.number("geometry.height"), c.number("geometry.cell")))
    c.fail("geometry.cell", "a cell size that divides geometry.height");
  if (!multiple(c.number("geometry.width"), c.number("geometry.cell")))
    c.fail("geometry.width", "a multiple of geometry.cell");
}

void check_couette(const core::Case& c) {
  check_common(c);
  if (c.string("numerics.shape") != "linear")
    c.fail("numerics.shape", "linear (the polar grid has linear shape functions only)");
  if (!(c.number("geometry.outer_radius") > c.number("geometry.inner_radius")))
    c.fail("geometry.outer_radius", "a value > geometry.inner_radius");
  if (!(c.number("run.average_from") < c.number("run.end_time")))
    c.fail("run.average_from", "a time < run.end_time");
  // The error is measured at the interior node rings (the two walls are prescribed).
  if (c.integer("geometry.cells_r") < 2)
    c.fail("geometry.cells_r",
           "at least 2 (the velocity error is measured at the interior node rings; one radial "
           "cell has none)");
}

void check_column(const core::Case& c) {
  check_common(c);
  if (!multiple(c.number("geometry.height"), c.number("geometry.cell")))
    c.fail("geometry.cell", "a cell size that divides geometry.height");
  if (!multiple(c.number("geometry.width"), c.number("geometry.cell")))
    c.fail("geometry.width", "a multiple of geometry.cell");
}

// The checkpoint of output.restart_from (continuum/mpm/restart.hpp): KindEntry::check_inputs,
// before the run directory exists (granflow check does not read it), and the run itself.
void terzaghi_inputs(const core::Case& c) {
  if (const auto r = check_restart(c, {"run.isochrones"})) check_terzaghi_restart(c, *r);
}

void couette_inputs(const core::Case& c) {
  if (const auto r = check_restart(c, {"run.average_from"})) check_couette_restart(c, *r);
}

void column_inputs(const core::Case& c) {
  if (const auto r = check_restart(c, {}))
    check_restart_end(c, *r, c.number("run.end_time"), "run.end_time");
}

// ---- running -----------------------------------------------------------------------------------

// The field frames of a whole run: t = 0 and `count` frames evenly spaced up to `end_time`, the
// end of the whole run, whichever segments advance() runs it in (Terzaghi's isochrones). After a
// restart the frames before the checkpoint are the earlier run's: only later ones are written.
// Several frames due within one step are written once.
class FrameSchedule {
 public:
  FrameSchedule(FieldWriter* writer, double end_time, int count, const Solver& s)
      : writer_(count > 0 ? writer : nullptr), end_(end_time), count_(count) {
    skip_due(s);
  }
  void write_initial(const Solver& s) {
    if (writer_ && s.steps() == 0 && !initial_written_) writer_->write(s);
    initial_written_ = true;
  }
  void write_due(core::RunContext& ctx, const Solver& s) {
    if (writer_ && skip_due(s)) {
      writer_->write(s);
      ctx.result.flush();  // result.h5 readable up to this frame even after SIGKILL
    }
  }

 private:
  bool skip_due(const Solver& s) {
    bool due = false;
    for (; next_ <= count_ && s.time() >= end_ * next_ / count_ - 0.5 * s.dt(); ++next_) due = true;
    return due;
  }
  FieldWriter* writer_;
  double end_;
  int count_, next_ = 1;
  bool initial_written_ = false;
};

// Runs the solver to `end_time` (one segment of the run), with its field frames, progress and
// failure translation; `sample` is called after every step. Returns the solver wall time.
template <class Sample>
double advance(core::RunContext& ctx, Solver& s, double end_time, FrameSchedule& frames,
               Sample&& sample) {
  core::Progress progress(ctx.log, "simulated time", end_time);
  const auto start = std::chrono::steady_clock::now();
  try {
    frames.write_initial(s);
    while (s.time() < end_time - 0.5 * s.dt() && !core::interrupted()) {
      s.step();
      sample();
      frames.write_due(ctx, s);
      progress.update(s.time());
    }
  } catch (const SolverFailure& f) {
    throw core::NumericalFailure(f.step, f.point, f.variable, f.value, f.what());
  }
  if (core::interrupted())
    ctx.log->warn("interrupted by {} at step {}, t = {:.6g} s (end time {:g} s)",
                  core::interrupt_name(), s.steps(), s.time(), end_time);
  progress.finish();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void report_setup(core::RunContext& ctx, const Solver& s, const RunHistory& history) {
  const auto& L = history.limits(s);
  ctx.log->info(
      "mpm: {} solid + {} liquid points, {} grid nodes, {} thread(s); Δt = {:.4g} s (critical: "
      "wave {:.4g}, viscous {:.4g}, drag {:.4g} s; factor {:g}{})",
      s.solid().size(), s.liquid().size(), s.grid_nodes(), s.threads(), s.dt(), L.wave, L.viscous,
      L.drag, s.options().cfl_factor, s.options().fixed_dt > 0 ? ", fixed Δt given" : "");
  if (s.options().pic_relaxation_time > 0)
    ctx.log->info("PIC relaxation time {:.4g} s: FLIP fraction exp(−Δt/t_PIC) = {:.6g} per step",
                  s.options().pic_relaxation_time, s.flip_fraction());
  else if (s.options().flip < 1)
    ctx.log->info("FLIP fraction {:g} per step (PIC relaxation time Δt/(−ln flip) = {:.4g} s)",
                  s.options().flip, s.dt() / -std::log(s.options().flip));
  if (s.options().mass_scaling > 1)
    ctx.log->warn("mass scaling × {:g}: inertia is not physical (modelling choice)",
                  s.options().mass_scaling);
  if (s.liquid().size() > 0 && s.liquid_options().bulk_modulus < 2.2e9)
    ctx.log->info(
        "reduced liquid bulk modulus K_w = {:.3g} Pa (water: 2.2e9 Pa), a modelling "
        "choice",
        s.liquid_options().bulk_modulus);
}

void common_summary(core::RunContext& ctx, const Solver& s, const RunHistory& history, double wall,
                    double ms0, double ml0) {
  auto& sum = ctx.summary;
  const double points = static_cast<double>(s.solid().size() + s.liquid().size());
  sum.set("cost.steps", static_cast<double>(s.steps()));
  sum.set("cost.solver_wall_s", wall);
  sum.set("cost.particle_updates_per_s", points * s.steps() / std::max(wall, 1e-9));
  sum.set("mpm.particles_solid", static_cast<double>(s.solid().size()));
  sum.set("mpm.particles_liquid", static_cast<double>(s.liquid().size()));
  sum.set("mpm.dt", s.dt());
  sum.set("mpm.flip_step", s.flip_fraction());
  sum.set("mpm.dt_critical", history.limits(s).critical());
  sum.set("mpm.threads", s.threads());
  sum.set("mpm.mass_scaling", s.options().mass_scaling);
  if (s.liquid().size() > 0) sum.set("mpm.bulk_modulus", s.liquid_options().bulk_modulus);
  sum.set("mass.solid_rel_change",
          ms0 > 0 ? std::fabs(s.total_mass(Phase::solid) - ms0) / ms0 : 0.0);
  sum.set("mass.liquid_rel_change",
          ml0 > 0 ? std::fabs(s.total_mass(Phase::liquid) - ml0) / ml0 : 0.0);
}

// After the summary: its error measures must be numbers (exit 3 naming the one that is not);
// then the checkpoint with the run's history (continuum/mpm/restart.hpp).
void finish_output(core::RunContext& ctx, const Solver& s, const RunHistory& history,
                   std::initializer_list<std::string_view> error_measures) {
  check_error_measures(ctx, s.steps(), error_measures);
  write_run_checkpoint(ctx, s, history);
}

std::unique_ptr<FieldWriter> field_writer(core::RunContext& ctx) {
  if (ctx.run_case.integer("output.frames") <= 0) return nullptr;
  return std::make_unique<FieldWriter>(ctx.directory / "fields");
}

int run_terzaghi(core::RunContext& ctx) {
  const core::Case& c = ctx.run_case;
  TerzaghiSpec t;
  t.height = c.number("geometry.height");
  t.width = c.number("geometry.width");
  t.cell = c.number("geometry.cell");
  t.points_per_cell = static_cast<int>(c.integer("geometry.points_per_cell"));
  t.empty_rows = static_cast<int>(c.integer("geometry.empty_rows"));
  t.young_modulus = c.number("solid.young_modulus");
  t.poisson_ratio = c.number("solid.poisson_ratio");
  t.porosity = c.number("solid.porosity");
  t.grain_density = c.number("solid.density");
  t.liquid_density = c.number("liquid.density");
  t.bulk_modulus = c.number("liquid.bulk_modulus");
  t.hydraulic_conductivity = c.number("liquid.hydraulic_conductivity");
  t.gravity_for_darcy = c.number("liquid.darcy_gravity");
  t.closure_drag = c.string("liquid.drag_law") == "closure";
  t.closure.viscosity = c.number("liquid.viscosity");
  t.closure.permeability = model::parse_permeability(c.string("liquid.permeability"));
  t.closure.sphericity = c.number("liquid.sphericity");
  t.grain_diameter = c.number("liquid.grain_diameter");
  t.load = c.number("loading.load");
  t.undrained_start = c.boolean("loading.undrained_start");
  t.options = read_options(c);
  terzaghi_inputs(c);
  auto s = make_terzaghi(t);
  RunHistory history = restore_run(ctx, *s);
  report_setup(ctx, *s, history);
  const TerzaghiConstants k = terzaghi_constants(t);
  ctx.log->info(
      "Terzaghi: p0 = {:.6g} Pa, k_D = {:.6g} m/s{}, c_v = {:.6g} m²/s, final "
      "settlement {:.6g} m",
      k.p0, k.hydraulic_conductivity, t.closure_drag ? " (equivalent to the closure)" : "", k.cv,
      k.final_settlement);
  const double ms0 = history.get("mass.solid0", s->total_mass(Phase::solid));
  const double ml0 = history.get("mass.liquid0", s->total_mass(Phase::liquid));
  auto isochrones = c.number_list("run.isochrones");
  std::sort(isochrones.begin(), isochrones.end());
  auto fields = field_writer(ctx);
  const int frames = static_cast<int>(c.integer("output.frames"));
  std::vector<double> time, settlement, settlement_exact;
  history.get("series.time", time);
  history.get("series.settlement", settlement);
  history.get("series.settlement_exact", settlement_exact);
  // The isochrones checked before a restart (check_terzaghi_restart: they come first).
  std::vector<double> done_Tv, done_p_err, done_s_err;
  history.get("terzaghi.isochrones", done_Tv);
  history.get("terzaghi.pressure_errors", done_p_err);
  history.get("terzaghi.settlement_errors", done_s_err);
  const long sample_every = 20;
  auto sample = [&]() {
    if (s->steps() % sample_every != 0) return;
    double u, ue;
    terzaghi_settlement(*s, t, u, ue);
    time.push_back(s->time());
    settlement.push_back(u);
    settlement_exact.push_back(ue);
  };
  double wall = 0;
  // Isochrone i in result.h5 (depth, p at the liquid points, exact p) and in the history.
  auto isochrone = [&](std::size_t i, double Tv, double at, double ep, std::vector<double> depth,
                       std::vector<double> p, std::vector<double> pe) {
    const std::string g = fmt::format("/isochrones/{}", i);
    ctx.result.write(g + "/depth", depth, "m", "depth below the top of the liquid points");
    ctx.result.write(g + "/pressure", p, "Pa", "pore pressure at the liquid points");
    ctx.result.write(g + "/pressure_exact", pe, "Pa", "Terzaghi series at the same depths");
    ctx.result.attribute(g, "time_factor", Tv);
    ctx.result.attribute(g, "time", at);
    ctx.result.attribute(g, "pressure_rms_error_over_p0", ep);
    const std::string h = fmt::format("terzaghi.isochrone_{}.", i);
    history.set(h + "time", at);
    history.set(h + "depth", std::move(depth));
    history.set(h + "pressure", std::move(p));
    history.set(h + "pressure_exact", std::move(pe));
  };
  for (std::size_t i = 0; i < done_Tv.size(); ++i) {
    const std::string h = fmt::format("terzaghi.isochrone_{}.", i);
    std::vector<double> at, depth, p, pe;
    history.get(h + "time", at);
    history.get(h + "depth", depth);
    history.get(h + "pressure", p);
    history.get(h + "pressure_exact", pe);
    isochrone(i, done_Tv[i], at.at(0), done_p_err.at(i), depth, p, pe);
  }
  // One frame set over the whole run, spaced on the last isochrone's time.
  FrameSchedule schedule(fields.get(), isochrones.back() * t.height * t.height / k.cv, frames, *s);
  for (std::size_t i = done_Tv.size(); i < isochrones.size(); ++i) {
    const double Tv = isochrones[i];
    const double end = Tv * t.height * t.height / k.cv;
    wall += advance(ctx, *s, end, schedule, sample);
    // An interrupted run has not reached this isochrone: neither it nor its checkpoint's history
    // may count it as checked.
    if (core::interrupted()) break;
    const double ep = terzaghi_pressure_error(*s, t);
    double u, ue;
    terzaghi_settlement(*s, t, u, ue);
    const double es = std::fabs(u - ue) / k.final_settlement;
    done_Tv.push_back(Tv);
    done_p_err.push_back(ep);
    done_s_err.push_back(es);
    ctx.log->info(
        "T_v = {:g} (t = {:.5g} s): pressure RMS error / p0 = {:.4g}; settlement {:.6g} "
        "m (exact {:.6g}), error / final = {:.4g}",
        Tv, s->time(), ep, u, ue, es);
    std::vector<double> depth, p, pe;
    for (std::size_t q = 0; q < s->liquid().size(); ++q) {
      const double d = t.height - s->liquid().y[q];
      depth.push_back(d);
      p.push_back(s->liquid().pressure[q]);
      pe.push_back(analytic::terzaghi_pressure(d, s->time(), t.height, k.cv, k.p0));
    }
    isochrone(i, Tv, s->time(), ep, std::move(depth), std::move(p), std::move(pe));
  }
  // Errors over every isochrone of the history, restarted or not.
  const double max_p_err =
      done_p_err.empty() ? 0.0 : *std::max_element(done_p_err.begin(), done_p_err.end());
  const double max_s_err =
      done_s_err.empty() ? 0.0 : *std::max_element(done_s_err.begin(), done_s_err.end());
  ctx.result.write("/series/time", time, "s", "time");
  ctx.result.write("/series/settlement", settlement, "m", "mean settlement of the top points");
  ctx.result.write("/series/settlement_exact", settlement_exact, "m",
                   "analytic settlement at the same points");
  ctx.result.attribute("/series", "p0", k.p0);
  ctx.result.attribute("/series", "cv", k.cv);
  ctx.result.attribute("/series", "height", t.height);
  ctx.result.attribute("/series", "final_settlement", k.final_settlement);
  ctx.result.flush();
  common_summary(ctx, *s, history, wall, ms0, ml0);
  ctx.summary.set("terzaghi.l2_err_pressure", max_p_err);
  ctx.summary.set("terzaghi.settlement_err", max_s_err);
  ctx.summary.set("terzaghi.p0", k.p0);
  ctx.summary.set("terzaghi.cv", k.cv);
  ctx.summary.set("terzaghi.cell", t.cell);
  ctx.summary.set("terzaghi.hydraulic_conductivity", k.hydraulic_conductivity);
  history.set("mass.solid0", ms0);
  history.set("mass.liquid0", ml0);
  history.set("series.time", time);
  history.set("series.settlement", settlement);
  history.set("series.settlement_exact", settlement_exact);
  history.set("terzaghi.isochrones", done_Tv);
  history.set("terzaghi.pressure_errors", done_p_err);
  history.set("terzaghi.settlement_errors", done_s_err);
  history.set("terzaghi.time_per_Tv", t.height * t.height / k.cv);
  finish_output(ctx, *s, history,
                {"terzaghi.l2_err_pressure", "terzaghi.settlement_err", "mass.solid_rel_change",
                 "mass.liquid_rel_change"});
  ctx.plot("plot_mpm.py");
  return core::exit_ok;
}

int run_couette(core::RunContext& ctx) {
  const core::Case& c = ctx.run_case;
  CouetteSpec cs;
  cs.inner_radius = c.number("geometry.inner_radius");
  cs.outer_radius = c.number("geometry.outer_radius");
  cs.cells_r = static_cast<int>(c.integer("geometry.cells_r"));
  cs.cells_theta = static_cast<int>(c.integer("geometry.cells_theta"));
  cs.points_per_cell = static_cast<int>(c.integer("geometry.points_per_cell"));
  cs.density = c.number("liquid.density");
  cs.viscosity = c.number("liquid.viscosity");
  cs.bulk_modulus = c.number("liquid.bulk_modulus");
  cs.wall_velocity = c.number("loading.wall_velocity");
  cs.options = read_options(c);
  couette_inputs(c);
  auto s = make_couette(cs);
  RunHistory history = restore_run(ctx, *s);
  report_setup(ctx, *s, history);
  const double ml0 = history.get("mass.liquid0", s->total_mass(Phase::liquid));
  const double end = c.number("run.end_time"), from = c.number("run.average_from");
  std::vector<double> vx(s->grid_nodes(), 0.0), vy(s->grid_nodes(), 0.0);
  long samples = 0;
  // A restart inside the averaging window continues its sums (check_couette_restart: the same
  // window); a window that starts after the checkpoint starts from zero.
  if (history.restarted() && !(s->time() < from)) {
    history.get("couette.vx_sum", vx);
    history.get("couette.vy_sum", vy);
    samples = std::lround(history.get("couette.samples", 0.0));
    if (vx.size() != static_cast<std::size_t>(s->grid_nodes()) || vy.size() != vx.size())
      refuse_restart(
          c, c.string("output.restart_from"),
          fmt::format("its averaging sums have {} nodes, the grid {}", vx.size(), s->grid_nodes()));
  }
  auto fields = field_writer(ctx);
  FrameSchedule schedule(fields.get(), end, static_cast<int>(c.integer("output.frames")), *s);
  const double wall = advance(ctx, *s, end, schedule, [&]() {
        if (s->time() < from) return;
        for (int a = 0; a < s->grid_nodes(); ++a) {
          vx[a] += s->nodes().vx_liquid[a];
          vy[a] += s->nodes().vy_liquid[a];
        }
        ++samples;
      });
  history.set("mass.liquid0", ml0);
  history.set("couette.average_from", from);
  history.set("couette.samples", static_cast<double>(samples));
  history.set("couette.vx_sum", vx);
  history.set("couette.vy_sum", vy);
  if (samples == 0)
    c.fail("run.average_from",
           fmt::format("a time at least one step (Δt = {:.4g} s) before run.end_time = {:g} s: no "
                       "step fell in the averaging window",
                       s->dt(), end));
  for (int a = 0; a < s->grid_nodes(); ++a) {
    vx[a] /= static_cast<double>(samples);
    vy[a] /= static_cast<double>(samples);
  }
  double et, er;
  couette_error(*s, cs, vx, vy, et, er);
  ctx.log->info(
      "Couette: RMS v_θ error / V = {:.4g}, RMS v_r / V = {:.4g} (grid velocity "
      "averaged over t in [{:g}, {:g}] s)",
      et, er, from, end);
  // Radial profile along θ = 0 ... all nodes of ring i averaged.
  const auto& g = std::get<PolarGrid>(s->grid());
  std::vector<double> r, vt, vt_exact;
  for (int i = 0; i <= g.cells_r(); ++i) {
    double sum = 0;
    for (int j = 0; j < g.cells_theta(); ++j) {
      const int a = g.node(i, j);
      const double th = g.node_angle(a);
      sum += -vx[a] * std::sin(th) + vy[a] * std::cos(th);
    }
    r.push_back(g.node_radius(i));
    vt.push_back(sum / g.cells_theta());
    vt_exact.push_back(analytic::couette_velocity(g.node_radius(i), cs.inner_radius,
                                                  cs.outer_radius, cs.wall_velocity));
  }
  ctx.result.write("/profile/radius", r, "m", "node ring radius");
  ctx.result.write("/profile/velocity", vt, "m/s", "ring-averaged, time-averaged grid v_θ");
  ctx.result.write("/profile/velocity_exact", vt_exact, "m/s", "A r + B / r");
  ctx.result.flush();
  common_summary(ctx, *s, history, wall, 0.0, ml0);
  ctx.summary.set("couette.l2_err_velocity", et);
  ctx.summary.set("couette.rms_radial_velocity", er);
  finish_output(
      ctx, *s, history,
      {"couette.l2_err_velocity", "couette.rms_radial_velocity", "mass.liquid_rel_change"});
  ctx.plot("plot_mpm.py");
  return core::exit_ok;
}

int run_column(core::RunContext& ctx) {
  const core::Case& c = ctx.run_case;
  ColumnSpec cs;
  cs.width = c.number("geometry.width");
  cs.height = c.number("geometry.height");
  cs.cell = c.number("geometry.cell");
  cs.points_per_cell = static_cast<int>(c.integer("geometry.points_per_cell"));
  cs.empty_rows = static_cast<int>(c.integer("geometry.empty_rows"));
  cs.young_modulus = c.number("solid.young_modulus");
  cs.poisson_ratio = c.number("solid.poisson_ratio");
  cs.density = c.number("solid.density");
  cs.gravity = c.number("loading.gravity");
  cs.options = read_options(c);
  column_inputs(c);
  auto s = make_elastic_column(cs);
  RunHistory history = restore_run(ctx, *s);
  report_setup(ctx, *s, history);
  const double ms0 = history.get("mass.solid0", s->total_mass(Phase::solid));
  std::vector<double> time, base;
  history.get("series.time", time);
  history.get("series.base_stress", base);
  auto fields = field_writer(ctx);
  FrameSchedule schedule(fields.get(), c.number("run.end_time"),
                         static_cast<int>(c.integer("output.frames")), *s);
  const double wall = advance(ctx, *s, c.number("run.end_time"), schedule, [&]() {
                                if (s->steps() % 10 != 0) return;
                                time.push_back(s->time());
                                base.push_back(column_error(*s, cs).base_stress);
                              });
  const ColumnError e = column_error(*s, cs);
  ctx.log->info(
      "column: RMS σ_yy error / (ρ g H) = {:.4g}, σ_xx {:.4g}; base σ_yy = {:.6g} Pa "
      "(ρ g H = {:.6g} Pa)",
      e.vertical_stress, e.horizontal_stress, e.base_stress, cs.density * cs.gravity * cs.height);
  std::vector<double> y0, syy, syy_exact;
  for (std::size_t p = 0; p < s->solid().size(); ++p) {
    y0.push_back(s->solid().y0[p]);
    syy.push_back(s->solid().syy[p]);
    syy_exact.push_back(
        analytic::column_vertical_stress(s->solid().y0[p], cs.height, cs.density, cs.gravity));
  }
  ctx.result.write("/series/time", time, "s", "time");
  ctx.result.write("/series/base_stress", base, "Pa", "mean σ_yy of the bottom row of points");
  ctx.result.write("/profile/y0", y0, "m", "initial height of the points");
  ctx.result.write("/profile/syy", syy, "Pa", "σ_yy at the points (tension-positive)");
  ctx.result.write("/profile/syy_exact", syy_exact, "Pa", "-ρ g (H - y0)");
  ctx.result.flush();
  common_summary(ctx, *s, history, wall, ms0, 0.0);
  ctx.summary.set("column.l2_err_stress", e.vertical_stress);
  ctx.summary.set("column.l2_err_horizontal_stress", e.horizontal_stress);
  ctx.summary.set("column.base_stress", e.base_stress);
  history.set("mass.solid0", ms0);
  history.set("series.time", time);
  history.set("series.base_stress", base);
  finish_output(ctx, *s, history,
                {"column.l2_err_stress", "column.l2_err_horizontal_stress", "column.base_stress",
                 "mass.solid_rel_change"});
  ctx.plot("plot_mpm.py");
  return core::exit_ok;
}

// ---- rheometer (docs/rheometer.md) -------------------------------------------------------------

core::Schema rheometer_schema() {
  core::Schema s = core::kind_header(
      "mpm", "rheometer",
      "The seed's undrained constant-volume annular rheometer (section 6) with the double-point "
      "MPM and the multi-regime material: outer ring v_θ = a t up to v_max, inner ring fixed.");
  auto& g = s.section("geometry", "annulus and polar grid");
  g.number("inner_radius", "m", "R_in (fixed ring)").default_value("0.08").greater_than(0);
  g.number("outer_radius", "m", "R_out (moving ring)").default_value("0.11").greater_than(0);
  g.integer("cells_r", "radial cells").default_value("8").at_least(2).sweepable();
  g.integer("cells_theta", "tangential cells").default_value("96").at_least(8).sweepable();
  g.integer("points_per_cell", "points per cell and direction (each phase)")
      .default_value("2")
      .at_least(1)
      .sweepable();
  s.add(continuum::material_section());
  s.add(continuum::force_chains_section());
  s.add(continuum::collisional_section());
  s.add(continuum::liquid_section());
  auto& sl = s.section("solid", "internal length of the skeleton's softening (docs/rheometer.md)");
  sl.number("internal_length", "m",
            "ℓ of the non-local average of the locus softening, w = exp(-(r/ℓ)²) over 2.5 ℓ "
            "(Bažant & Jirásek 2002); 0 = local model")
      .default_value("0")
      .at_least(0);
  sl.number("overnonlocal", "1",
            "m of r_c ← r_c (1 + m δ̄ + (1 − m) δ): 1 non-local, > 1 over-nonlocal (Vermeer & "
            "Brinkgreve 1994; m = 1 still localizes into one spacing, docs/rheometer.md)")
      .default_value("2")
      .at_least(1);
  auto& i = s.section("initial", "state after the drained isotropic consolidation (phase i)");
  i.number("void_ratio", "1", "e0").default_value("0.818").greater_than(0);
  i.number("effective_pressure", "Pa", "p'0 (σ_FC = p'0 I)").default_value("50.0e3").at_least(0);
  i.number("pore_pressure", "Pa", "u_w0").default_value("50.0e3").at_least(0);
  i.number("ocr", "1", "r_c / (√3 p'0)").default_value("1.0").at_least(1);
  i.number("temperature", "m^2/s^2", "T0").default_value("0").at_least(0);
  auto& ld = s.section("loading", "outer ring (phases ii and iii)");
  ld.number("acceleration", "m/s^2", "a of v_θ = a t").default_value("333").greater_than(0);
  ld.number("max_velocity", "m/s", "v_max held in phase iii")
      .default_value("1.0")
      .greater_than(0)
      .sweepable();
  auto& r = s.section("run", "duration and output");
  r.number("end_time", "s", "simulated time").default_value("0.02").greater_than(0);
  r.number_list("profile_times", "s", "times of the radial profiles (γ, v_θ)")
      .default_value("[0.002, 0.005, 0.01, 0.02]")
      .greater_than(0);
  r.integer("profile_bins", "radial bins of the profiles").default_value("16").at_least(2);
  r.integer("sample_every", "steps between samples of the averaged series")
      .default_value("20")
      .at_least(1);
  r.boolean("conduct_temperature",
            "conduct T through the nodes with the collisional conductivity ρ_p d f4 T^½")
      .default_value("true");
  r.boolean("closed_domain",
            "remove the volume-weighted mean of the liquid's volumetric rate (closed rigid "
            "annulus: its exact integral is zero; point quadrature leaves a drift of p̄)")
      .default_value("false");
  r.number("steady_fraction", "1", "steady values: means over this last fraction of the run")
      .default_value("0.2")
      .greater_than(0)
      .at_most(1);
  add_numerics(s, {"0.0", "true"});
  return s;
}

void check_rheometer(const core::Case& c) {
  check_common(c);
  if (c.string("numerics.shape") != "linear")
    c.fail("numerics.shape", "linear (the polar grid has linear shape functions only)");
  if (!(c.number("geometry.outer_radius") > c.number("geometry.inner_radius")))
    c.fail("geometry.outer_radius", "a value > geometry.inner_radius");
  if (!c.boolean("force_chains.enabled"))
    c.fail("force_chains.enabled", "true (the rheometer needs the skeleton)");
  // The initial solid fraction below the packing limits of the closures, as the REV tests.
  const auto settings = continuum::read_multi_regime_settings(c);
  const double nu0 = 1.0 / (1.0 + c.number("initial.void_ratio"));
  if (settings.collisional && nu0 >= model::maximum_solid_fraction(settings.collisional_parameters))
    c.fail(
        "initial.void_ratio",
        fmt::format("solid fraction 1/(1+e0) = {:.6g} is at or beyond collisional."
                    "jamming_fraction {:.6g} where g0 diverges; expected e0 > {:.6g} or a larger "
                    "jamming fraction",
                    nu0, settings.collisional_parameters.jamming_fraction,
                    1.0 / settings.collisional_parameters.jamming_fraction - 1.0));
  if (settings.liquid && nu0 >= model::maximum_mixture_solid_fraction(settings.liquid_parameters))
    c.fail("initial.void_ratio",
           fmt::format("solid fraction 1/(1+e0) = {:.6g} is at or beyond liquid.maximum_packing "
                       "{:.6g} where η(ν) diverges; expected e0 > {:.6g}",
                       nu0, settings.liquid_parameters.maximum_packing,
                       1.0 / settings.liquid_parameters.maximum_packing - 1.0));
}

void rheometer_inputs(const core::Case& c) {
  if (const auto r =
          check_restart(c, {"run.profile_times", "run.profile_bins", "run.steady_fraction"}))
    check_restart_end(c, *r, c.number("run.end_time"), "run.end_time");
}

RheometerSpec read_rheometer(const core::Case& c) {
  RheometerSpec r;
  r.inner_radius = c.number("geometry.inner_radius");
  r.outer_radius = c.number("geometry.outer_radius");
  r.cells_r = static_cast<int>(c.integer("geometry.cells_r"));
  r.cells_theta = static_cast<int>(c.integer("geometry.cells_theta"));
  r.points_per_cell = static_cast<int>(c.integer("geometry.points_per_cell"));
  r.void_ratio = c.number("initial.void_ratio");
  r.effective_pressure = c.number("initial.effective_pressure");
  r.pore_pressure = c.number("initial.pore_pressure");
  r.ocr = c.number("initial.ocr");
  r.initial_temperature = c.number("initial.temperature");
  r.acceleration = c.number("loading.acceleration");
  r.max_velocity = c.number("loading.max_velocity");
  r.model = continuum::read_multi_regime_settings(c);
  // The liquid points: the same liquid as the model (ρ_L, K_w, η0, κ(ν) drag closure). Their own
  // viscous stress is the Newtonian η0 part; the mixture viscosity σ_L of the model acts on the
  // solid points (multi_regime_material.hpp).
  r.liquid.density = r.model.liquid_parameters.density;
  r.liquid.bulk_modulus = r.model.liquid_parameters.bulk_modulus;
  r.liquid.viscosity = r.model.liquid_parameters.viscosity;
  r.liquid.viscosity_law = ViscosityLaw::constant;
  r.liquid.drag_law = DragLaw::closure;
  r.liquid.closure = r.model.liquid_parameters;
  r.liquid.grain_diameter = r.model.collisional_parameters.diameter;
  r.options = read_options(c);
  // T conducted through the nodes with the collisional conductivity ρ_p d f4 T^½ of each point
  // when the collisional term is on (seed section 5).
  r.options.material_conductivity = r.model.collisional && c.boolean("run.conduct_temperature");
  r.options.closed_domain = c.boolean("run.closed_domain");
  return r;
}

int run_rheometer(core::RunContext& ctx) {
  const core::Case& c = ctx.run_case;
  const RheometerSpec spec = read_rheometer(c);
  rheometer_inputs(c);
  Rheometer rh = make_rheometer(spec);
  rh.material->set_internal_length(c.number("solid.internal_length"),
                                   c.number("solid.overnonlocal"));
  Solver& s = *rh.solver;
  RunHistory history = restore_run(ctx, s);
  report_setup(ctx, s, history);
  if (spec.options.material_conductivity)
    ctx.log->info("T conducted through the nodes with κ_T = ρ_p d f4 T^½ of each point");
  const double ms0 = history.get("mass.solid0", s.total_mass(Phase::solid));
  const double ml0 = history.get("mass.liquid0", s.total_mass(Phase::liquid));
  std::vector<double> gamma(s.solid().size(), 0.0);
  history.get("rheometer.shear_strain", gamma);
  if (gamma.size() != s.solid().size())
    refuse_restart(c, c.string("output.restart_from"),
                   fmt::format("its shear strains have {} points, the case {}", gamma.size(),
                               s.solid().size()));
  // The material counts its clamped updates from its construction: add those before a restart.
  const double clamped0 = history.get("rheometer.clamped_updates", 0.0);
  auto clamped = [&]() { return clamped0 + static_cast<double>(rh.material->clamped_updates()); };
  const RheometerAverages a0 = rheometer_averages(s, *rh.material, gamma);
  ctx.log->info(
      "rheometer: e0 = {:g}, p'0 = {:g} Pa, u_w0 = {:g} Pa; v_θ = {:g} t up to v_max = {:g} m/s "
      "(t = {:.4g} s); mixture volume {:.6g} m² (annulus {:.6g})",
      spec.void_ratio, spec.effective_pressure, spec.pore_pressure, spec.acceleration,
      spec.max_velocity, spec.max_velocity / spec.acceleration, a0.mixture_volume,
      M_PI * (spec.outer_radius * spec.outer_radius - spec.inner_radius * spec.inner_radius));
  auto fields = field_writer(ctx);
  if (fields) {
    fields->add_solid_field("r_c", &rh.material->locus_size(), "Pa");
    fields->add_solid_field("void_ratio", &rh.material->void_ratio(), "1");
    fields->add_solid_field("shear_strain", &gamma, "1");
  }
  const int frames = static_cast<int>(c.integer("output.frames"));
  const double end_time = c.number("run.end_time");
  const long sample_every = c.integer("run.sample_every");
  auto profile_times = c.number_list("run.profile_times");
  std::sort(profile_times.begin(), profile_times.end());
  const int bins = static_cast<int>(c.integer("run.profile_bins"));
  std::vector<double> t_s, tau_s, sg_s, gam_s, rate_s, vol_s, pw_s, nstd_s, fl_s, tmean_s;
  // Numerics diagnostics: Δt and its limits, the largest ν and T, the clamp counter.
  std::vector<double> dt_s, dt_wave_s, dt_cond_s, numax_s, tmax_s, clamp_s, pstd_s, vr_s;
  // Crowns (inner r < R_in + L/3, middle, outer r > R_out − L/3): where strain starts, which
  // crown compacts, which fluidizes first (seed Figs. 4-6; docs/rheometer.md).
  constexpr int crowns = 3;
  std::array<std::vector<double>, crowns> crown_gamma, crown_n, crown_rc, crown_fluid;
  RheometerProfiles at_peak;
  double tau_max = -std::numeric_limits<double>::infinity();
  // The history a restart continues: every series (the summaries are taken over them), the
  // running peak and the crown strains at it.
  const std::vector<std::pair<std::string, std::vector<double>*>> series = [&]() {
    std::vector<std::pair<std::string, std::vector<double>*>> v = {
        {"time", &t_s},
        {"tau", &tau_s},
        {"sigma_G", &sg_s},
        {"gamma", &gam_s},
        {"gamma_dot", &rate_s},
        {"mixture_volume", &vol_s},
        {"pore_pressure", &pw_s},
        {"porosity_std", &nstd_s},
        {"fluidized_fraction", &fl_s},
        {"temperature", &tmean_s},
        {"dt", &dt_s},
        {"dt_wave", &dt_wave_s},
        {"dt_conduction", &dt_cond_s},
        {"solid_fraction_max", &numax_s},
        {"temperature_max", &tmax_s},
        {"clamped_updates", &clamp_s},
        {"pore_pressure_std", &pstd_s},
        {"radial_velocity_rms", &vr_s},
    };
    for (int k = 0; k < crowns; ++k) {
      const std::string crown = fmt::format("crown_{}.", k);
      v.emplace_back(crown + "shear_strain", &crown_gamma[k]);
      v.emplace_back(crown + "porosity", &crown_n[k]);
      v.emplace_back(crown + "locus_size", &crown_rc[k]);
      v.emplace_back(crown + "fluidized_fraction", &crown_fluid[k]);
    }
    return v;
  }();
  for (auto& [name, v] : series) history.get("rheometer.series." + name, *v);
  tau_max = history.get("rheometer.tau_max", tau_max);
  history.get("rheometer.peak_crown_shear_strain", at_peak.shear_strain);
  auto record_history = [&]() {
    for (auto& [name, v] : series) history.set("rheometer.series." + name, *v);
    history.set("rheometer.tau_max", tau_max);
    history.set("rheometer.peak_crown_shear_strain", at_peak.shear_strain);
    history.set("rheometer.shear_strain", gamma);
    history.set("rheometer.clamped_updates", clamped());
    history.set("mass.solid0", ms0);
    history.set("mass.liquid0", ml0);
  };
  auto sample = [&]() {
    const RheometerAverages a = rheometer_averages(s, *rh.material, gamma);
    const RheometerProfiles cr = rheometer_profiles(s, *rh.material, spec, gamma, crowns);
    for (int k = 0; k < crowns; ++k) {
      crown_gamma[k].push_back(cr.shear_strain[k]);
      crown_n[k].push_back(cr.porosity[k]);
      crown_rc[k].push_back(cr.locus_size[k]);
      crown_fluid[k].push_back(cr.fluidized_fraction[k]);
    }
    if (a.shear_stress > tau_max) {
      tau_max = a.shear_stress;
      at_peak = cr;
    }
    double T = 0;
    for (double v : s.solid().temperature) T += v;
    t_s.push_back(s.time());
    tau_s.push_back(a.shear_stress);
    sg_s.push_back(a.normal_stress);
    gam_s.push_back(a.shear_strain);
    rate_s.push_back(a.shear_rate);
    vol_s.push_back(a.mixture_volume);
    pw_s.push_back(a.pore_pressure);
    nstd_s.push_back(a.porosity_std);
    fl_s.push_back(a.fluidized_fraction);
    tmean_s.push_back(T / std::max<double>(1.0, s.solid().size()));
    pstd_s.push_back(a.pore_pressure_std);
    vr_s.push_back(a.radial_velocity_rms);
    dt_s.push_back(s.dt());
    dt_wave_s.push_back(history.limits(s).wave);
    dt_cond_s.push_back(history.limits(s).conduction);
    double nu_max = 0, T_max = 0;
    for (double n : s.solid().porosity) nu_max = std::max(nu_max, 1.0 - n);
    for (double v : s.solid().temperature) T_max = std::max(T_max, v);
    numax_s.push_back(nu_max);
    tmax_s.push_back(T_max);
    clamp_s.push_back(clamped());
  };
  // Profile group k of result.h5 (kept in the history: a restarted run writes them again).
  int profiles = 0;
  auto arrays = [](RheometerProfiles& pr) {
    return std::array<std::pair<const char*, std::vector<double>*>, 7>{{
        {"radius", &pr.radius},
        {"shear_strain", &pr.shear_strain},
        {"velocity", &pr.velocity},
        {"shear_stress", &pr.shear_stress},
        {"porosity", &pr.porosity},
        {"locus_size", &pr.locus_size},
        {"fluidized_fraction", &pr.fluidized_fraction},
    }};
  };
  auto write_profile = [&](RheometerProfiles pr, double at) {
    const std::string grp = fmt::format("/profiles/{}", profiles);
    const std::string h = fmt::format("rheometer.profile_{}.", profiles);
    for (const auto& [name, v] : arrays(pr)) history.set(h + name, *v);
    history.set(h + "time", at);
    ctx.result.write(grp + "/radius", pr.radius, "m", "bin centre radius");
    ctx.result.write(grp + "/shear_strain", pr.shear_strain, "1", "θ-averaged accumulated γ_rθ");
    ctx.result.write(grp + "/velocity", pr.velocity, "m/s", "θ-averaged solid v_θ");
    ctx.result.write(grp + "/shear_stress", pr.shear_stress, "Pa", "θ-averaged solid σ'_rθ");
    ctx.result.write(grp + "/porosity", pr.porosity, "1", "θ-averaged porosity n");
    ctx.result.write(grp + "/locus_size", pr.locus_size, "Pa", "θ-averaged r_c");
    ctx.result.write(grp + "/fluidized_fraction", pr.fluidized_fraction, "1",
                     "volume fraction with r_c below fluidization");
    ctx.result.attribute(grp, "time", at);
    const double vt = std::min(spec.max_velocity, spec.acceleration * at);
    ctx.result.attribute(grp, "wall_velocity", vt);
    ++profiles;
    history.set("rheometer.profiles", profiles);
  };
  for (int k = 0, n = std::lround(history.get("rheometer.profiles", 0.0)); k < n; ++k) {
    const std::string h = fmt::format("rheometer.profile_{}.", k);
    RheometerProfiles pr;
    std::vector<double> at;
    for (const auto& [name, v] : arrays(pr)) history.get(h + name, *v);
    history.get(h + "time", at);
    write_profile(std::move(pr), at.at(0));
  }
  // The profile times still ahead (a restart has taken those up to its checkpoint).
  std::size_t next_profile = 0;
  while (history.restarted() && next_profile < profile_times.size() &&
         s.time() >= profile_times[next_profile] - 0.5 * s.dt())
    ++next_profile;
  auto profile = [&]() {
    write_profile(rheometer_profiles(s, *rh.material, spec, gamma, bins), s.time());
    ++next_profile;
  };
  core::Progress progress(ctx.log, "simulated time", end_time);
  const auto start = std::chrono::steady_clock::now();
  FrameSchedule schedule(fields.get(), end_time, frames, s);
  if (!history.restarted()) sample();  // the restored series start with it
  try {
    schedule.write_initial(s);
    while (s.time() < end_time - 0.5 * s.dt() && !core::interrupted()) {
      s.step();
      accumulate_shear_strain(s, gamma);
      if (s.steps() % sample_every == 0) sample();
      while (next_profile < profile_times.size() &&
             s.time() >= profile_times[next_profile] - 0.5 * s.dt())
        profile();
      schedule.write_due(ctx, s);
      progress.update(s.time());
    }
  } catch (const SolverFailure& f) {
    throw core::NumericalFailure(f.step >= 0 ? f.step : s.steps() + 1, f.point, f.variable, f.value,
                                 f.what());
  }
  if (core::interrupted())
    ctx.log->warn("interrupted by {} at step {}, t = {:.6g} s (end time {:g} s)",
                  core::interrupt_name(), s.steps(), s.time(), end_time);
  progress.finish();
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  record_history();  // as the loop left it: a restart continues from here, not from the sample
  sample();
  ctx.result.write("/series/time", t_s, "s", "time");
  ctx.result.write("/series/tau", tau_s, "Pa", "averaged shear stress τ̄ = <σ_rθ> of the solid");
  ctx.result.write("/series/sigma_G", sg_s, "Pa", "averaged mean solid stress σ̄_G (compr. +)");
  ctx.result.write("/series/gamma", gam_s, "1", "averaged shear strain γ̄");
  ctx.result.write("/series/gamma_dot", rate_s, "1/s", "averaged shear rate <γ̇_rθ>");
  ctx.result.write("/series/mixture_volume", vol_s, "m^2", "Σ V of the solid points");
  ctx.result.write("/series/pore_pressure", pw_s, "Pa", "mean pore pressure");
  ctx.result.write("/series/porosity_std", nstd_s, "1", "standard deviation of n");
  ctx.result.write("/series/fluidized_fraction", fl_s, "1", "volume fraction with r_c = 0");
  ctx.result.write("/series/temperature", tmean_s, "m^2/s^2", "mean T of the solid points");
  ctx.result.write("/series/temperature_max", tmax_s, "m^2/s^2", "largest T of a solid point");
  ctx.result.write("/series/solid_fraction_max", numax_s, "1", "largest ν of a solid point");
  ctx.result.write("/series/pore_pressure_std", pstd_s, "Pa",
                   "rms of p about its mean over each ring of cells (θ-dependent part)");
  ctx.result.write("/series/radial_velocity_rms", vr_s, "m/s", "rms of the solid v_r");
  ctx.result.write("/series/dt", dt_s, "s", "time step");
  ctx.result.write("/series/dt_wave", dt_wave_s, "s", "critical step of the wave speed");
  ctx.result.write("/series/dt_conduction", dt_cond_s, "s", "critical step of T conduction");
  ctx.result.write("/series/clamped_updates", clamp_s, "1",
                   "point updates evaluated at ν_lim so far (multi-regime guard)");
  const char* crown_name[crowns] = {"inner", "middle", "outer"};
  for (int k = 0; k < crowns; ++k) {
    const std::string g = fmt::format("/crowns/{}", crown_name[k]);  // on /series/time
    ctx.result.write(g + "/shear_strain", crown_gamma[k], "1", "crown mean of γ_rθ");
    ctx.result.write(g + "/porosity", crown_n[k], "1", "crown mean of n");
    ctx.result.write(g + "/locus_size", crown_rc[k], "Pa", "crown mean of r_c");
    ctx.result.write(g + "/fluidized_fraction", crown_fluid[k], "1", "crown fraction r_c = 0");
  }
  ctx.result.attribute("/series", "max_velocity", spec.max_velocity);
  ctx.result.attribute("/series", "inner_radius", spec.inner_radius);
  ctx.result.attribute("/series", "outer_radius", spec.outer_radius);
  ctx.result.flush();
  // steady values: means over the last fraction of the run
  const double t_steady = end_time * (1.0 - c.number("run.steady_fraction"));
  double tau_st = 0, sg_st = 0, rate_st = 0;
  int m = 0;
  for (std::size_t k = 0; k < t_s.size(); ++k) {
    if (t_s[k] < t_steady) continue;
    tau_st += tau_s[k];
    sg_st += sg_s[k];
    rate_st += rate_s[k];
    ++m;
  }
  m = std::max(m, 1);
  const std::size_t ipeak =
      static_cast<std::size_t>(std::max_element(tau_s.begin(), tau_s.end()) - tau_s.begin());
  const double vmax_dev = [&]() {
    double d = 0;
    for (double v : vol_s) d = std::max(d, std::fabs(v - vol_s.front()) / vol_s.front());
    return d;
  }();
  // max |p̄ − u_w0| relative to u_w0 (to p'0 when the initial pore pressure is 0)
  const double pw_dev = [&]() {
    double d = 0;
    for (double p : pw_s) d = std::max(d, std::fabs(p - pw_s.front()));
    return d / (std::fabs(pw_s.front()) > 0 ? std::fabs(pw_s.front()) : spec.effective_pressure);
  }();
  common_summary(ctx, s, history, wall, ms0, ml0);
  auto& sum = ctx.summary;
  sum.set("cost.wall_s", wall);
  sum.set("peak.tau", tau_s[ipeak]);
  sum.set("time.peak", t_s[ipeak]);
  sum.set("peak.sigma_G", *std::max_element(sg_s.begin(), sg_s.end()));
  sum.set("steady.tau", tau_st / m);
  sum.set("steady.sigma_G", sg_st / m);
  sum.set("steady.gamma_dot", rate_st / m);
  sum.set("final.gamma", gam_s.back());
  sum.set("fluidized_fraction.final", fl_s.back());
  sum.set("porosity.std.final", nstd_s.back());
  sum.set("volume.mixture_rel_change_max", vmax_dev);
  sum.set("pore_pressure.mean_rel_change", pw_dev);
  // Loading regime: τ* / τ̄_peak > 1 means the ring acceleration's inertia outweighs the 1/r²
  // concentration at the peak (the outer ring is the more loaded), < 1 the quasi-static regime.
  const double tau_star = inertial_shear_stress(spec);
  sum.set("loading.inertial_stress", tau_star);
  sum.set("loading.inertia_ratio", tau_star / std::max(tau_s[ipeak], 1e-300));
  for (int k = 0; k < crowns; k += 2) {
    const std::string name = crown_name[k];
    sum.set("peak.gamma_" + name, at_peak.shear_strain[k]);
    sum.set("final.gamma_" + name, crown_gamma[k].back());
    sum.set("final.porosity_" + name, crown_n[k].back());
    sum.set("final.locus_size_" + name, crown_rc[k].back());
    // first time half of the crown has r_c = 0 (−1: never)
    double t_half = -1.0;
    for (std::size_t i = 0; i < crown_fluid[k].size(); ++i)
      if (crown_fluid[k][i] >= 0.5) {
        t_half = t_s[i];
        break;
      }
    sum.set("time.fluidized_" + name, t_half);
  }
  sum.set("final.porosity_middle", crown_n[1].back());
  sum.set("rheometer.max_velocity", spec.max_velocity);
  sum.set("rheometer.clamped_updates", clamped());
  sum.set("pore_pressure.mean_final", pw_s.back());
  sum.set("rheometer.cells_r", spec.cells_r);
  sum.set("rheometer.cells_theta", spec.cells_theta);
  sum.set("rheometer.points_per_cell", spec.points_per_cell);
  ctx.log->info(
      "rheometer: peak τ̄ = {:.4g} Pa at t = {:.4g} s; steady τ̄ = {:.4g} Pa, σ̄_G = {:.4g} Pa, "
      "γ̇ = {:.4g} 1/s; fluidized fraction {:.3g}; porosity std {:.3g}; max |ΔV|/V = {:.3g}; "
      "max |Δp̄| = {:.3g} of the initial",
      tau_s[ipeak], t_s[ipeak], tau_st / m, sg_st / m, rate_st / m, fl_s.back(), nstd_s.back(),
      vmax_dev, pw_dev);
  finish_output(
      ctx, s, history,
      {"volume.mixture_rel_change_max", "mass.solid_rel_change", "mass.liquid_rel_change"});
  ctx.plot("plot_rheometer.py");
  return core::exit_ok;
}

}  // namespace

void register_mpm_kinds(core::KindRegistry& registry) {
  registry.add({"mpm", "terzaghi", "Terzaghi consolidation, two-phase double-point MPM",
                terzaghi_schema(), check_terzaghi, run_terzaghi, "cases/mpm/terzaghi.yaml",
                terzaghi_inputs});
  registry.add({"mpm", "couette", "Couette flow of the liquid in an annulus (polar grid)",
                couette_schema(), check_couette, run_couette, "cases/mpm/couette.yaml",
                couette_inputs});
  registry.add({"mpm", "elastic_column", "elastic column under gravity, at rest", column_schema(),
                check_column, run_column, "cases/mpm/elastic_column.yaml", column_inputs});
  registry.add({"mpm", "rheometer",
                "undrained constant-volume annular rheometer with the multi-regime material",
                rheometer_schema(), check_rheometer, run_rheometer,
                "cases/mpm/rheometer_test1.yaml", rheometer_inputs});
}

}  // namespace granflow::mpm
