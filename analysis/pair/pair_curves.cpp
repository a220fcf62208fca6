#include "analysis/pair/pair_curves.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>

#include "analysis/pair/pair_columns.hpp"

namespace granflow::pair {

// Smooth model curves over the DEM's range of γ̇ (a factor 2 beyond each end, 80 rates, log
// spaced) with the first point's μ_p and η0: /pair/curve/*. The normal stress follows the DEM's
// measured σ_yy (constant volume: the solid fraction follows the DEM's φ), interpolated linearly
// in log γ̇ between the points (constant beyond the ends), so that the curves pass through the
// model's values at the DEM points (the model is not a function of I alone: the critical state
// line depends on p).
void write_model_curves(core::RunContext& ctx, const std::vector<calibration::DataPoint>& points,
                        const calibration::CalibratedModel& model,
                        const calibration::CalibratedModel& kinetic,
                        const calibration::CalibratedModel* calibrated) {
  if (points.empty()) return;
  const bool volume = points.front().protocol == calibration::Protocol::constant_volume;
  std::vector<std::pair<double, double>> measured;  // (ln γ̇, σ_yy or φ), sorted
  for (const auto& p : points)
    measured.emplace_back(std::log(p.shear_rate), volume ? p.value[1] : p.normal_stress);
  std::sort(measured.begin(), measured.end());
  const auto sigma_at = [&](double gamma_dot) {
    const double x = std::log(gamma_dot);
    if (x <= measured.front().first) return measured.front().second;
    if (x >= measured.back().first) return measured.back().second;
    std::size_t k = 1;
    while (measured[k].first < x) ++k;
    const auto& [x0, y0] = measured[k - 1];
    const auto& [x1, y1] = measured[k];
    return x1 > x0 ? y0 + (y1 - y0) * (x - x0) / (x1 - x0) : y1;
  };
  double lo = std::exp(measured.front().first) * 0.5, hi = std::exp(measured.back().first) * 2.0;
  constexpr int count = 80;
  std::map<std::string, std::vector<double>> curve;
  for (int i = 0; i < count; ++i) {
    calibration::DataPoint at = points.front();
    at.shear_rate = lo * std::pow(hi / lo, double(i) / (count - 1));
    double sigma = sigma_at(at.shear_rate);
    if (volume) {  // the imposed φ; σ_yy is the model's at it
      at.value[1] = sigma;
      const auto s = calibration::predict(model, at);
      sigma = s.ok ? s.normal_stress : NAN;
      curve["solid_fraction"].push_back(at.value[1]);
    }
    at.normal_stress = sigma;
    curve["shear_rate"].push_back(at.shear_rate);
    curve["normal_stress"].push_back(sigma);
    const double eta0 = std::isfinite(at.liquid_viscosity) ? at.liquid_viscosity : 0.0;
    curve["viscous_number"].push_back(eta0 * at.shear_rate / sigma);
    const double rho_p = model.settings.collisional_parameters.particle_density;
    curve["inertial_number"].push_back(
        at.shear_rate * model.settings.collisional_parameters.diameter / std::sqrt(sigma / rho_p));
    const auto add = [&](const std::string& tag, const calibration::CalibratedModel& m) {
      const auto s = calibration::predict(m, at);
      curve["friction_" + tag].push_back(s.ok ? s.friction : NAN);
      curve["solid_fraction_" + tag].push_back(s.ok ? s.solid_fraction : NAN);
      curve["granular_temperature_" + tag].push_back(s.ok ? s.granular_temperature : NAN);
      curve["share_tau_fc_" + tag].push_back(s.ok ? s.force_chain_shear_stress / s.shear_stress
                                                  : NAN);
    };
    add("model", model);
    add("kt", kinetic);
    if (calibrated) add("cal", *calibrated);
  }
  // Named as the shared vocabulary, QUANTITY_SOURCE (pair_columns.hpp).
  for (const auto& [name, values] : curve) {
    namespace c = core::columns;
    std::string unit = "1", doc;
    if (name == c::shear_rate.name || name == c::normal_stress.name ||
        name == c::inertial_number.name || name == c::viscous_number.name ||
        name == c::solid_fraction.name) {
      for (const core::Column& q : {c::shear_rate, c::normal_stress, c::inertial_number,
                                    c::viscous_number, c::solid_fraction})
        if (name == q.name) unit = q.unit, doc = q.description;
    } else if (name.rfind("share_tau_fc_", 0) == 0) {
      doc = "τ_FC/τ, the share of τ carried by the force chains: " + pair_source(name.substr(12));
    } else {
      const PairColumn column = pair_column(name);
      unit = column.unit, doc = column.description;
    }
    ctx.result.write("/pair/curve/" + name, values, unit,
                     doc + ", along a smooth γ̇ sweep at the DEM's σ_yy interpolated in log γ̇");
  }
}

// Immersed pairs that vary η0: smooth curves over the viscous number J = η0 γ̇/σ_yy, one per
// level of σ_yy (points within 30 % of each other's σ_yy form a level), at the level's mean γ̇
// and σ_yy, η0 log spaced from half the smallest to twice the largest of the level:
// /pair/curve_J/<level>/{viscous_number, friction_*, solid_fraction_*, granular_temperature_*}.
void write_viscous_curves(core::RunContext& ctx, const std::vector<calibration::DataPoint>& points,
                          const calibration::CalibratedModel& model,
                          const calibration::CalibratedModel& kinetic,
                          const calibration::CalibratedModel* calibrated) {
  std::vector<const calibration::DataPoint*> wet;
  for (const auto& p : points)
    if (std::isfinite(p.liquid_viscosity) && p.liquid_viscosity > 0) wet.push_back(&p);
  std::set<double> viscosities;
  for (const auto* p : wet) viscosities.insert(p->liquid_viscosity);
  if (viscosities.size() < 2) return;
  std::sort(wet.begin(), wet.end(),
            [](auto* a, auto* b) { return a->normal_stress < b->normal_stress; });
  std::vector<std::vector<const calibration::DataPoint*>> levels;
  for (const auto* p : wet) {
    if (levels.empty() || p->normal_stress > 1.3 * levels.back().front()->normal_stress)
      levels.emplace_back();
    levels.back().push_back(p);
  }
  for (std::size_t level = 0; level < levels.size(); ++level) {
    double sigma = 0, gamma_dot = 0, lo = INFINITY, hi = 0;
    for (const auto* p : levels[level]) {
      sigma += p->normal_stress / levels[level].size();
      gamma_dot += p->shear_rate / levels[level].size();
      lo = std::min(lo, p->liquid_viscosity), hi = std::max(hi, p->liquid_viscosity);
    }
    lo *= 0.5, hi *= 2.0;
    constexpr int count = 60;
    std::map<std::string, std::vector<double>> curve;
    for (int i = 0; i < count; ++i) {
      calibration::DataPoint at = *levels[level].front();
      at.liquid_viscosity = lo * std::pow(hi / lo, double(i) / (count - 1));
      at.shear_rate = gamma_dot;
      at.normal_stress = sigma;
      curve[core::columns::viscous_number.name].push_back(at.liquid_viscosity * gamma_dot / sigma);
      const auto add = [&](const std::string& tag, const calibration::CalibratedModel& m) {
        const auto s = calibration::predict(m, at);
        curve["friction_" + tag].push_back(s.ok ? s.friction : NAN);
        curve["solid_fraction_" + tag].push_back(s.ok ? s.solid_fraction : NAN);
        curve["granular_temperature_" + tag].push_back(s.ok ? s.granular_temperature : NAN);
      };
      add("model", model);
      add("kt", kinetic);
      if (calibrated) add("cal", *calibrated);
    }
    const std::string group = fmt::format("/pair/curve_J/{}/", level);
    for (const auto& [name, values] : curve) {
      const PairColumn column =
          name == core::columns::viscous_number.name
              ? PairColumn{name, "1", core::columns::viscous_number.description}
              : pair_column(name);
      ctx.result.write(group + name, values, column.unit,
                       fmt::format("{}, along a smooth η0 sweep at γ̇ = {:g} 1/s, σ_yy = {:g} Pa",
                                   column.description, gamma_dot, sigma));
    }
    ctx.result.attribute(group.substr(0, group.size() - 1), "normal_stress", sigma);
  }
}

}  // namespace granflow::pair
