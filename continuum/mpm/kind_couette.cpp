// The `mpm` / `couette` run: Couette flow of the liquid between two cylinders on the polar grid,
// the time-averaged grid velocity against v_θ = A r + B / r (problems.hpp builds the annulus).
#include <fmt/format.h>

#include <cmath>
#include <variant>
#include <vector>

#include "continuum/mpm/analytic.hpp"
#include "continuum/mpm/kind_geometry.hpp"
#include "continuum/mpm/kind_run.hpp"
#include "continuum/mpm/problems.hpp"

namespace granflow::mpm::kind {

void couette_inputs(const core::Case& c) {
  if (const auto r = check_restart(c, {"run.average_from"})) check_couette_restart(c, *r);
}

int run_couette(core::RunContext& ctx) {
  const core::Case& c = ctx.run_case;
  CouetteSpec cs;
  read_annulus(c, cs);
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

}  // namespace granflow::mpm::kind
