// MultiRegimePoint::advance_plane(): the material-point update of advance_mass_balanced() for the
// plane strain of the MPM (multi_regime_point.hpp), on the four in-plane components instead of
// 3 × 3 matrices, without the diagnostics an MPM point does not use. Steps and closures are those
// of multi_regime_point.cpp (docs/model/multi_regime.md):
//   2. σ_FC, χ, r_c by the force-chain model with Δε = ε̇ dt and T at the start of the step;
//   3. T^½ by the exact Riccati update (granular_temperature_update.hpp) at the new ν;
//   4. σ = σ_FC + σ_IC + σ_COL + σ_L at the new state (compression positive, without u_w):
//        σ_COL = p_COL I + 2 η_COL ε̇',  p_COL = ρ_p f1 T,  η_COL = ρ_p d f2 T^½,
//        σ_IC = p_IC I + 2 (μ_IC p_IC/γ̇) ε̇',  σ_L = 2 η(ν) ε̇'   (seed Eq. 27),
//      ε̇' = ε̇ − (tr ε̇/3) I, γ̇ = sqrt(2 ε̇':ε̇').
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "continuum/multi_regime/multi_regime_point.hpp"

namespace granflow::continuum {

PlaneStep MultiRegimePoint::advance_plane(PointState& state, double exx, double eyy, double exy,
                                          double dt, double volume_factor) const {
  const double T_start = state.granular_temperature;
  // 2. force chains
  if (force_chain_model_) {
    auto& fc = state.force_chains;
    const auto& fp = force_chain_model_->parameters();
    if (!fc.fluidized && fc.r_c < fp.fluidization_size) {
      // ForceChainModel::update of a skeleton whose locus is below the fluidization size and not
      // yet flagged fluidized: it becomes fluid in this update (became_fluid), so it does not
      // regrow (r_c = 0), σ_FC = 0, χ is frozen, ε^p += Δε, e from (1 + e) exp(-Δε_v); the same
      // checks of the increment first (force_chain_model.cpp).
      const double dxx = exx * dt, dyy = eyy * dt, dxy = exy * dt;
      if (!std::isfinite(dxx) || !std::isfinite(dyy) || !std::isfinite(dxy))
        throw std::invalid_argument("force_chains: non-finite strain increment");
      if (!(volume_factor > 0.0)) volume_factor = std::exp(-(dxx + dyy));
      if (!((1.0 + std::max(fc.void_ratio, 0.0)) * volume_factor > 1.0))
        throw std::invalid_argument(
            "force_chains: volumetric strain increment compacts the skeleton "
            "beyond zero void ratio");
      fc.fluidized = true;
      fc.r_c = 0.0;
      fc.stress.setZero();
      fc.plastic_strain(0, 0) += dxx;
      fc.plastic_strain(1, 1) += dyy;
      fc.plastic_strain(0, 1) += dxy;
      fc.plastic_strain(1, 0) += dxy;
      fc.void_ratio = std::max((1.0 + fc.void_ratio) * volume_factor - 1.0, 0.0);
    } else {
      Eigen::Matrix3d increment;
      increment << exx * dt, exy * dt, 0.0, exy * dt, eyy * dt, 0.0, 0.0, 0.0, 0.0;
      force_chain_model_->update(fc, increment, dt, T_start, volume_factor);
    }
  }
  const double nu = state.solid_fraction;
  state.force_chains.void_ratio = 1.0 / nu - 1.0;

  // ε̇' and ε̇':ε̇' of the plane rate (ε̇'_zz = -tr ε̇/3)
  const double trace = exx + eyy, third = trace / 3.0;
  const double ax = exx - third, ay = eyy - third;
  const double deviator_norm2 = ax * ax + ay * ay + third * third + 2.0 * exy * exy;
  PlaneStep out;
  out.shear_rate = std::sqrt(2.0 * deviator_norm2);
  const double gamma_dot = out.shear_rate;
  double eta2 = 0.0, pressure = 0.0;  // 2 × the summed viscosities, and p_IC + p_COL
  double p_ic = 0.0, eta2_ic = 0.0;
  double p_col = 0.0, eta2_col = 0.0;
  // 3. T (MultiRegimePoint::update with a unit heat-capacity factor)
  if (settings_.collisional) {
    const auto& p = settings_.collisional_parameters;
    const model::CollisionalCoefficients c = coefficients(nu);
    const double lambda_over_T = liquid_dissipation_per_temperature(nu, c.g0);
    const double L = model::correlation_length(p, c, gamma_dot, T_start);
    const RiccatiCoefficients k = riccati(nu, deviator_norm2, trace, c, L, lambda_over_T);
    const double s0 = std::sqrt(std::max(T_start, 0.0));
    const double s1 = advance_sqrt_temperature(s0, k, dt);
    const double T = s1 * s1;
    state.granular_temperature = T;
    out.f4 = c.f4;
    out.sqrt_temperature = s1;
    p_col = model::collisional_pressure(p, c, T);
    eta2_col = 2.0 * (p.particle_density * p.diameter * c.f2 * s1);  // 2 η_COL, η_COL at T^½ = s1
    out.collisional_pressure = p_col;
  }
  // 4. stresses
  if (contact_stress_on(settings_)) {
    p_ic = inertial_contact_pressure(nu, gamma_dot);
    if (gamma_dot > 0) eta2_ic = 2.0 * inertial_contact_friction_ * p_ic / gamma_dot;
  }
  double eta2_liquid = 0.0;
  if (settings_.liquid)
    eta2_liquid = 2.0 * model::mixture_viscosity(settings_.liquid_parameters, nu);
  pressure = p_ic + p_col;
  eta2 = eta2_ic + eta2_col + eta2_liquid;
  double fxx = 0.0, fyy = 0.0, fzz = 0.0, fxy = 0.0;
  if (settings_.force_chains) {
    const Eigen::Matrix3d& s = state.force_chains.stress;
    fxx = s(0, 0);
    fyy = s(1, 1);
    fzz = s(2, 2);
    fxy = 0.5 * (s(0, 1) + s(1, 0));
  }
  out.xx = fxx + pressure + eta2 * ax;
  out.yy = fyy + pressure + eta2 * ay;
  out.zz = fzz + pressure - eta2 * third;
  out.xy = fxy + eta2 * exy;
  return out;
}

}  // namespace granflow::continuum
