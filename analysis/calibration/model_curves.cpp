#include "analysis/calibration/model_curves.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "core/result_columns.hpp"

namespace granflow::calibration {

namespace {

// The conditions a curve interpolates: ln γ̇, ln σ_yy (constant pressure), φ (constant volume),
// ln η0 (immersed); NaN where the condition does not apply.
constexpr int conditions = 4;
using Conditions = std::array<double, conditions>;
constexpr int ln_rate = 0, ln_stress = 1, phi = 2, ln_viscosity = 3;

bool immersed(const DataPoint& p) { return std::isfinite(p.liquid_viscosity); }
bool at_volume(const DataPoint& p) { return p.protocol == Protocol::constant_volume; }

Conditions conditions_of(const DataPoint& p) {
  return {std::log(p.shear_rate), at_volume(p) ? NAN : std::log(p.normal_stress),
          at_volume(p) ? p.value[static_cast<int>(Observable::solid_fraction)] : NAN,
          immersed(p) ? std::log(p.liquid_viscosity) : NAN};
}

// Index in Conditions of the curve variable.
int index_of(CurveVariable v) {
  switch (v) {
    case CurveVariable::shear_rate:
      return ln_rate;
    case CurveVariable::solid_fraction:
      return phi;
    case CurveVariable::liquid_viscosity:
      return ln_viscosity;
    case CurveVariable::normal_stress:
      return ln_stress;
  }
  return ln_rate;
}

// Equal to a relative 1e-9 (ln values and φ: absolute 1e-9), both NaN counting as equal.
bool same(double a, double b) {
  return (std::isnan(a) && std::isnan(b)) || std::abs(a - b) <= 1e-9 * std::max(1.0, std::abs(a));
}

// The other conditions of a and b (all but the variable's) agree: within 1e-9, or, with
// `factor`, within ln 1.3 (the level rule; the others are ln of γ̇, σ_yy or η0).
bool others_agree(const Conditions& a, const Conditions& b, int variable, bool factor) {
  for (int k = 0; k < conditions; ++k) {
    if (k == variable) continue;
    if (factor ? !(std::isnan(a[k]) ? std::isnan(b[k]) : std::abs(a[k] - b[k]) <= std::log(1.3))
               : !same(a[k], b[k]))
      return false;
  }
  return true;
}

// The monotone cubic Hermite interpolant of (c[i][v], y[i]) at u in [c[k-1][v], c[k][v]]
// (Fritsch & Carlson 1980, SIAM J. Numer. Anal. 17, 238; node slopes as scipy's
// PchipInterpolator: the weighted harmonic mean of the neighbouring secants δ, 0 where they
// differ in sign, the shape-preserving three-point formula at the ends). C¹ through the nodes and
// within the range of its two nodes between them: no kink at a row, no overshoot.
double monotone_cubic(const std::vector<Conditions>& c, int v, const std::vector<double>& y,
                      std::size_t k, double u) {
  const std::size_t n = y.size();
  const auto h = [&](std::size_t i) { return c[i + 1][v] - c[i][v]; };
  const auto delta = [&](std::size_t i) { return (y[i + 1] - y[i]) / h(i); };
  const auto sign = [](double a) { return (a > 0) - (a < 0); };
  const auto slope = [&](std::size_t i) {
    if (n == 2) return delta(0);
    if (i == 0 || i == n - 1) {  // three-point end formula, kept within the shape of the data
      const std::size_t e = i == 0 ? 0 : n - 2, f = i == 0 ? 1 : n - 3;
      const double d = ((2 * h(e) + h(f)) * delta(e) - h(e) * delta(f)) / (h(e) + h(f));
      if (sign(d) != sign(delta(e))) return 0.0;
      if (sign(delta(e)) != sign(delta(f)) && std::abs(d) > 3 * std::abs(delta(e)))
        return 3 * delta(e);
      return d;
    }
    const double d0 = delta(i - 1), d1 = delta(i);
    if (d0 * d1 <= 0) return 0.0;
    const double w0 = 2 * h(i) + h(i - 1), w1 = h(i) + 2 * h(i - 1);
    return (w0 + w1) / (w0 / d0 + w1 / d1);
  };
  const double width = h(k - 1), t = (u - c[k - 1][v]) / width;
  return (1 + 2 * t) * (1 - t) * (1 - t) * y[k - 1] + t * (1 - t) * (1 - t) * width * slope(k - 1) +
         t * t * (3 - 2 * t) * y[k] + t * t * (t - 1) * width * slope(k);
}

// A series of the rows `rows` of `points` (one level): nodes sorted by x, repeats merged.
CurveSeries make_series(const std::vector<DataPoint>& points, std::vector<std::size_t> rows,
                        CurveVariable variable) {
  CurveSeries s;
  s.variable = variable;
  s.protocol = points[rows.front()].protocol;
  const int v = index_of(variable);
  std::stable_sort(rows.begin(), rows.end(), [&](std::size_t a, std::size_t b) {
    return conditions_of(points[a])[v] < conditions_of(points[b])[v];
  });
  s.rows = rows;
  for (std::size_t i = 0; i < rows.size();) {
    const Conditions first = conditions_of(points[rows[i]]);
    Conditions mean{};
    bool differ = false;
    std::size_t n = 0;
    for (; i + n < rows.size() && same(conditions_of(points[rows[i + n]])[v], first[v]); ++n) {
      const Conditions c = conditions_of(points[rows[i + n]]);
      for (int k = 0; k < conditions; ++k) {
        mean[k] += c[k];
        differ = differ || !(c[k] == first[k] || (std::isnan(c[k]) && std::isnan(first[k])));
      }
    }
    DataPoint node = points[rows[i]];
    if (differ) {  // repeats that differ within 1e-9: the mean of each (ln for γ̇, σ_yy, η0)
      for (int k = 0; k < conditions; ++k) mean[k] /= static_cast<double>(n);
      node.shear_rate = std::exp(mean[ln_rate]);
      if (!at_volume(node)) node.normal_stress = std::exp(mean[ln_stress]);
      if (at_volume(node)) node.value[static_cast<int>(Observable::solid_fraction)] = mean[phi];
      if (immersed(node)) node.liquid_viscosity = std::exp(mean[ln_viscosity]);
    }
    if (at_volume(node)) node.normal_stress = NAN;  // predicted, not a condition
    s.nodes.push_back(node);
    i += n;
  }
  s.lower = curve_value(s.nodes.front(), variable);
  s.upper = curve_value(s.nodes.back(), variable);
  return s;
}

}  // namespace

const char* curve_variable_name(CurveVariable variable) {
  namespace c = core::columns;
  switch (variable) {
    case CurveVariable::shear_rate:
      return c::shear_rate.name;
    case CurveVariable::solid_fraction:
      return c::solid_fraction.name;
    case CurveVariable::liquid_viscosity:
      return c::liquid_viscosity.name;
    case CurveVariable::normal_stress:
      return c::normal_stress.name;
  }
  return "";
}

double curve_value(const DataPoint& point, CurveVariable variable) {
  switch (variable) {
    case CurveVariable::shear_rate:
      return point.shear_rate;
    case CurveVariable::solid_fraction:
      return point.value[static_cast<int>(Observable::solid_fraction)];
    case CurveVariable::liquid_viscosity:
      return point.liquid_viscosity;
    case CurveVariable::normal_stress:
      return point.normal_stress;
  }
  return NAN;
}

std::vector<CurveSeries> curve_series(const std::vector<DataPoint>& points) {
  // Groups: protocol, μ_p, dry or immersed, in the order of their first row.
  std::vector<std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    auto group = std::find_if(groups.begin(), groups.end(), [&](const auto& g) {
      const auto& q = points[g.front()];
      return q.protocol == p.protocol && immersed(q) == immersed(p) &&
             same(q.particle_friction, p.particle_friction);
    });
    if (group == groups.end())
      groups.push_back({i});
    else
      group->push_back(i);
  }
  std::vector<CurveSeries> out;
  for (const auto& group : groups) {
    const auto& first = points[group.front()];
    const auto varies = [&](CurveVariable v) {
      return std::any_of(group.begin(), group.end(), [&](std::size_t i) {
        return !same(std::log(curve_value(points[i], v)), std::log(curve_value(first, v)));
      });
    };
    const CurveVariable variable = at_volume(first) ? CurveVariable::solid_fraction
                                   : varies(CurveVariable::shear_rate) ? CurveVariable::shear_rate
                                   : immersed(first) && varies(CurveVariable::liquid_viscosity)
                                       ? CurveVariable::liquid_viscosity
                                       : CurveVariable::normal_stress;
    const int v = index_of(variable);
    // Levels only where x does not tell the rows' conditions apart.
    bool ambiguous = false;
    for (std::size_t a = 0; a < group.size() && !ambiguous; ++a)
      for (std::size_t b = a + 1; b < group.size() && !ambiguous; ++b) {
        const auto ca = conditions_of(points[group[a]]), cb = conditions_of(points[group[b]]);
        ambiguous = same(ca[v], cb[v]) && !others_agree(ca, cb, v, false);
      }
    std::vector<std::vector<std::size_t>> levels;
    if (!ambiguous) {
      levels.push_back(group);
    } else {
      std::vector<std::size_t> sorted = group;  // by the other conditions, for a stable order
      std::stable_sort(sorted.begin(), sorted.end(), [&](std::size_t a, std::size_t b) {
        auto ca = conditions_of(points[a]), cb = conditions_of(points[b]);
        ca[v] = cb[v] = 0;
        for (auto& c : ca) c = std::isnan(c) ? 0 : c;
        for (auto& c : cb) c = std::isnan(c) ? 0 : c;
        return ca < cb;
      });
      for (const auto i : sorted) {
        auto level = std::find_if(levels.begin(), levels.end(), [&](const auto& l) {
          return others_agree(conditions_of(points[l.front()]), conditions_of(points[i]), v, true);
        });
        if (level == levels.end())
          levels.push_back({i});
        else
          level->push_back(i);
      }
    }
    for (const auto& level : levels) {
      CurveSeries s = make_series(points, level, variable);
      if (s.nodes.size() >= 2) out.push_back(std::move(s));
    }
  }
  return out;
}

DataPoint curve_condition(const CurveSeries& series, double x) {
  const bool linear = series.variable == CurveVariable::solid_fraction;
  const int v = index_of(series.variable);
  x = std::clamp(x, series.lower, series.upper);
  const double u = linear ? x : std::log(x);
  std::vector<Conditions> c;
  for (const auto& node : series.nodes) c.push_back(conditions_of(node));
  std::size_t k = 1;
  while (k + 1 < c.size() && c[k][v] < u) ++k;
  if (u == c[k - 1][v]) return series.nodes[k - 1];
  if (u == c[k][v]) return series.nodes[k];
  // Between the nodes: each condition a monotone cubic in u (γ̇, σ_yy, η0 in their logarithm).
  const auto at = [&](int q) {
    std::vector<double> y;
    for (const auto& node : c) y.push_back(node[q]);
    return std::isnan(y[k]) ? NAN : monotone_cubic(c, v, y, k, u);
  };
  DataPoint p = series.nodes[k - 1];
  p.shear_rate = series.variable == CurveVariable::shear_rate ? x : std::exp(at(ln_rate));
  if (!at_volume(p))
    p.normal_stress = series.variable == CurveVariable::normal_stress ? x : std::exp(at(ln_stress));
  if (at_volume(p)) p.value[static_cast<int>(Observable::solid_fraction)] = linear ? x : at(phi);
  if (immersed(p))
    p.liquid_viscosity =
        series.variable == CurveVariable::liquid_viscosity ? x : std::exp(at(ln_viscosity));
  p.inertial_number = NAN;  // a model output here, not a measured one
  return p;
}

std::vector<double> curve_grid(const CurveSeries& series, int count) {
  std::vector<double> x(static_cast<std::size_t>(std::max(count, 2)));
  const double n = static_cast<double>(x.size() - 1);
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double t = static_cast<double>(i) / n;
    x[i] = series.variable == CurveVariable::solid_fraction
               ? series.lower + t * (series.upper - series.lower)
               : series.lower * std::pow(series.upper / series.lower, t);
  }
  x.front() = series.lower;  // the ends exactly
  x.back() = series.upper;
  return x;
}

std::vector<long> write_model_curves(core::ResultFile& out, const std::vector<DataPoint>& points,
                                     const std::map<std::string, const CalibratedModel*>& models,
                                     int count) {
  namespace c = core::columns;
  std::vector<long> member(points.size(), -1L);
  const auto series = curve_series(points);
  for (std::size_t n = 0; n < series.size(); ++n) {
    const CurveSeries& s = series[n];
    for (const auto row : s.rows) member[row] = static_cast<long>(n);
    const std::string group = fmt::format("/curve/{}", n);
    const bool volume = s.protocol == Protocol::constant_volume;
    const bool wet = std::isfinite(s.nodes.front().liquid_viscosity);
    const std::string along =
        fmt::format(", along the model curve over the DEM rows' {} ({} to {})",
                    curve_variable_name(s.variable), s.lower, s.upper);
    std::vector<DataPoint> at;
    for (const double x : curve_grid(s, count)) at.push_back(curve_condition(s, x));
    const auto column = [&](auto get) {
      std::vector<double> values;
      for (const auto& p : at) values.push_back(get(p));
      return values;
    };
    // The conditions (the imposed ones; at constant volume σ_yy and I are model outputs).
    out.write(group + "/" + c::shear_rate.name, column([](auto& p) { return p.shear_rate; }),
              c::shear_rate.unit, std::string(c::shear_rate.description) + along);
    if (volume) {
      out.write(
          group + "/" + c::solid_fraction.name,
          column([](auto& p) { return p.value[static_cast<int>(Observable::solid_fraction)]; }),
          c::solid_fraction.unit, std::string("imposed ") + c::solid_fraction.description + along);
    } else {
      out.write(group + "/" + c::normal_stress.name,
                column([](auto& p) { return p.normal_stress; }), c::normal_stress.unit,
                std::string("imposed ") + c::normal_stress.description + along);
      const auto& col = models.begin()->second->settings.collisional_parameters;
      // I = γ̇ d / sqrt(σ_yy/ρ_p) of the imposed σ_yy (the DEM's definition, as /data)
      out.write(group + "/" + c::inertial_number.name, column([&](auto& p) {
                  return p.shear_rate * col.diameter /
                         std::sqrt(p.normal_stress / col.particle_density);
                }),
                c::inertial_number.unit, std::string(c::inertial_number.description) + along);
    }
    if (wet) {
      out.write(group + "/" + c::liquid_viscosity.name,
                column([](auto& p) { return p.liquid_viscosity; }), c::liquid_viscosity.unit,
                std::string(c::liquid_viscosity.description) + along);
      if (!volume)
        out.write(group + "/" + c::viscous_number.name, column([](auto& p) {
                    return p.liquid_viscosity * p.shear_rate / p.normal_stress;
                  }),
                  c::viscous_number.unit, std::string(c::viscous_number.description) + along);
    }
    for (const auto& [name, model] : models) {
      std::vector<SteadyShearState> states;
      for (const auto& p : at) {
        try {
          states.push_back(predict(*model, p));
        } catch (const std::exception&) {  // a parameter outside a closure's domain
          states.push_back(SteadyShearState{});
        }
      }
      for (int k = 0; k < observable_count; ++k) {
        std::vector<double> values;
        for (const auto& st : states) values.push_back(st.ok ? predicted(st, Observable(k)) : NAN);
        out.write(
            group + "/" + name + "/" + observable_names()[k], values, "1",
            "continuum steady " + observable_names()[k] + " (" + name + " parameters)" + along);
      }
      std::vector<double> I;
      for (const auto& st : states) I.push_back(st.ok ? st.inertial_number : NAN);
      out.write(group + "/" + name + "/" + c::inertial_number.name, I, c::inertial_number.unit,
                "continuum I (" + name + " parameters)" + along);
    }
    // The axis the plot draws against: I at constant pressure (φ, σ_yy swept), J over η0, φ at
    // constant volume.
    out.attribute(group, "protocol", protocol_name(s.protocol));
    out.attribute(group, "variable", curve_variable_name(s.variable));
    out.attribute(group, "axis",
                  volume                                          ? c::solid_fraction.name
                  : s.variable == CurveVariable::liquid_viscosity ? c::viscous_number.name
                                                                  : c::inertial_number.name);
    out.attribute(group, "particle_friction", s.nodes.front().particle_friction);
    out.attribute(group, "count", static_cast<long>(at.size()));
    out.attribute(group, "rows", static_cast<long>(s.rows.size()));
  }
  return member;
}

}  // namespace granflow::calibration
