// The multi-regime material point (seed Eq. 7, 19, 24; model.md §1): the stress is a sum of
// terms working in parallel,
//     σ = σ_FC + σ_COL + σ_L,
// and the granular temperature T follows the energy balance of model.md §5 (seed Eq. 21).
// Terms switched off in the case are skipped by one branch per update, outside any inner loop,
// so they cost nothing. The force-chain term (σ_FC, issue 3) plugs in beside these two.
//
// Sign convention inside granflow's constitutive code: compression-positive stress and strain
// rate (soil mechanics, model.md §0): tr(ε̇) > 0 is compaction.
#pragma once

#include <Eigen/Core>

#include "continuum/model/closures.hpp"
#include "continuum/multi_regime/granular_temperature_update.hpp"

namespace granflow::continuum {

struct MultiRegimeSettings {
  bool collisional = true;               // σ_COL, Γ and the T balance
  bool liquid = false;                   // σ_L viscous part, η(ν)
  bool fluctuation_dissipation = false;  // Λ (needs liquid)
  model::CollisionalParameters collisional_parameters;
  model::LiquidParameters liquid_parameters;
};

struct PointState {
  double solid_fraction = 0.5;        // ν = 1/(1+e)
  double granular_temperature = 0.0;  // T, m²/s²
};

// Everything one evaluation produces (compression-positive stresses, Pa).
struct StressParts {
  Eigen::Matrix3d collisional = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d liquid = Eigen::Matrix3d::Zero();
  double collisional_pressure = 0;      // p_COL, Pa
  double collisional_viscosity = 0;     // ρ_p d f2 T^½, Pa s
  double mixture_viscosity = 0;         // η(ν), Pa s
  double correlation_length = 0;        // L, m
  double collisional_dissipation = 0;   // Γ, W/m³
  double liquid_dissipation = 0;        // Λ, W/m³
  double collisional_power = 0;         // σ_COL : ε̇, W/m³
  RiccatiCoefficients temperature_equation;  // coefficients of ds/dt, s = T^½
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

  // Shear rate γ̇ = 2 sqrt(ε̇':ε̇' / 2)... for simple shear ε̇_xy = γ̇/2 gives γ̇.
  static double shear_rate(const Eigen::Matrix3d& strain_rate);

  const MultiRegimeSettings& settings() const { return settings_; }

 private:
  MultiRegimeSettings settings_;
};

}  // namespace granflow::continuum
