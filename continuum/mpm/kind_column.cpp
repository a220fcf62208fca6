// The `mpm` / `elastic_column` run: an elastic column under gravity brought to rest, σ_yy at the
// points against -ρ g (H - y) (problems.hpp builds the column).
#include <fmt/format.h>

#include <vector>

#include "continuum/mpm/analytic.hpp"
#include "continuum/mpm/kind_geometry.hpp"
#include "continuum/mpm/kind_run.hpp"
#include "continuum/mpm/linear_elastic.hpp"
#include "continuum/mpm/problems.hpp"

namespace granflow::mpm::kind {

void column_inputs(const core::Case& c) {
  if (const auto r = check_restart(c, {}))
    check_restart_end(c, *r, c.number("run.end_time"), "run.end_time");
}

int run_column(core::RunContext& ctx) {
  const core::Case& c = ctx.run_case;
  ColumnSpec cs;
  read_box(c, cs);
  // The constants of the exact solution at rest (K0 = ν/(1-ν), ρ g); the column itself is the
  // material `solid.material` names.
  const LinearElasticParameters elastic = read_linear_elastic(c);
  cs.young_modulus = elastic.young_modulus;
  cs.poisson_ratio = elastic.poisson_ratio;
  cs.density = elastic.density;
  cs.gravity = c.number("loading.gravity");
  cs.options = read_options(c);
  column_inputs(c);
  auto s = make_elastic_column(cs, material_registry().create(c));
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

}  // namespace granflow::mpm::kind
