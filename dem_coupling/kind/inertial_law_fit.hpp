// The dry inertial rheology fitted to DEM steady points, one fit per interparticle
// friction μ_p, the law selected by name:
//   "gdr_midi"      frictional spheres (μ_p > 0): μ = μ_s + (μ_2 − μ_s)/(1 + I_0/I), φ = φ_c − a I
//                   (gdr_midi_law.hpp);
//   "peyneau_roux"  frictionless spheres (μ_p = 0): μ = μ_0 + c I^α, φ = φ_RCP − b I^β
//                   (peyneau_roux_law.hpp), since the GDR MiDi form does not fit them
//                   (docs/dem_dataset.md: χ²_red 8 and 52 on the full dry sweep).
// Every parameter is fitted, the published μ_0 and φ_RCP included: holding them would assume the
// agreement that the comparison with the published values is meant to test, and the six points
// of the dry sweep (I = 0.01-0.3) determine them to ±0.008 and ±0.0003 (docs/dem_dataset.md).
// Weighted least squares with the DEM standard errors (statistics/least_squares.hpp), bounds by
// transform: I_0, c, b > 0; μ_0 >= 0; α, β in (0, 2); φ_RCP in (0, π/√18) (FCC packing). The
// straight line φ(I) of GDR MiDi is solved in closed form.
// Published DEM values compared with (the I → 0 limits μ_s|μ_0 and φ_c|φ_RCP):
//   μ_p = 0.5: μ_s ≈ 0.35-0.38, φ_c ≈ 0.587 (Chialvo, Sun & Sundaresan 2012, PRE 85, 021305),
//   μ_p = 0:   μ_0 ≈ 0.10 (internal friction angle ≈ 5.8°), φ_RCP ≈ 0.639
//              (Peyneau & Roux 2008, PRE 78, 011307; Chialvo et al. 2012).
// Header-only (see statistics/least_squares.hpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "statistics/least_squares.hpp"
#include "dem_coupling/kind/gdr_midi_law.hpp"
#include "dem_coupling/kind/peyneau_roux_law.hpp"

namespace granflow::dem {

using statistics::LeastSquaresFit;
using statistics::LineFit;
using statistics::ParameterBounds;

enum class DryLaw { gdr_midi, peyneau_roux };

inline const char* dry_law_name(DryLaw law) {
  return law == DryLaw::gdr_midi ? GdrMidiLaw::name : PeyneauRouxLaw::name;
}
// Throws std::invalid_argument naming the valid names.
inline DryLaw dry_law_from_name(const std::string& name) {
  if (name == GdrMidiLaw::name) return DryLaw::gdr_midi;
  if (name == PeyneauRouxLaw::name) return DryLaw::peyneau_roux;
  throw std::invalid_argument("unknown dry rheology law '" + name + "' (expected " +
                              GdrMidiLaw::name + " or " + PeyneauRouxLaw::name + ")");
}
// The law for a friction: Peyneau & Roux for frictionless spheres, GDR MiDi otherwise.
inline DryLaw dry_law_for_friction(double particle_friction) {
  return particle_friction == 0.0 ? DryLaw::peyneau_roux : DryLaw::gdr_midi;
}

struct DryLawText {
  const char* reference;
  const char* friction_formula;
  const char* solid_fraction_formula;
  std::vector<std::string> friction_parameters, solid_fraction_parameters;
};
inline DryLawText dry_law_text(DryLaw law) {
  auto names = [](const auto& list) {
    return std::vector<std::string>(std::begin(list), std::end(list));
  };
  if (law == DryLaw::gdr_midi)
    return {GdrMidiLaw::reference, GdrMidiLaw::friction_formula, GdrMidiLaw::solid_fraction_formula,
            names(GdrMidiLaw::friction_parameters), names(GdrMidiLaw::solid_fraction_parameters)};
  return {PeyneauRouxLaw::reference, PeyneauRouxLaw::friction_formula,
          PeyneauRouxLaw::solid_fraction_formula, names(PeyneauRouxLaw::friction_parameters),
          names(PeyneauRouxLaw::solid_fraction_parameters)};
}
inline double dry_law_friction(DryLaw law, double inertial, const Eigen::VectorXd& theta) {
  return law == DryLaw::gdr_midi ? GdrMidiLaw::friction(inertial, theta)
                                 : PeyneauRouxLaw::friction(inertial, theta);
}
inline double dry_law_solid_fraction(DryLaw law, double inertial, const Eigen::VectorXd& theta) {
  return law == DryLaw::gdr_midi ? GdrMidiLaw::solid_fraction(inertial, theta)
                                 : PeyneauRouxLaw::solid_fraction(inertial, theta);
}

struct PublishedDemLaw {
  double mu_s_low, mu_s_high;  // published range of the quasi-static friction μ_s (μ_0)
  double phi_c;                // critical (jamming) solid fraction (φ_RCP)
  const char* source;
  // Both φ_c are quoted to three digits without an error bar: any value in phi_c ± 0.0005
  // rounds to the quoted one, so that interval is what the DEM is compared with (like μ_s).
  static constexpr double phi_c_rounding = 0.0005;
};

// Published values for μ_p = 0.5 and μ_p = 0 (above); nothing for other μ_p.
inline std::optional<PublishedDemLaw> published_dem_law(double particle_friction) {
  if (std::abs(particle_friction - 0.5) < 1e-9)
    return PublishedDemLaw{0.35, 0.38, 0.587, "Chialvo, Sun & Sundaresan 2012"};
  if (particle_friction == 0.0)
    return PublishedDemLaw{0.10, 0.10, 0.639, "Peyneau & Roux 2008; Chialvo et al. 2012"};
  return std::nullopt;
}

// Summary label of a friction value: "frictionless" for μ_p = 0, else "mu_p_0p5" (no '.', so a
// summary key fit.<label>.mu_s has exactly three components).
inline std::string friction_label(double particle_friction) {
  if (particle_friction == 0.0) return "frictionless";
  char text[32];
  std::snprintf(text, sizeof text, "mu_p_%g", particle_friction);
  std::string label = text;
  std::replace(label.begin(), label.end(), '.', 'p');
  return label;
}

// The closed-form line φ = intercept + slope I as a fit of θ_φ = (φ_c, a = −slope).
inline LeastSquaresFit line_as_fit(const LineFit& line) {
  LeastSquaresFit fit;
  fit.points = line.points;
  fit.dof = line.dof;
  if (line.points < 3) return fit;
  fit.estimate = Eigen::Vector2d(line.intercept, -line.slope);
  fit.covariance.resize(2, 2);
  fit.covariance << line.intercept_err * line.intercept_err, -line.covariance, -line.covariance,
      line.slope_err * line.slope_err;
  fit.standard_error = Eigen::Vector2d(line.intercept_err, line.slope_err);
  fit.correlation =
      fit.covariance.array() / (fit.standard_error * fit.standard_error.transpose()).array();
  fit.normalised_residuals = Eigen::Map<const Eigen::VectorXd>(
      line.normalised_residuals.data(), Eigen::Index(line.normalised_residuals.size()));
  fit.chi2 = line.chi2;
  fit.chi2_red = line.chi2_red;
  fit.converged = fit.identifiable = std::isfinite(line.intercept_err);
  fit.parameter_at_bound.assign(2, false);
  return fit;
}

struct InertialLawFit {
  double particle_friction = 0;
  DryLaw law = DryLaw::gdr_midi;
  std::vector<double> inertial, friction, friction_err, solid_fraction, solid_fraction_err;
  LeastSquaresFit mu;   // θ_μ: (μ_s, μ_2, I_0) or (μ_0, c, α)
  LeastSquaresFit phi;  // θ_φ: (φ_c, a) or (φ_RCP, b, β)

  double mu_value(int j) const { return j < mu.estimate.size() ? mu.estimate[j] : NAN; }
  double mu_error(int j) const { return j < mu.standard_error.size() ? mu.standard_error[j] : NAN; }
  double phi_value(int j) const { return j < phi.estimate.size() ? phi.estimate[j] : NAN; }
  double phi_error(int j) const {
    return j < phi.standard_error.size() ? phi.standard_error[j] : NAN;
  }
  // The I → 0 limits of either law: μ_s (GDR MiDi) or μ_0 (Peyneau & Roux), φ_c or φ_RCP.
  double mu_s() const { return mu_value(0); }
  double mu_s_err() const { return mu_error(0); }
  double phi_c() const { return phi_value(0); }
  double phi_c_err() const { return phi_error(0); }
  // GDR MiDi parameters (NaN for the Peyneau & Roux law).
  bool gdr_midi() const { return law == DryLaw::gdr_midi; }
  double mu_2() const { return gdr_midi() ? mu_value(1) : NAN; }
  double mu_2_err() const { return gdr_midi() ? mu_error(1) : NAN; }
  double i_0() const { return gdr_midi() ? mu_value(2) : NAN; }
  double i_0_err() const { return gdr_midi() ? mu_error(2) : NAN; }
  double a() const { return gdr_midi() ? phi_value(1) : NAN; }
  double a_err() const { return gdr_midi() ? phi_error(1) : NAN; }
  // The fitted curves.
  double friction_at(double inertial_number) const {
    return mu.estimate.size() ? dry_law_friction(law, inertial_number, mu.estimate) : NAN;
  }
  double solid_fraction_at(double inertial_number) const {
    return phi.estimate.size() ? dry_law_solid_fraction(law, inertial_number, phi.estimate) : NAN;
  }
  // Distance of μ_s to the published range in its SE (0 inside), and φ_c − published φ_c in SE
  // (NaN without published values).
  double mu_s_published_deviation() const {
    const auto pub = published_dem_law(particle_friction);
    const double m = mu_s();
    if (!pub || !std::isfinite(m)) return NAN;
    return m < pub->mu_s_low    ? (m - pub->mu_s_low) / mu_s_err()
           : m > pub->mu_s_high ? (m - pub->mu_s_high) / mu_s_err()
                                : 0.0;
  }
  // Distance of φ_c outside the published value's rounding interval, in standard errors (0 inside).
  double phi_c_published_deviation() const {
    const auto pub = published_dem_law(particle_friction);
    const double p = phi_c();
    if (!pub || !std::isfinite(p)) return NAN;
    const double low = pub->phi_c - PublishedDemLaw::phi_c_rounding;
    const double high = pub->phi_c + PublishedDemLaw::phi_c_rounding;
    return p < low ? (p - low) / phi_c_err() : p > high ? (p - high) / phi_c_err() : 0.0;
  }
};

namespace inertial_law_detail {

// The smallest χ² over the starts (an empty fit if none has a finite χ²).
template <class Model>
LeastSquaresFit best_of(const Model& model, const std::vector<double>& y,
                        const std::vector<double>& sigma,
                        const std::vector<Eigen::VectorXd>& starts,
                        const std::vector<ParameterBounds>& bounds) {
  LeastSquaresFit best;
  for (const Eigen::VectorXd& start : starts) {
    LeastSquaresFit trial = statistics::weighted_least_squares(model, y, sigma, start, bounds);
    if (std::isfinite(trial.chi2) && (best.estimate.size() == 0 || trial.chi2 < best.chi2))
      best = std::move(trial);
  }
  if (best.estimate.size() == 0) best.points = int(y.size()), best.dof = int(y.size() - 3);
  return best;
}

}  // namespace inertial_law_detail

// Fits the points with finite I, μ, φ and positive error bars (a failed sweep point is NaN and
// skipped) with `law`. Needs more points than parameters (GDR MiDi: μ >= 4, φ >= 3; Peyneau &
// Roux: >= 4 each); with fewer the corresponding fit is empty (estimate of size 0, NaN).
inline InertialLawFit fit_inertial_law(double particle_friction, DryLaw law,
                                       const std::vector<double>& inertial,
                                       const std::vector<double>& friction,
                                       const std::vector<double>& friction_err,
                                       const std::vector<double>& solid_fraction,
                                       const std::vector<double>& solid_fraction_err) {
  using inertial_law_detail::best_of;
  InertialLawFit fit;
  fit.particle_friction = particle_friction;
  fit.law = law;
  for (std::size_t k = 0; k < inertial.size(); ++k) {
    const double values[] = {inertial[k], friction[k], friction_err[k], solid_fraction[k],
                             solid_fraction_err[k]};
    if (!std::all_of(std::begin(values), std::end(values),
                     [](double v) { return std::isfinite(v); }))
      continue;
    if (!(inertial[k] > 0 && friction_err[k] > 0 && solid_fraction_err[k] > 0)) continue;
    fit.inertial.push_back(inertial[k]);
    fit.friction.push_back(friction[k]);
    fit.friction_err.push_back(friction_err[k]);
    fit.solid_fraction.push_back(solid_fraction[k]);
    fit.solid_fraction_err.push_back(solid_fraction_err[k]);
  }
  const auto& I = fit.inertial;
  const int n = int(I.size());
  fit.mu.points = fit.phi.points = n;
  const auto [mu_lo, mu_hi] = std::minmax_element(fit.friction.begin(), fit.friction.end());
  const auto [phi_lo, phi_hi] =
      std::minmax_element(fit.solid_fraction.begin(), fit.solid_fraction.end());
  const double i_max = n ? *std::max_element(I.begin(), I.end()) : NAN;
  auto mu_model = [&](std::size_t i, const Eigen::VectorXd& t) {
    return dry_law_friction(law, I[i], t);
  };
  auto phi_model = [&](std::size_t i, const Eigen::VectorXd& t) {
    return dry_law_solid_fraction(law, I[i], t);
  };
  constexpr double inf = std::numeric_limits<double>::infinity();
  if (law == DryLaw::gdr_midi) {
    fit.phi = line_as_fit(statistics::weighted_line(I, fit.solid_fraction, fit.solid_fraction_err));
    fit.mu.dof = n - 3;
    if (n < 4) return fit;
    // Starts: μ_s just below the smallest μ, μ_2 above the largest, and I_0 over a decade ladder
    // (the law is flat in I_0 far from the data); the smallest χ² wins. μ_s, μ_2 unbounded.
    std::vector<Eigen::VectorXd> starts;
    for (double i_0 : {0.03, 0.1, 0.3, 1.0})
      starts.push_back(Eigen::Vector3d(*mu_lo - 0.02, *mu_hi + 0.2, i_0));
    fit.mu = best_of(mu_model, fit.friction, fit.friction_err, starts,
                     {ParameterBounds{}, ParameterBounds{}, ParameterBounds::positive()});
    return fit;
  }
  fit.mu.dof = fit.phi.dof = n - 3;
  if (n < 4) return fit;
  // Peyneau & Roux: starts over a ladder of exponents, the prefactor through the largest I and
  // the quasi-static limit half-way below the smallest μ (above the largest φ).
  std::vector<Eigen::VectorXd> mu_starts, phi_starts;
  const double mu_0 = 0.5 * *mu_lo;
  const double phi_rcp =
      std::min(*phi_hi + 0.005, 0.5 * (*phi_hi + std::numbers::pi / std::sqrt(18.0)));
  for (double exponent : {0.3, 0.5, 0.8, 1.0}) {
    mu_starts.push_back(
        Eigen::Vector3d(mu_0, std::max(*mu_hi - mu_0, 1e-3) / std::pow(i_max, exponent), exponent));
    phi_starts.push_back(Eigen::Vector3d(
        phi_rcp, std::max(phi_rcp - *phi_lo, 1e-4) / std::pow(i_max, exponent), exponent));
  }
  fit.mu = best_of(
      mu_model, fit.friction, fit.friction_err, mu_starts,
      {ParameterBounds{0.0, inf}, ParameterBounds::positive(), ParameterBounds::between(0.0, 2.0)});
  fit.phi = best_of(phi_model, fit.solid_fraction, fit.solid_fraction_err, phi_starts,
                    {ParameterBounds::between(0.0, std::numbers::pi / std::sqrt(18.0)),
                     ParameterBounds::positive(), ParameterBounds::between(0.0, 2.0)});
  return fit;
}

// The law selected for the friction (dry_law_for_friction).
inline InertialLawFit fit_inertial_law(double particle_friction,
                                       const std::vector<double>& inertial,
                                       const std::vector<double>& friction,
                                       const std::vector<double>& friction_err,
                                       const std::vector<double>& solid_fraction,
                                       const std::vector<double>& solid_fraction_err) {
  return fit_inertial_law(particle_friction, dry_law_for_friction(particle_friction), inertial,
                          friction, friction_err, solid_fraction, solid_fraction_err);
}

}  // namespace granflow::dem
