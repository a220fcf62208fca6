// α of the mixed number K = J + α I² (Trulsson, Andreotti & Claudin 2012, PRL 109, 118305;
// Ness & Sun 2015) fitted from a wet DEM sweep so that μ collapses on one smooth μ(K).
//
// Method (one-parameter weighted least squares): the smooth curve is Boyer, Guazzelli & Pouliquen
// (2011, PRL 107, 188301)'s μ(J) law with J replaced by K (docs/dem_dataset.md),
//   μ_B(K) = μ1 + (μ2 − μ1)/(1 + J0/K) + K + (5/2) ν_m K^½,  μ1 = 0.32, μ2 = 0.7, J0 = 0.005,
//   ν_m = 0.585,
// which is the viscous limit (α I² ≪ J) exactly; α minimises
//   S(α) = Σ_i ((μ_i − μ_B(J_i + α I_i²)) / s_i)²,  s_i = max(err μ_i, 1e-3)
// over log10 α in [−3, 2]: a 501-point scan of log α, then golden-section refinement in the
// bracketing interval. Only α is fitted (the law's constants are Boyer's), so the result answers
// "which α makes the inertial points fall on the viscous law".
#pragma once

#include <vector>

namespace granflow::dem {

double boyer_friction(double viscous_number);  // μ_B(J)

struct MixedNumberFit {
  double alpha = 0;         // fitted α
  double rms = 0;           // RMS of μ_i − μ_B(K_i) at the fit
  double chi2_per_dof = 0;  // S(α) / (n − 1)
  int points = 0;           // points used (finite, J > 0)
};

// J, I, μ, err μ per condition (same length); points with a non-finite value or J <= 0 are
// skipped. Needs >= 2 usable points (returns points < 2 otherwise, alpha = NaN).
MixedNumberFit fit_trulsson_alpha(const std::vector<double>& viscous_number,
                                  const std::vector<double>& inertial_number,
                                  const std::vector<double>& friction,
                                  const std::vector<double>& friction_err);

}  // namespace granflow::dem
