// The multi-regime material point (seed Eq. 7, 19, 24; docs/model/multi_regime.md): the stress is a
// sum of terms working in parallel,
//     σ = σ_FC + σ_COL + σ_L,
// and the granular temperature T follows the energy balance of docs/model/multi_regime.md §3 (seed
// Eq. 21). Terms switched off in the case are skipped by one branch per update, outside any inner
// loop, so they cost nothing. The force-chain term σ_FC (docs/model/force_chains.md,
// model::force_chains::ForceChainModel) is the effective stress σ' of the skeleton; it is rate
// independent and carries the state (σ_FC, χ, r_c). T raises p_COL; under an imposed total stress
// (REV drivers, rev/element_test.hpp) the force-chain part therefore unloads as p_COL rises.
//
// Sign convention inside granflow's constitutive code: compression-positive stress and strain
// rate (soil mechanics): tr(ε̇) > 0 is compaction. Every layer's convention and the one
// conversion (to the MPM) are in docs/model/conventions.md.
#pragma once

#include <Eigen/Core>
#include <optional>

#include "continuum/model/closures.hpp"
#include "continuum/model/force_chains/force_chain_model.hpp"
#include "continuum/multi_regime/granular_temperature_update.hpp"

namespace granflow::continuum {

struct MultiRegimeSettings {
  bool force_chains = false;             // σ_FC (effective stress of the skeleton)
  bool collisional = true;               // σ_COL, Γ and the T balance
  bool liquid = false;                   // σ_L viscous part, η(ν)
  bool fluctuation_dissipation = false;  // Λ (needs liquid)
  // σ_IC, the contacts' stress of dense flow (collisional.inertial_contact a_c, _power m,
  // liquid.viscous_contact b_v; docs/model/multi_regime.md §2):
  //   p_IC = [ρ_p (a_c d γ̇)² + b_v η0 γ̇] (ν_c - ν)^-m,   σ_IC = p_IC I + 2 (μ_IC p_IC / γ̇) ε̇',
  // the inertial scale of dry grains and the viscous scale of immersed ones (b_v only with the
  // liquid on), as the mixed number K = J + α I² of Trulsson et al. (2012) adds them,
  // ν_c the jamming fraction of g0, μ_IC the contacts' friction (collisional.
  // inertial_contact_friction; 0: the force chains' critical state friction in plane strain,
  // M(θ = 0)/√3 of force_chain_parameters). a_c = 0 and b_v = 0 (the defaults) switch it off
  // (the seed's model) at the cost of one branch.
  double inertial_contact = 0.0;
  double inertial_contact_power = 2.0;
  double inertial_contact_friction = 0.0;
  double viscous_contact = 0.0;  // b_v (liquid.viscous_contact), used with liquid on
  model::CollisionalParameters collisional_parameters;
  model::LiquidParameters liquid_parameters;
  model::force_chains::ForceChainParameters force_chain_parameters;
};

// p_IC = [ρ_p (a_c d γ̇)² + b_v η0 γ̇] (ν_c - ν)^-m, Pa (0 when a_c = 0 and b_v η0 = 0); the one
// definition the material point and the steady model share. Throws std::domain_error at
// ν >= ν_c when the term is on.
double contact_pressure(const MultiRegimeSettings& settings, double solid_fraction,
                        double shear_rate);
// Whether σ_IC is on: a_c > 0, or b_v > 0 with the liquid on.
bool contact_stress_on(const MultiRegimeSettings& settings);

struct PointState {
  double solid_fraction = 0.5;        // ν = 1/(1+e)
  double granular_temperature = 0.0;  // T, m²/s²
  // σ_FC, χ, r_c and e of the skeleton (used only with settings.force_chains; its void ratio is
  // kept equal to 1/ν - 1 by advance()).
  model::force_chains::ForceChainState force_chains{};
};

// Everything one evaluation produces (compression-positive stresses, Pa).
struct StressParts {
  Eigen::Matrix3d force_chain = Eigen::Matrix3d::Zero();  // σ_FC = σ' (effective stress)
  Eigen::Matrix3d collisional = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d liquid = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d inertial_contact = Eigen::Matrix3d::Zero();  // σ_IC (zero when off)
  double collisional_pressure = 0;                             // p_COL, Pa
  double inertial_contact_pressure = 0;                        // p_IC, Pa
  double collisional_viscosity = 0;                            // ρ_p d f2 T^½, Pa s
  double mixture_viscosity = 0;                                // η(ν), Pa s
  double correlation_length = 0;                               // L, m
  double collisional_dissipation = 0;                          // Γ, W/m³
  double liquid_dissipation = 0;                               // Λ, W/m³
  double collisional_power = 0;                                // σ_COL : ε̇, W/m³
  RiccatiCoefficients temperature_equation;                    // coefficients of ds/dt, s = T^½
  model::CollisionalCoefficients coefficients;         // g0, f1..f4 at ν (collisional only)
  model::force_chains::UpdateInfo force_chain_update;  // of the last advance() (diagnostics)

  // σ_FC + σ_IC + σ_COL + σ_L without the pore pressure u_w (the driver adds u_w I).
  Eigen::Matrix3d total_without_pore_pressure() const {
    return force_chain + inertial_contact + collisional + liquid;
  }
};

// What MultiRegimePoint::advance_plane() returns (compression-positive stresses, Pa).
struct PlaneStep {
  double xx = 0, yy = 0, zz = 0, xy = 0;  // σ_FC + σ_IC + σ_COL + σ_L, without u_w
  double collisional_pressure = 0;        // p_COL
  double shear_rate = 0;                  // γ̇ = sqrt(2 ε̇':ε̇')
  double sqrt_temperature = 0;            // T^½ at the end of the step (0 without the term)
  double f4 = 0;  // f4(ν) of the conductivity (kinetic_theory_coefficients.hpp), collisional only
};

class MultiRegimePoint {
 public:
  explicit MultiRegimePoint(MultiRegimeSettings settings);

  // Stress parts at the state for a strain rate (compression-positive), no state change.
  StressParts evaluate(const PointState& state, const Eigen::Matrix3d& strain_rate) const;

  // Advance T over dt at the given strain rate with ν frozen (exact local Riccati update of
  // T^½), then return the stress parts at the new state. `heat_capacity_factor` (>= 1) divides
  // the right-hand side: a driver that slaves ν to T (constant pressure) folds the volumetric
  // work p tr(ε̇) = p (dν/dT) Ṫ / ν into an effective heat capacity instead of an explicit
  // source, which is what keeps that coupling stable (see rev/simple_shear.cpp).
  StressParts update(PointState& state, const Eigen::Matrix3d& strain_rate, double dt,
                     double heat_capacity_factor = 1.0) const;

  // Full material-point update over dt at the strain rate ε̇ (compression positive), in order:
  //  1. ν <- ν exp(tr ε̇ dt) (mass balance, seed Eq. 1: 1+e ∝ exp(-ε_v));
  //  2. σ_FC, χ, r_c by the force-chain model with Δε = ε̇ dt and the T at the start of the step
  //     (its regrowth rule needs T);
  //  3. T by the exact Riccati update of T^½ with the coefficients at the new ν;
  //  4. σ_COL, σ_L at the new state.
  // Each part is skipped when its term is off. Not thread-safe per state, const per point.
  // Throws std::domain_error if ν leaves the range of the closures (the driver prevents it).
  StressParts advance(PointState& state, const Eigen::Matrix3d& strain_rate, double dt) const;
  // advance() from its step 2: the caller has done the mass balance, state.solid_fraction is the
  // ν at the end of the step (the MPM material, which needs that ν first for its guard).
  // volume_factor: exp(-tr ε̇ dt) if the caller has it (> 0), else computed (force-chain update).
  StressParts advance_mass_balanced(PointState& state, const Eigen::Matrix3d& strain_rate,
                                    double dt, double volume_factor = 0.0) const;

  // advance_mass_balanced() for plane strain (ε̇_zz = ε̇_xz = ε̇_yz = 0), returning only what an
  // MPM point needs (PlaneStep): the total stress without u_w, p_COL, γ̇, f4 and T^½. The same
  // closures and the same order of the steps; it leaves out the diagnostics of StressParts (Γ, L
  // and the Riccati coefficients at the new T, the collisional power, the 3 × 3 parts) and takes
  // η_COL = ρ_p d f2 T^½ from the T^½ of the Riccati update (the two differ by round-off). A
  // skeleton without force chains at the start (r_c below the fluidization size, not flagged
  // fluidized: it cannot regrow in this update) takes ForceChainModel::update's own result without
  // the call (multi_regime_plane.cpp). ε̇_xx, ε̇_yy, ε̇_xy: the compression-positive plane strain rate
  // ε̇ = -D of the MPM, 1/s (separate arguments: passed in registers).
  PlaneStep advance_plane(PointState& state, double exx, double eyy, double exy, double dt,
                          double volume_factor) const;

  // Isotropic initial state: e, effective pressure p' (σ_FC = p' I), ocr = r_c/(√3 p') >= 1, T.
  PointState initial_state(double void_ratio, double effective_pressure, double ocr,
                           double granular_temperature) const;

  const model::force_chains::ForceChainModel* force_chain_model() const {
    return force_chain_model_ ? &*force_chain_model_ : nullptr;
  }

  // The largest admissible ν: just below the collisional closures' ν_c and the mixture
  // viscosity's maximum packing (the terms that are on; 1 when neither is), where they diverge.
  double solid_fraction_limit() const;

  // p_IC = contact_pressure(settings(), ν, γ̇), Pa. Throws std::domain_error at ν >= ν_c.
  double inertial_contact_pressure(double solid_fraction, double shear_rate) const;
  // μ_IC = M(θ = 0)/√3 of the force chains' critical state (τ_IC = μ_IC p_IC in simple shear).
  double inertial_contact_friction() const { return inertial_contact_friction_; }

  // Shear rate γ̇ = 2 sqrt(ε̇':ε̇' / 2)... for simple shear ε̇_xy = γ̇/2 gives γ̇.
  static double shear_rate(const Eigen::Matrix3d& strain_rate);

  const MultiRegimeSettings& settings() const { return settings_; }

 private:
  // evaluate() with the collisional coefficients at state.solid_fraction given (unused when the
  // collisional term is off), and the Riccati coefficients alone.
  // `lambda_over_T` = Λ/T at ν (liquid_dissipation_per_temperature(), 0 without Λ).
  StressParts evaluate(const PointState& state, const Eigen::Matrix3d& strain_rate,
                       const model::CollisionalCoefficients& c, double lambda_over_T) const;
  RiccatiCoefficients temperature_equation(const PointState& state,
                                           const Eigen::Matrix3d& strain_rate,
                                           const model::CollisionalCoefficients& c,
                                           double lambda_over_T) const;
  // The Riccati coefficients from ν, ε̇':ε̇', tr ε̇, the coefficients at ν, L and Λ/T (one
  // expression for evaluate() and temperature_equation()).
  RiccatiCoefficients riccati(double nu, double deviator_norm2, double trace,
                              const model::CollisionalCoefficients& c, double correlation_length,
                              double lambda_over_T) const;
  // g0, f1..f4 at ν with the material's constant effective restitution.
  model::CollisionalCoefficients coefficients(double nu) const;
  // Λ/T = 54 ν η0 R_diss(ν, g0)/d² (0 without Λ): depends on ν only, so one evaluation serves
  // the T update and the stresses of a step.
  double liquid_dissipation_per_temperature(double nu, double g0) const;

  MultiRegimeSettings settings_;
  double effective_restitution_ = 0.0;      // ε of the collisional parameters (a constant)
  double inertial_contact_friction_ = 0.0;  // μ_IC
  std::optional<model::force_chains::ForceChainModel> force_chain_model_;
};

}  // namespace granflow::continuum
