// The `mpm` / `terzaghi` run: Terzaghi consolidation of a layer, pore pressure isochrones and
// settlement against the analytic series (problems.hpp builds the layer).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "continuum/model/closures.hpp"
#include "continuum/mpm/analytic.hpp"
#include "continuum/mpm/kind_geometry.hpp"
#include "continuum/mpm/kind_run.hpp"
#include "continuum/mpm/linear_elastic.hpp"
#include "continuum/mpm/problems.hpp"

namespace granflow::mpm::kind {

// The checkpoint of output.restart_from (continuum/mpm/restart.hpp): KindEntry::check_inputs,
// before the run directory exists (granflow check does not read it), and the run itself.
void terzaghi_inputs(const core::Case& c) {
  if (const auto r = check_restart(c, {"run.isochrones"})) check_terzaghi_restart(c, *r);
}

int run_terzaghi(core::RunContext& ctx) {
  const core::Case& c = ctx.run_case;
  TerzaghiSpec t;
  read_box(c, t);
  // The constants of Terzaghi's solution (an elastic skeleton); the skeleton itself is the
  // material `solid.material` names.
  const LinearElasticParameters elastic = read_linear_elastic(c);
  t.young_modulus = elastic.young_modulus;
  t.poisson_ratio = elastic.poisson_ratio;
  t.grain_density = elastic.density;
  t.porosity = c.number("solid.porosity");
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
  auto s = make_terzaghi(t, material_registry().create(c));
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

}  // namespace granflow::mpm::kind
