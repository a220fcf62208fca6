// A step in the shear rate (rate_step.strain γ_s, rate_step.shear_rate; docs/transient_dem.md,
// "A step in the shear rate"): the flow before the step, after it, and the transient between,
// computed by the same function on the DEM's series and on the continuum's (the transient pair).
//   before: means of μ = τ/σ_yy, φ and T over the last fraction r (transient.residual_fraction)
//     of the strain before the step, γ in [(1 − r) γ_s, γ_s];
//   after: the same over the last fraction r of the strain after it,
//     γ >= γ_s + (1 − r)(γ_end − γ_s);
//   dilation: φ_after − φ_before (< 0: the step up dilates the sample);
//   dilation strain: the strain after the step at which φ has first covered half of the dilation
//     (linear between samples); -1 when it never does;
//   peak μ after the step: the largest μ sample after it (its overshoot over μ_after).
#pragma once

#include <span>

namespace granflow::dem {

struct RateStepMetrics {
  double mu_before = 0, phi_before = 0, T_before = 0;
  double mu_after = 0, phi_after = 0, T_after = 0;
  double dilation = 0, dilation_strain = -1, peak_mu = 0;
};

RateStepMetrics rate_step_metrics(std::span<const double> strain, std::span<const double> tau,
                                  std::span<const double> sigma_yy,
                                  std::span<const double> solid_fraction,
                                  std::span<const double> temperature, double step_strain,
                                  double residual_fraction);

}  // namespace granflow::dem
