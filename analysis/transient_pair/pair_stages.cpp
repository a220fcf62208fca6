#include "analysis/transient_pair/pair_stages.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <optional>
#include <tuple>

#include "core/numerical_failure.hpp"
#include "core/result_columns.hpp"
#include "dem_coupling/kind/rate_step_metrics.hpp"
#include "dem_coupling/kind/transient.hpp"

namespace granflow::transient_pair {

double relative_error(double model, double data) {
  return data != 0.0 ? model / data - 1.0 : std::numeric_limits<double>::quiet_NaN();
}

std::string metric_key(const std::string& side, const std::string& name, const std::string& g) {
  return "transient." + side + "." + name + g;
}

void write_metrics(core::RunContext& ctx, std::span<const MetricPair> metrics,
                   const DemTransient& dem, const std::string& group, const std::string& g,
                   const std::string& suffix) {
  auto& sum = ctx.summary;
  const std::string cont = "cont" + suffix;
  for (const auto& [name, values] : metrics) {
    if (suffix.empty()) {
      sum.set(metric_key("dem", name, g), values.first);
      ctx.result.attribute(group, std::string("dem_") + name, values.first);
      if (const auto e = dem.metric_err.find(name); e != dem.metric_err.end())
        sum.set(metric_key("dem", std::string(name) + "_err", g), e->second);
    }
    sum.set(metric_key(cont, name, g), values.second);
    ctx.result.attribute(group, cont + "_" + name, values.second);
  }
}

std::string compare_times(core::Summary& sum, const char* name, double dem_time, double cont_time,
                          const std::string& suffix, const std::string& g, const char* unit) {
  const auto text = [&](double t) {
    return t > 0 ? fmt::format("{:.4g}{}{}", t, *unit ? " " : "", unit) : std::string("never");
  };
  const bool both = dem_time > 0 && cont_time > 0;
  if (both) sum.set(metric_key("rel_err" + suffix, name, g), relative_error(cont_time, dem_time));
  return fmt::format("{} (DEM) and {} (continuum){}", text(dem_time), text(cont_time),
                     both ? fmt::format(", ratio {:.3g}", cont_time / dem_time) : "");
}

void compare_stop(core::RunContext& ctx, const core::Case& condition, const DemTransient& dem,
                  const rev::SimpleShearResult& rev, const Thresholds& limits,
                  const std::string& group, const std::string& g, const std::string& suffix) {
  rev::SimpleShearSeries stop;
  const double normal_stress = drained_normal_stress(condition, dem.p0);
  std::optional<core::NumericalFailure> failure;
  try {
    continuum_stop(condition, rev, normal_stress, stop);
  } catch (const core::NumericalFailure& e) {
    failure = e;
  }
  const bool drained = condition.number("stop.drainage_length") > 0.0;
  namespace col = core::columns;
  const std::string model =
      suffix.empty() ? "continuum" : "continuum with the fitted force-chain parameters";
  const std::pair<core::Column, const std::vector<double>&> series[] = {
      {col::described(col::time, "time since the shear was stopped"), stop.time},
      {col::described(col::mean_stress, "mean stress p' = p_COL + tr(σ_FC)/3, shear stopped"),
       stop.pressure},
      {col::described(col::granular_temperature, "granular temperature T, shear stopped"),
       stop.granular_temperature},
      {col::described(col::normal_stress, "normal stress σ_yy of the grains, shear stopped"),
       stop.normal_stress},
      {col::described(col::solid_fraction, "solid fraction φ, shear stopped"), stop.solid_fraction},
  };
  for (const auto& [column, values] : series)
    ctx.result.write(group + "/stop/" + column.name + suffix, values, column.unit,
                     model + ": " + column.description);
  if (failure && drained && condition.boolean("liquid.enabled") &&
      condition.number("liquid.maximum_packing") < condition.number("collisional.jamming_fraction"))
    ctx.log->warn(
        "  the drained stop compacts towards liquid.maximum_packing = {:g}, where η(ν) diverges, "
        "below collisional.jamming_fraction = {:g}; a packing the DEM compacts past it cannot "
        "follow (docs/transient_pairs.md, \"Drained reconsolidation\")",
        condition.number("liquid.maximum_packing"),
        condition.number("collisional.jamming_fraction"));
  if (failure) throw *failure;
  const auto dem_m = dem::stop_metrics(dem.stop_time, dem.stop_T_mean, dem.stop_p_mean,
                                       dem::residual_mean(dem.strain, dem.T_mean, limits.residual),
                                       dem.p0, limits.cooling);
  const auto cont_m = dem::stop_metrics(
      stop.time, stop.granular_temperature, stop.pressure,
      dem::residual_mean(rev.series.strain, rev.series.granular_temperature, limits.residual),
      dem.p0, limits.cooling);
  auto& sum = ctx.summary;
  const std::string cont = "cont" + suffix;
  const MetricPair metrics[] = {
      {"flowing_T", {dem_m.flowing_temperature, cont_m.flowing_temperature}},
      {"cooling_time", {dem_m.cooling_time, cont_m.cooling_time}},
      {"stop_T_over_flowing_T", {dem_m.final_temperature_ratio, cont_m.final_temperature_ratio}},
      {"stop_p_over_p0", {dem_m.final_p_over_p0, cont_m.final_p_over_p0}},
  };
  write_metrics(ctx, metrics, dem, group, g, suffix);
  ctx.log->info(
      "  shear stopped: T below {:g} × the flowing T after {}; p' at the end {:.3g} p0 (DEM), "
      "{:.3g} p0 (continuum)",
      limits.cooling,
      compare_times(sum, "cooling_time", dem_m.cooling_time, cont_m.cooling_time, suffix, g),
      dem_m.final_p_over_p0, cont_m.final_p_over_p0);
  if (!drained) return;
  const auto dem_d =
      dem::drained_stop_metrics(dem.stop_time, dem.stop_sigma_yy_mean, dem.stop_phi_mean, dem.phi0,
                                normal_stress, limits.reconsolidation);
  const auto cont_d = dem::drained_stop_metrics(stop.time, stop.normal_stress, stop.solid_fraction,
                                                dem.phi0, normal_stress, limits.reconsolidation);
  const MetricPair drained_metrics[] = {
      {"reconsolidation_time", {dem_d.reconsolidation_time, cont_d.reconsolidation_time}},
      {"stop_phi", {dem_d.final_solid_fraction, cont_d.final_solid_fraction}},
      {"stop_phi_change", {dem_d.solid_fraction_change, cont_d.solid_fraction_change}},
  };
  write_metrics(ctx, drained_metrics, dem, group, g, suffix);
  ctx.result.attribute(group, "stop_normal_stress", normal_stress);
  ctx.log->info(
      "  drained under σ_n = {:.4g} Pa: σ_yy reached {:g} σ_n after {}; φ {:.4f} -> {:.4f} (DEM), "
      "{:.4f} (continuum)",
      normal_stress, limits.reconsolidation,
      compare_times(sum, "reconsolidation_time", dem_d.reconsolidation_time,
                    cont_d.reconsolidation_time, suffix, g),
      dem.phi0, dem_d.final_solid_fraction, cont_d.final_solid_fraction);
}

void compare_rate_step(core::RunContext& ctx, const core::Case& condition, const DemTransient& dem,
                       const rev::SimpleShearResult& rev, const Thresholds& limits,
                       const std::string& group, const std::string& g, const std::string& suffix) {
  const double step = condition.number("rate_step.strain");
  const auto& s = rev.series;
  const auto d = dem::rate_step_metrics(dem.strain, dem.tau_mean, dem.sigma_yy_mean, dem.phi_mean,
                                        dem.T_mean, step, limits.residual);
  const auto c = dem::rate_step_metrics(s.strain, s.shear_stress, s.normal_stress, s.solid_fraction,
                                        s.granular_temperature, step, limits.residual);
  const MetricPair metrics[] = {
      {"mu_before_step", {d.mu_before, c.mu_before}},
      {"mu_after_step", {d.mu_after, c.mu_after}},
      {"phi_before_step", {d.phi_before, c.phi_before}},
      {"phi_after_step", {d.phi_after, c.phi_after}},
      {"T_before_step", {d.T_before, c.T_before}},
      {"T_after_step", {d.T_after, c.T_after}},
      {"dilation", {d.dilation, c.dilation}},
      {"peak_mu_after_step", {d.peak_mu, c.peak_mu}},
  };
  write_metrics(ctx, metrics, dem, group, g, suffix);
  auto& sum = ctx.summary;
  const std::string cont = "cont" + suffix;
  if (d.dilation_strain >= 0 && suffix.empty()) {
    sum.set(metric_key("dem", "dilation_strain", g), d.dilation_strain);
    if (const auto e = dem.metric_err.find("dilation_strain"); e != dem.metric_err.end())
      sum.set(metric_key("dem", "dilation_strain_err", g), e->second);
  }
  if (c.dilation_strain >= 0) sum.set(metric_key(cont, "dilation_strain", g), c.dilation_strain);
  for (const auto& [name, dem_value, cont_value] :
       {std::tuple{"mu_before_step", d.mu_before, c.mu_before},
        std::tuple{"mu_after_step", d.mu_after, c.mu_after},
        std::tuple{"dilation", d.dilation, c.dilation}})
    sum.set(metric_key("rel_err" + suffix, name, g), relative_error(cont_value, dem_value));
  ctx.result.attribute(group, "rate_step_strain", step);
  ctx.result.attribute(group, "rate_step_shear_rate", condition.number("rate_step.shear_rate"));
  ctx.log->info(
      "  rate step {:g} -> {:g} 1/s at γ = {:g}: μ {:.4g} -> {:.4g} (DEM), {:.4g} -> {:.4g} "
      "(continuum); φ {:.4f} -> {:.4f} (DEM), {:.4f} -> {:.4f} (continuum); half the "
      "dilation after {}",
      condition.number("shear_rate"), condition.number("rate_step.shear_rate"), step, d.mu_before,
      d.mu_after, c.mu_before, c.mu_after, d.phi_before, d.phi_after, c.phi_before, c.phi_after,
      compare_times(sum, "dilation_strain", d.dilation_strain, c.dilation_strain, suffix, g, ""));
}

}  // namespace granflow::transient_pair
