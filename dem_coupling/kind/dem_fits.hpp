// The science of a DEM sweep, from its steady table (docs/dem_dataset.md, /fits):
//   dry sweeps: μ(I) and φ(I) fitted per particle friction (inertial_law_fit.hpp) and compared
//     with the published DEM values;
//   immersed sweeps: the free mixed-number law μ(K), φ(K) with α (mixed_number_law_fit.hpp), and
//     per point the contact and lubrication stress ratios τ_contact/σ_yy, τ_lub/σ_yy against
//     Boyer et al. 2011's contact part μ_c(J) and hydrodynamic part μ_h(J).
// Used at the end of `granflow run` (dem_kind.cpp) and by `granflow report RUN_DIR`
// (analysis/report.cpp, dem_fits_file.hpp), which re-derives it from an existing result.h5.
// Header-only (see statistics/least_squares.hpp).
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "statistics/steady_state.hpp"
#include "dem_coupling/kind/inertial_law_fit.hpp"
#include "dem_coupling/kind/mixed_number_law_fit.hpp"

namespace granflow::dem {

// Steady ratio <part>/<σ_yy> over series[start:] and its standard error (correlated_mean,
// statistics/steady_state.hpp) of the linearised residual part − ratio σ_yy (delta method, as μ in
// dem_kind.cpp).
struct StressRatio {
  double value = std::numeric_limits<double>::quiet_NaN();
  double error = std::numeric_limits<double>::quiet_NaN();
};
inline StressRatio stress_ratio_of_series(const std::vector<double>& part,
                                          const std::vector<double>& sigma, std::size_t start) {
  StressRatio out;
  if (part.size() != sigma.size() || start + 4 > sigma.size()) return out;
  const auto p = statistics::correlated_mean(std::span(part).subspan(start));
  const auto s = statistics::correlated_mean(std::span(sigma).subspan(start));
  out.value = p.mean / s.mean;
  std::vector<double> residual(sigma.size());
  for (std::size_t i = 0; i < sigma.size(); ++i) residual[i] = part[i] - out.value * sigma[i];
  out.error = statistics::correlated_mean(std::span(residual).subspan(start)).standard_error / s.mean;
  return out;
}

// One row per sweep condition (NaN for a failed condition), the columns of /steady used here.
struct DemSteadyTable {
  std::vector<double> particle_friction, inertial, inertial_err, friction, friction_err,
      solid_fraction, solid_fraction_err;
  bool wet = false;  // immersed: the columns below are filled
  std::vector<double> stokes, viscous, viscous_err, friction_contact, friction_contact_err,
      friction_lubrication, friction_lubrication_err;
  std::size_t rows() const { return friction.size(); }
};

// Per condition of an immersed sweep: DEM stress ratios against Boyer's parts at the same J.
struct ViscousSplit {
  std::vector<double> contact_law, contact_law_err, hydrodynamic_law, contact_residual,
      friction_law, solid_fraction_law;
  // Over the viscous points (St <= 1, where Boyer's law applies): Σ residual² / n, the count, and
  // the mean of τ_lub/σ_yy over μ_h(J).
  double contact_chi2_per_point = std::numeric_limits<double>::quiet_NaN();
  double lubrication_share_of_hydrodynamic = std::numeric_limits<double>::quiet_NaN();
  int viscous_points = 0;
};

struct DemFits {
  std::vector<InertialLawFit> dry;  // one per particle friction (dry sweeps)
  bool wet = false;
  MixedNumberLawFit mixed;
  ViscousSplit split;
};

// St <= 1: the viscous end (J >= I², inertia at most comparable to viscous stress).
constexpr double viscous_stokes_limit = 1.0;

inline DemFits compute_dem_fits(const DemSteadyTable& t) {
  DemFits f;
  f.wet = t.wet;
  if (!t.wet) {
    std::set<double> frictions;
    for (double m : t.particle_friction)
      if (std::isfinite(m)) frictions.insert(m);
    for (double m : frictions) {
      std::vector<double> I, Ie, mu, mue, phi, phie;
      for (std::size_t k = 0; k < t.rows(); ++k) {
        if (t.particle_friction[k] != m) continue;
        I.push_back(t.inertial[k]);
        mu.push_back(t.friction[k]);
        mue.push_back(t.friction_err[k]);
        phi.push_back(t.solid_fraction[k]);
        phie.push_back(t.solid_fraction_err[k]);
      }
      f.dry.push_back(fit_inertial_law(m, I, mu, mue, phi, phie));
    }
    return f;
  }
  f.mixed = fit_mixed_number_law(t.viscous, t.inertial, t.friction, t.friction_err,
                                 t.solid_fraction, t.solid_fraction_err);
  ViscousSplit& s = f.split;
  double chi2 = 0, share = 0;
  for (std::size_t k = 0; k < t.rows(); ++k) {
    const double j = t.viscous[k];
    const double law = boyer2011::contact_friction(j);
    const double law_err = boyer2011::contact_friction_slope(j) * t.viscous_err[k];
    s.contact_law.push_back(law);
    s.contact_law_err.push_back(law_err);
    s.hydrodynamic_law.push_back(boyer2011::hydrodynamic_friction(j));
    s.friction_law.push_back(law + boyer2011::hydrodynamic_friction(j));
    s.solid_fraction_law.push_back(boyer2011::solid_fraction(j));
    const double combined =
        std::hypot(t.friction_contact_err[k], std::isfinite(law_err) ? law_err : 0.0);
    const double residual = (t.friction_contact[k] - law) / combined;
    s.contact_residual.push_back(residual);
    if (std::isfinite(residual) && t.stokes[k] <= viscous_stokes_limit) {
      ++s.viscous_points;
      chi2 += residual * residual;
      share += t.friction_lubrication[k] / boyer2011::hydrodynamic_friction(j);
    }
  }
  if (s.viscous_points > 0) {
    s.contact_chi2_per_point = chi2 / s.viscous_points;
    s.lubrication_share_of_hydrodynamic = share / s.viscous_points;
  }
  return f;
}

// The numbers of a dry fit, as /fits/<label> attributes and fit.<label>.* summary keys: the
// law's parameters and errors by name (GDR MiDi: mu_s, mu_2, I_0, phi_c, a; Peyneau & Roux:
// mu_0, c, alpha, phi_rcp, b, beta), the I → 0 limits under common names (mu_s and phi_c: for
// Peyneau & Roux these are μ_0 and φ_RCP), goodness of fit, a law code (law_peyneau_roux: 1 for
// Peyneau & Roux, 0 for GDR MiDi; the name is the string attribute "law") and the deviations from
// the published values.
inline std::vector<std::pair<std::string, double>> dry_fit_numbers(const InertialLawFit& d) {
  std::vector<std::pair<std::string, double>> out = {
      {"particle_friction", d.particle_friction},
      {"points", double(d.inertial.size())},
      {"law_peyneau_roux", d.law == DryLaw::peyneau_roux ? 1.0 : 0.0}};
  const DryLawText text = dry_law_text(d.law);
  for (std::size_t j = 0; j < text.friction_parameters.size(); ++j) {
    out.emplace_back(text.friction_parameters[j], d.mu_value(int(j)));
    out.emplace_back(text.friction_parameters[j] + "_err", d.mu_error(int(j)));
  }
  for (std::size_t j = 0; j < text.solid_fraction_parameters.size(); ++j) {
    out.emplace_back(text.solid_fraction_parameters[j], d.phi_value(int(j)));
    out.emplace_back(text.solid_fraction_parameters[j] + "_err", d.phi_error(int(j)));
  }
  if (!d.gdr_midi()) {
    out.emplace_back("mu_s", d.mu_s());
    out.emplace_back("mu_s_err", d.mu_s_err());
    out.emplace_back("phi_c", d.phi_c());
    out.emplace_back("phi_c_err", d.phi_c_err());
  }
  const std::pair<const char*, double> rest[] = {
      {"mu_chi2_red", d.mu.chi2_red},
      {"mu_dof", double(d.mu.dof)},
      {"mu_max_residual", d.mu.max_abs_residual()},
      {"mu_at_bound", d.mu.at_bound ? 1.0 : 0.0},
      {"phi_chi2_red", d.phi.chi2_red},
      {"phi_dof", double(d.phi.dof)},
      {"phi_max_residual", d.phi.max_abs_residual()},
      {"phi_at_bound", d.phi.at_bound ? 1.0 : 0.0},
      {"mu_s_published_deviation", d.mu_s_published_deviation()},
      {"phi_c_published_deviation", d.phi_c_published_deviation()}};
  for (const auto& [name, value] : rest) out.emplace_back(name, value);
  return out;
}

// One line for the run log: "μ_p = 0: peyneau_roux μ(I) mu_0 = 0.102 ± 0.008, ... (χ²_red 1.6);
// φ(I) phi_rcp = ... (χ²_red 3.5); 6 points".
inline std::string dry_fit_log_line(const InertialLawFit& d) {
  const DryLawText text = dry_law_text(d.law);
  auto part = [](const LeastSquaresFit& fit, const std::vector<std::string>& names) {
    std::string out;
    for (std::size_t j = 0; j < names.size(); ++j) {
      const bool has = j < std::size_t(fit.estimate.size());
      out += fmt::format("{}{} = {:.4g} ± {:.2g}", j ? ", " : "", names[j],
                         has ? fit.estimate[j] : NAN, has ? fit.standard_error[j] : NAN);
    }
    return out +
           fmt::format(" (χ²_red {:.3g}{})", fit.chi2_red, fit.at_bound ? ", on a bound" : "");
  };
  return fmt::format("μ_p = {:g}: {} μ(I) {}; φ(I) {}; {} points", d.particle_friction,
                     dry_law_name(d.law), part(d.mu, text.friction_parameters),
                     part(d.phi, text.solid_fraction_parameters), d.inertial.size());
}

// Writes /fits (docs/dem_dataset.md) through `sink`, which has the ResultFile interface:
// attribute(group, name, double / long / string) and write(path, values, unit, description).
template <class Sink>
void write_dem_fits(const DemFits& f, const DemSteadyTable& t, Sink& sink) {
  auto fit_values = [](const std::vector<double>& x, auto law) {
    std::vector<double> y;
    for (double v : x) y.push_back(law(v));
    return y;
  };
  sink.attribute("/fits", "method",
                 std::string("weighted least squares, error bars = DEM standard errors, "
                             "covariance (J^T W J)^-1 not rescaled (docs/dem_dataset.md)"));
  for (const InertialLawFit& d : f.dry) {
    const std::string g = "/fits/" + friction_label(d.particle_friction);
    const DryLawText text = dry_law_text(d.law);
    sink.attribute(g, "law", std::string(dry_law_name(d.law)));
    sink.attribute(g, "law_reference", std::string(text.reference));
    sink.attribute(g, "friction_law", std::string(text.friction_formula));
    sink.attribute(g, "solid_fraction_law", std::string(text.solid_fraction_formula));
    for (const auto& [name, value] : dry_fit_numbers(d)) {
      const std::string_view n = name;
      if (n == "points" || n == "law_peyneau_roux" || n.ends_with("_dof") ||
          n.ends_with("_at_bound"))  // counts and flags as integers
        sink.attribute(g, name, static_cast<long>(value));
      else
        sink.attribute(g, name, value);
    }
    if (const auto pub = published_dem_law(d.particle_friction)) {
      sink.attribute(g, "published_mu_s_low", pub->mu_s_low);
      sink.attribute(g, "published_mu_s_high", pub->mu_s_high);
      sink.attribute(g, "published_phi_c", pub->phi_c);
      sink.attribute(g, "published_phi_c_rounding", PublishedDemLaw::phi_c_rounding);
      sink.attribute(g, "published_source", std::string(pub->source));
    }
    sink.write(g + "/inertial_number", d.inertial, "1", "I of the points fitted");
    sink.write(g + "/friction", d.friction, "1", "DEM μ of the points fitted");
    sink.write(g + "/friction_err", d.friction_err, "1", "their standard errors");
    if (d.mu.estimate.size()) {
      sink.write(g + "/friction_fit",
                 fit_values(d.inertial, [&](double i) { return d.friction_at(i); }), "1",
                 std::string("fitted ") + text.friction_formula + " at the points");
      std::vector<double> r(d.mu.normalised_residuals.data(),
                            d.mu.normalised_residuals.data() + d.mu.normalised_residuals.size());
      sink.write(g + "/friction_residual", r, "1", "(μ − μ_fit)/err μ");
    }
    sink.write(g + "/solid_fraction", d.solid_fraction, "1", "DEM φ of the points fitted");
    sink.write(g + "/solid_fraction_err", d.solid_fraction_err, "1", "their standard errors");
    if (d.phi.estimate.size()) {
      sink.write(g + "/solid_fraction_fit",
                 fit_values(d.inertial, [&](double i) { return d.solid_fraction_at(i); }), "1",
                 std::string("fitted ") + text.solid_fraction_formula + " at the points");
      std::vector<double> r(d.phi.normalised_residuals.data(),
                            d.phi.normalised_residuals.data() + d.phi.normalised_residuals.size());
      sink.write(g + "/solid_fraction_residual", r, "1", "(φ − φ_fit)/err φ");
    }
  }
  if (!f.wet) return;
  const MixedNumberLawFit& m = f.mixed;
  const std::string g = "/fits/mixed_number";
  const char* names[] = {"mu_1", "mu_2", "K_0", "alpha"};
  for (int j = 0; j < 4; ++j) {
    sink.attribute(g, names[j], m.value(j));
    sink.attribute(g, std::string(names[j]) + "_err", m.error(j));
  }
  sink.attribute(g, "points", static_cast<long>(m.viscous.size()));
  sink.attribute(g, "mu_chi2_red", m.mu.chi2_red);
  sink.attribute(g, "mu_dof", static_cast<long>(m.mu.dof));
  sink.attribute(g, "mu_max_residual", m.mu.max_abs_residual());
  const bool phi_ok = m.phi.estimate.size() == 2;
  sink.attribute(g, "phi_m", phi_ok ? m.phi.estimate[0] : NAN);
  sink.attribute(g, "phi_m_err", phi_ok ? m.phi.standard_error[0] : NAN);
  sink.attribute(g, "b", phi_ok ? m.phi.estimate[1] : NAN);
  sink.attribute(g, "b_err", phi_ok ? m.phi.standard_error[1] : NAN);
  sink.attribute(g, "phi_chi2_red", m.phi.chi2_red);
  sink.attribute(g, "phi_dof", static_cast<long>(m.phi.dof));
  if (m.mu.estimate.size()) {
    std::vector<double> k;
    for (std::size_t i = 0; i < m.viscous.size(); ++i) k.push_back(m.mixed_number(i));
    sink.write(g + "/mixed_number", k, "1", "K = J + α I² with the fitted α (points fitted)");
    sink.write(g + "/friction", m.friction, "1", "DEM μ of the points fitted");
    sink.write(g + "/friction_err", m.friction_err, "1", "their standard errors");
    std::vector<double> r(m.mu.normalised_residuals.data(),
                          m.mu.normalised_residuals.data() + m.mu.normalised_residuals.size());
    sink.write(g + "/friction_residual", r, "1", "(μ − μ(K) fit)/err μ");
  }
  const std::string b = "/fits/boyer_split";
  const ViscousSplit& s = f.split;
  sink.attribute(b, "viscous_stokes_limit", viscous_stokes_limit);
  sink.attribute(b, "viscous_points", static_cast<long>(s.viscous_points));
  sink.attribute(b, "contact_chi2_per_point", s.contact_chi2_per_point);
  sink.attribute(b, "lubrication_share_of_hydrodynamic", s.lubrication_share_of_hydrodynamic);
  sink.write(b + "/stokes_number", t.stokes, "1", "St per condition (sweep order)");
  sink.write(b + "/viscous_number", t.viscous, "1", "J per condition");
  sink.write(b + "/friction_contact", t.friction_contact, "1", "τ_contact/σ_yy (DEM)");
  sink.write(b + "/friction_contact_err", t.friction_contact_err, "1", "standard error");
  sink.write(b + "/friction_lubrication", t.friction_lubrication, "1", "τ_lub/σ_yy (DEM)");
  sink.write(b + "/friction_lubrication_err", t.friction_lubrication_err, "1", "standard error");
  sink.write(b + "/contact_law", s.contact_law, "1", "Boyer μ_c(J) = μ1 + (μ2 − μ1)/(1 + J0/J)");
  sink.write(b + "/contact_law_err", s.contact_law_err, "1", "from the error of J");
  sink.write(b + "/hydrodynamic_law", s.hydrodynamic_law, "1", "Boyer μ_h(J) = J + 2.5 ν_m J^½");
  sink.write(b + "/contact_residual", s.contact_residual, "1",
             "(τ_contact/σ_yy − μ_c(J)) / combined standard error");
}

// summary.json entries (docs/dem_dataset.md): fit.<label>.* (dry), fit.* and boyer.*.N (wet).
inline std::map<std::string, double> dem_fit_summary(const DemFits& f, const DemSteadyTable& t) {
  std::map<std::string, double> out;
  for (const InertialLawFit& d : f.dry) {
    const std::string p = "fit." + friction_label(d.particle_friction) + ".";
    for (const auto& [name, value] : dry_fit_numbers(d)) out[p + name] = value;
  }
  if (!f.wet) return out;
  const MixedNumberLawFit& m = f.mixed;
  out["fit.alpha"] = m.alpha(), out["fit.alpha_err"] = m.alpha_err();
  out["fit.mu_1"] = m.value(0), out["fit.mu_1_err"] = m.error(0);
  out["fit.mu_2"] = m.value(1), out["fit.mu_2_err"] = m.error(1);
  out["fit.K_0"] = m.value(2), out["fit.K_0_err"] = m.error(2);
  out["fit.mu_K_chi2_red"] = m.mu.chi2_red, out["fit.mu_K_dof"] = m.mu.dof;
  out["fit.mu_K_max_residual"] = m.mu.max_abs_residual();
  out["fit.mixed_points"] = double(m.viscous.size());
  if (m.phi.estimate.size() == 2) {
    out["fit.phi_m"] = m.phi.estimate[0], out["fit.phi_m_err"] = m.phi.standard_error[0];
    out["fit.b"] = m.phi.estimate[1], out["fit.b_err"] = m.phi.standard_error[1];
    out["fit.phi_K_chi2_red"] = m.phi.chi2_red;
  }
  const ViscousSplit& s = f.split;
  for (std::size_t k = 0; k < t.rows(); ++k) {
    if (!std::isfinite(t.friction_contact[k])) continue;
    const std::string n = fmt::format(".{}", k);
    out["boyer.mu_contact" + n] = t.friction_contact[k];
    out["boyer.mu_contact_err" + n] = t.friction_contact_err[k];
    out["boyer.mu_lub" + n] = t.friction_lubrication[k];
    out["boyer.mu_lub_err" + n] = t.friction_lubrication_err[k];
    out["boyer.mu_c" + n] = s.contact_law[k];
    out["boyer.mu_h" + n] = s.hydrodynamic_law[k];
    out["boyer.contact_residual" + n] = s.contact_residual[k];
  }
  out["boyer.viscous_points"] = s.viscous_points;
  out["boyer.contact_chi2_per_point"] = s.contact_chi2_per_point;
  out["boyer.lubrication_share_of_hydrodynamic"] = s.lubrication_share_of_hydrodynamic;
  return out;
}

// Markdown tables for report.md.
inline std::string dem_fits_markdown(const DemFits& f, const DemSteadyTable& t) {
  auto num = [](double v, const char* format = "{:.4g}") {
    return std::isfinite(v) ? fmt::format(fmt::runtime(format), v) : std::string("NaN");
  };
  std::string md;
  if (!f.dry.empty()) {
    md +=
        "## μ(I) and φ(I) fits (weighted by the DEM standard errors)\n\n"
        "The law is chosen per friction (dem_coupling/kind/inertial_law_fit.hpp): GDR MiDi for "
        "frictional spheres, μ(I) = μ_s + (μ_2 − μ_s)/(1 + I_0/I), φ(I) = φ_c − a I "
        "(docs/dem_dataset.md); Peyneau & Roux 2008 for frictionless spheres, μ(I) = μ_0 + c I^α, "
        "φ(I) = φ_RCP − "
        "b I^β; every parameter fitted. Residuals are (DEM − fit)/SE; χ²_red ≈ 1 when the points "
        "lie on the law within their error bars. μ(0) and φ(0) are the I → 0 limits (μ_s or μ_0, "
        "φ_c or φ_RCP).\n\n"
        "| μ_p | law | points | μ(I) parameters | χ²_red μ (dof) | max \\|res\\| μ | φ(I) "
        "parameters | χ²_red φ (dof) | max \\|res\\| φ | published μ(0), φ(0) "
        "|\n|---|---|---|---|---|---|---|---|---|---|\n";
    auto parameters = [&](const LeastSquaresFit& fit, const std::vector<std::string>& names) {
      std::string text;
      for (std::size_t j = 0; j < names.size(); ++j)
        text += fmt::format(
            "{}{} = {} ± {}", j ? ", " : "", names[j],
            num(j < std::size_t(fit.estimate.size()) ? fit.estimate[j] : NAN),
            num(j < std::size_t(fit.standard_error.size()) ? fit.standard_error[j] : NAN,
                "{:.2g}"));
      return text + (fit.at_bound ? " (on a bound)" : "");
    };
    for (const InertialLawFit& d : f.dry) {
      const auto pub = published_dem_law(d.particle_friction);
      const DryLawText text = dry_law_text(d.law);
      md += fmt::format(
          "| {:g} | {} | {} | {} | {} ({}) | {} | {} | {} ({}) | {} | {} |\n", d.particle_friction,
          dry_law_name(d.law), d.inertial.size(), parameters(d.mu, text.friction_parameters),
          num(d.mu.chi2_red, "{:.3g}"), d.mu.dof, num(d.mu.max_abs_residual(), "{:.2g}"),
          parameters(d.phi, text.solid_fraction_parameters), num(d.phi.chi2_red, "{:.3g}"),
          d.phi.dof, num(d.phi.max_abs_residual(), "{:.2g}"),
          pub ? fmt::format("{}, {:g} ({})",
                            pub->mu_s_high > pub->mu_s_low
                                ? fmt::format("{:g}-{:g}", pub->mu_s_low, pub->mu_s_high)
                                : fmt::format("{:g}", pub->mu_s_low),
                            pub->phi_c, pub->source)
              : std::string("-"));
    }
    md +=
        "\nAgainst the published DEM values: μ(0) outside the published range, and φ(0) "
        "outside the published value's rounding interval ± 0.0005 (three digits quoted), in SE "
        "(0 = inside):";
    for (const InertialLawFit& d : f.dry)
      md += fmt::format(" μ_p = {:g}: {} and {};", d.particle_friction,
                        num(d.mu_s_published_deviation(), "{:+.2f}"),
                        num(d.phi_c_published_deviation(), "{:+.1f}"));
    md +=
        "\n\nPer point (residuals in standard errors):\n\n| μ_p | I | μ | res μ | φ | res φ |\n"
        "|---|---|---|---|---|---|\n";
    for (const InertialLawFit& d : f.dry)
      for (std::size_t i = 0; i < d.inertial.size(); ++i)
        md += fmt::format(
            "| {:g} | {} | {} ± {} | {} | {} ± {} | {} |\n", d.particle_friction,
            num(d.inertial[i]), num(d.friction[i]), num(d.friction_err[i], "{:.2g}"),
            d.mu.normalised_residuals.size() ? num(d.mu.normalised_residuals[i], "{:+.2f}") : "-",
            num(d.solid_fraction[i]), num(d.solid_fraction_err[i], "{:.2g}"),
            d.phi.normalised_residuals.size() ? num(d.phi.normalised_residuals[i], "{:+.2f}")
                                              : "-");
    md += "\n";
  }
  if (!f.wet) return md;
  const MixedNumberLawFit& m = f.mixed;
  md += fmt::format(
      "## Mixed number K = J + α I² (free fit)\n\n"
      "μ(K) = μ_1 + (μ_2 − μ_1)/(1 + K_0/K) with μ_1, μ_2, K_0, α fitted together over {} "
      "points: α = {} ± {}, μ_1 = {} ± {}, μ_2 = {} ± {}, K_0 = {} ± {}; χ²_red = {} ({} dof), "
      "worst point {} SE.",
      m.viscous.size(), num(m.alpha()), num(m.alpha_err(), "{:.2g}"), num(m.value(0)),
      num(m.error(0), "{:.2g}"), num(m.value(1)), num(m.error(1), "{:.2g}"), num(m.value(2)),
      num(m.error(2), "{:.2g}"), num(m.mu.chi2_red, "{:.3g}"), m.mu.dof,
      num(m.mu.max_abs_residual(), "{:.2g}"));
  if (m.phi.estimate.size() == 2)
    md += fmt::format(" φ(K) = φ_m/(1 + b K^½): φ_m = {} ± {}, b = {} ± {}, χ²_red = {}.",
                      num(m.phi.estimate[0]), num(m.phi.standard_error[0], "{:.2g}"),
                      num(m.phi.estimate[1]), num(m.phi.standard_error[1], "{:.2g}"),
                      num(m.phi.chi2_red, "{:.3g}"));
  md +=
      "\n\n## Viscous end against Boyer et al. 2011: contact and hydrodynamic parts\n\n"
      "μ_c(J) = 0.32 + 0.38/(1 + 0.005/J) (contact), μ_h(J) = J + 2.5 · 0.585 J^½ "
      "(hydrodynamic). The DEM has pairwise lubrication for h < h_max only (no far-field "
      "hydrodynamics).\n\n| point | St | J | μ (DEM) | μ Boyer | τ_contact/σ_yy | μ_c(J) | res "
      "(SE) | τ_lub/σ_yy | μ_h(J) | φ (DEM) | φ Boyer |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  const ViscousSplit& s = f.split;
  for (std::size_t k = 0; k < t.rows(); ++k)
    md += fmt::format(
        "| {} | {:.3g} | {} | {} ± {} | {} | {} ± {} | {} | {} | {} ± {} | {} | {} ± {} | {} |\n",
        k, t.stokes[k], num(t.viscous[k]), num(t.friction[k]), num(t.friction_err[k], "{:.2g}"),
        num(s.friction_law[k]), num(t.friction_contact[k]),
        num(t.friction_contact_err[k], "{:.2g}"), num(s.contact_law[k]),
        num(s.contact_residual[k], "{:+.2f}"), num(t.friction_lubrication[k]),
        num(t.friction_lubrication_err[k], "{:.2g}"), num(s.hydrodynamic_law[k]),
        num(t.solid_fraction[k]), num(t.solid_fraction_err[k], "{:.2g}"),
        num(s.solid_fraction_law[k]));
  md += fmt::format(
      "\nViscous points (St <= {:g}): {}; Σ res²/n of the contact part = {}; τ_lub/σ_yy is on "
      "average {} of μ_h(J).\n\n",
      viscous_stokes_limit, s.viscous_points, num(s.contact_chi2_per_point, "{:.3g}"),
      num(s.lubrication_share_of_hydrodynamic, "{:.2f}"));
  return md;
}

}  // namespace granflow::dem
