// The continuum side of a transient pair: the multi-regime REV's undrained (constant-volume)
// simple shear from a prepared state (φ0, p0), and the least-squares fit of force-chain
// parameters to a DEM transient (p'(γ), τ(γ) with the DEM's seed band).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "continuum/rev/simple_shear.hpp"
#include "core/case.hpp"

namespace granflow::transient_pair {

// rev::run_simple_shear at constant volume e0 = 1/φ0 − 1 from the skeleton isotropic at p'0 = p0
// on its yield locus (r_c = √3 p'0), T0 = continuum.initial_temperature × (d γ̇)² (the DEM starts
// at rest; kinetic theory needs T > 0), run through strain.total (no steady stop), Δγ at most
// continuum.strain_increment. control.mode drained: from e0, the total normal stress
// control.normal_stress (default p0) held while the liquid drains over control.drainage_length
// (the mixed control with the drainage resistance, rev/simple_shear.hpp); damped_height: the same
// with the constant resistance control.height_resistance. With rate_step.strain
// the shear rate steps to rate_step.shear_rate there. Throws core::NumericalFailure (step,
// variable); `result` then holds the series so far.
void continuum_transient(const core::Case& condition, double phi0, double p0,
                         rev::SimpleShearResult& result);

// The continuum's stop stage after `sheared` (rev/shear_stop.hpp) for stop.duration from the
// state at the end of the shear: the same point held at its volume with ε̇ = 0, or, with
// stop.drainage_length > 0, drained under the total `normal_stress` (stop.normal_stress, or the
// DEM's prepared p0: drained_normal_stress); rows (time since the stop) appended to `out`. Throws
// core::NumericalFailure.
void continuum_stop(const core::Case& condition, const rev::SimpleShearResult& sheared,
                    double normal_stress, rev::SimpleShearSeries& out);

// σ_n of a drained stop: stop.normal_stress, else the prepared p0 (as the DEM kind defaults it).
inline double drained_normal_stress(const core::Case& condition, double p0) {
  return condition.has("stop.normal_stress") ? condition.number("stop.normal_stress") : p0;
}

// The case key of a fitted parameter: force_chains.NAME, or NAME itself when it is a key path
// (e.g. liquid.viscous_contact).
std::string fitted_key(const std::string& name);

// `condition` with `fitted_key(NAME)=value` for each name (the case's own checks apply).
// `schema` must outlive the returned Case.
core::Case with_force_chain_values(const core::Case& condition, const core::Schema& schema,
                                   const std::vector<std::string>& names,
                                   const std::vector<double>& values);

// A DEM transient: the seed mean and band (lowest, highest seed) at the sampled strains.
struct DemTransient {
  std::vector<double> strain, p_mean, p_min, p_max, tau_mean, tau_min, tau_max, T_mean;
  // σ_yy and φ seed means over the shear (a rate step's metrics; empty from older DEM runs).
  std::vector<double> sigma_yy_mean, phi_mean;
  // The shear stopped (stop.duration > 0): time since the stop, T and p' seed means; else empty.
  std::vector<double> stop_time, stop_T_mean, stop_p_mean;
  // A drained stop (stop.drainage_length > 0): σ_yy and φ seed means over the stop; else empty.
  std::vector<double> stop_sigma_yy_mean, stop_phi_mean;
  double phi0 = 0, p0 = 0;
  std::map<std::string, double> metric_err;  // between-seed standard error of each metric
};

struct TransientFit {
  std::vector<std::string> names;
  std::vector<double> start, estimate, standard_error;
  std::vector<bool> at_bound;
  double chi2_red = 0, chi2_initial = 0;
  int evaluations = 0, points = 0;
  bool converged = false;
};

// Fits force_chains.NAME (each > 0, within calibrate.range of its case value; the fit works in
// ln θ) so that the continuum's p'(γ) and
// τ(γ), interpolated linearly at the DEM's strains, match the DEM's seed means, weighted by
// σ = max(half the seed band, 0.01 p0) (the band is the seed-to-seed spread; the floor keeps one
// seed, or a band that closes, from dominating):
//   χ² = Σ_i [(p_cont − p_DEM)² / σ_p,i² + (τ_cont − τ_DEM)² / σ_τ,i²].
// A continuum run that fails at a trial point counts as a residual of 1e3 per sample.
TransientFit fit_force_chains(const core::Case& condition, const core::Schema& schema,
                              const std::vector<std::string>& names, const DemTransient& dem);

// y(x) of a piecewise-linear series at `at` (clamped to its ends).
double interpolate(const std::vector<double>& x, const std::vector<double>& y, double at);

}  // namespace granflow::transient_pair
