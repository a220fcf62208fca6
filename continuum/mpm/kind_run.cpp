// The pieces of the `mpm` problems' runs that kind_run.hpp declares.
#include "continuum/mpm/kind_run.hpp"

#include <algorithm>
#include <cmath>

namespace granflow::mpm::kind {

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

}  // namespace granflow::mpm::kind
