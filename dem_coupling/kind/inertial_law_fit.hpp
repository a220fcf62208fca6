// The dense inertial rheology fitted to dry DEM steady points (issue 4), one fit per interparticle
// friction μ_p (model.md §7):
//   μ(I) = μ_s + (μ_2 − μ_s)/(1 + I_0/I)   (GDR MiDi 2004; Jop, Forterre & Pouliquen 2006),
//   φ(I) = φ_c − a I                        (da Cruz et al. 2005, PRE 72, 021309),
// weighted by the DEM standard errors (weighted_least_squares.hpp: LM for μ(I) with I_0 > 0, the
// closed form for the straight line φ(I)). The published DEM values they are compared with:
//   μ_p = 0.5: μ_s ≈ 0.35-0.38, φ_c ≈ 0.587 (Chialvo, Sun & Sundaresan 2012, PRE 85, 021305),
//   μ_p = 0:   μ_s ≈ 0.10 (internal friction angle ≈ 5.8°), φ_c ≈ 0.639 = random close packing
//              (Peyneau & Roux 2008, PRE 78, 011307; Chialvo et al. 2012).
// Header-only (see weighted_least_squares.hpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "dem_coupling/kind/weighted_least_squares.hpp"

namespace granflow::dem {

// μ(I) of GDR MiDi / Jop et al. 2006.
inline double inertial_friction_law(double inertial, double mu_s, double mu_2, double i_0) {
  return mu_s + (mu_2 - mu_s) / (1.0 + i_0 / inertial);
}

struct PublishedDemLaw {
  double mu_s_low, mu_s_high;  // published range of the quasi-static friction μ_s
  double phi_c;                // critical (jamming) solid fraction
  const char* source;
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

struct InertialLawFit {
  double particle_friction = 0;
  std::vector<double> inertial, friction, friction_err, solid_fraction, solid_fraction_err;
  LeastSquaresFit mu;  // estimate = (μ_s, μ_2, I_0)
  LineFit phi;         // intercept = φ_c, slope = −a
  double mu_s() const { return mu.estimate.size() ? mu.estimate[0] : NAN; }
  double mu_2() const { return mu.estimate.size() ? mu.estimate[1] : NAN; }
  double i_0() const { return mu.estimate.size() ? mu.estimate[2] : NAN; }
  double mu_s_err() const { return mu.standard_error.size() ? mu.standard_error[0] : NAN; }
  double mu_2_err() const { return mu.standard_error.size() ? mu.standard_error[1] : NAN; }
  double i_0_err() const { return mu.standard_error.size() ? mu.standard_error[2] : NAN; }
  double phi_c() const { return phi.intercept; }
  double phi_c_err() const { return phi.intercept_err; }
  double a() const { return -phi.slope; }
  double a_err() const { return phi.slope_err; }
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
  double phi_c_published_deviation() const {
    const auto pub = published_dem_law(particle_friction);
    return pub ? (phi_c() - pub->phi_c) / phi_c_err() : NAN;
  }
};

// Fits the points with finite I, μ, φ and positive error bars (a failed sweep point is NaN and
// skipped). μ(I) needs >= 4 points, φ(I) >= 3 (more points than parameters); with fewer the
// corresponding fit is empty (estimate of size 0 / NaN).
inline InertialLawFit fit_inertial_law(double particle_friction,
                                       const std::vector<double>& inertial,
                                       const std::vector<double>& friction,
                                       const std::vector<double>& friction_err,
                                       const std::vector<double>& solid_fraction,
                                       const std::vector<double>& solid_fraction_err) {
  InertialLawFit fit;
  fit.particle_friction = particle_friction;
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
  fit.phi = weighted_line(I, fit.solid_fraction, fit.solid_fraction_err);
  fit.mu.points = int(I.size());
  if (I.size() < 4) return fit;
  auto model = [&](std::size_t i, const Eigen::VectorXd& theta) {
    return inertial_friction_law(I[i], theta[0], theta[1], theta[2]);
  };
  // Starts: μ_s just below the smallest μ, μ_2 above the largest, and I_0 over a decade ladder
  // (the law is flat in I_0 far from the data); the smallest χ² wins.
  const auto [lo, hi] = std::minmax_element(fit.friction.begin(), fit.friction.end());
  for (double i_0 : {0.03, 0.1, 0.3, 1.0}) {
    Eigen::VectorXd start(3);
    start << *lo - 0.02, *hi + 0.2, i_0;
    LeastSquaresFit trial =
        weighted_least_squares(model, fit.friction, fit.friction_err, start, {false, false, true});
    if (fit.mu.estimate.size() == 0 || trial.chi2 < fit.mu.chi2) fit.mu = trial;
  }
  return fit;
}

}  // namespace granflow::dem
