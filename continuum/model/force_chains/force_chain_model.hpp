// The force-chain (σ_FC) strain-hardening elastic-plastic model of the multi-regime material
// (docs/model/force_chains.md, seed §3.1; equations and parameters in docs/model/force_chains.md).
//
// SIGN CONVENTION: everything in this folder is COMPRESSION-POSITIVE (soil mechanics): stress
// σ > 0 in compression, strain increments > 0 in shortening, p = tr(σ)/3, ε_v = tr(ε). Convert
// at the boundary (σ_tension-positive = -σ, dε_tension-positive = -dε); every layer's convention
// is in docs/model/conventions.md.
//
// Ingredients: closed yield locus of di Prisco et al. (1993) of size r_c and axis χ; pressure-
// dependent elasticity; Lade-Duncan critical state as attractor; state-dependent, Lode-angle-
// independent dilatancy; isotropic hardening of r_c (softening under dilative plastic flow and
// for looser-than-critical states); rotational hardening of χ; fluidization (r_c -> 0, σ_FC = 0,
// χ frozen) and regrowth of r_c under compaction when the granular temperature is small.
// Integration: modified-Euler explicit sub-stepping with local error control and yield-surface
// drift correction (Sloan, Abbo & Sheng 2001). Value types, no allocation, no virtual calls.
#pragma once

#include <Eigen/Core>

#include "continuum/model/force_chains/critical_state_lade_duncan.hpp"
#include "continuum/model/force_chains/dilatancy_state_dependent.hpp"
#include "continuum/model/force_chains/elasticity_pressure_dependent.hpp"
#include "continuum/model/force_chains/force_chain_parameters.hpp"
#include "continuum/model/force_chains/stress_invariants.hpp"
#include "continuum/model/force_chains/symmetric_tensor.hpp"
#include "continuum/model/force_chains/yield_function_diprisco.hpp"

namespace granflow::model::force_chains {

struct ForceChainState {
  Eigen::Matrix3d stress = Eigen::Matrix3d::Zero();  // σ_FC, Pa, compression positive
  Eigen::Matrix3d chi = Eigen::Matrix3d::Identity() / 1.7320508075688772;  // axis, |χ| = 1
  double r_c = 0.0;         // locus size, Pa (0 when fluidized)
  double void_ratio = 0.7;  // e, updated from the volumetric strain: 1+e ∝ exp(-ε_v)
  Eigen::Matrix3d plastic_strain = Eigen::Matrix3d::Zero();  // accumulated ε^p (bookkeeping)
  bool fluidized = false;  // true: no enduring contacts, σ_FC = 0
};

struct UpdateInfo {
  bool plastic = false;                   // some plastic flow happened
  bool contact_loss = false;              // the stress path reached the stress-free apex
  bool became_fluid = false;              // r_c fell below fluidization_size during this update
  bool resolidified = false;              // regrowth brought r_c back to resolidification_size
  int substeps = 0;                       // accepted plastic sub-steps
  int rejected_substeps = 0;              // rejected by the error control
  bool substep_budget_exhausted = false;  // max_substeps reached: the rest was integrated in
                                          // <= 64 forced sub-steps (error above STOL)
  double yield_value = 0.0;  // f at the end (dimensionless; |f| <= 1e-6 after plastic flow)
  double plastic_volumetric_strain = 0.0;  // Δε^p_v of this update
};

class ForceChainModel {
 public:
  explicit ForceChainModel(ForceChainParameters parameters);

  // Strain increment (compression positive) over dt, with the granular temperature T (m²/s²)
  // of the collisional part for the regrowth rule. dt only documents the rate: the model is
  // rate independent. A state with r_c < fluidization_size (e.g. default-constructed) is
  // fluidized on entry. Throws std::invalid_argument for a non-finite increment or one that
  // compacts beyond e = 0 (Δε_v >= ln(1+e)); std::runtime_error if the result is not finite.
  // volume_factor: exp(-tr Δε) = (1 + e_new)/(1 + e) when the caller has it (> 0; one exp
  // fewer), else 0 and it is computed here. The plastic update uses the symmetric part of
  // strain_increment (stress, axis and plastic strain stay symmetric).
  UpdateInfo update(ForceChainState& state, const Eigen::Matrix3d& strain_increment, double dt,
                    double granular_temperature, double volume_factor = 0.0) const;

  // Isotropic state at mean stress p, void ratio e, isotropic axis, r_c = √3 p · ocr (ocr >= 1:
  // the ratio of the locus size to the current stress on the axis).
  ForceChainState isotropic_state(double p, double void_ratio, double ocr = 1.0) const;

  // Diagnostics (not used in the hot path).
  double yield_value(const ForceChainState& state) const;  // f; -1e3 at the stress-free origin
  double dilatancy(const Eigen::Matrix3d& stress, double void_ratio) const;  // D = dε^p_v/dε^p_q
  Eigen::Matrix3d flow_direction(const ForceChainState& state) const;        // unit m
  double deviatoric_hardening(double state_parameter) const;                 // ξ(ψ)

  const ForceChainParameters& parameters() const { return par_; }
  const PressureDependentElasticity& elasticity() const { return elastic_; }
  const YieldFunctionDiPrisco& yield_function() const { return yield_; }
  const CriticalStateLadeDuncan& critical_state() const { return critical_; }
  const DilatancyStateDependent& dilatancy_law() const { return dilatancy_; }

 private:
  // The integration works on symmetric tensors (symmetric_tensor.hpp): 6 components each.
  using Locus = YieldFunctionDiPrisco::Locus;
  struct Point {  // integration variables
    SymTensor stress, chi, plastic_strain;
    double r_c, void_ratio;
  };
  struct Increment {
    SymTensor stress, chi, plastic_strain;
    double r_c, void_ratio;
  };
  struct PlasticRates {
    SymTensor n, m, stiffness_m, chi_rate;
    double size_rate, denominator;
    double bulk_modulus;  // K(p) at the point
  };

  // p^ξ_c and M_d = M_c exp(x), x = n_d ψ, of the last direct pow resp. exp of an
  // integration: the later plastic rates (sub-steps, drift correction), whose p and x differ
  // little from these, take theirs from Taylor series about them (dilatancy_terms). The anchor
  // is reset by every integrate(): the update still depends on the state and the increment
  // only.
  struct Anchor {
    bool p_set = false, x_set = false;
    double inv_p = 0.0, p_power = 0.0, x = 0.0, m_d = 0.0;
  };

  static bool admissible(const SymTensor& stress, const SymTensor& chi, double r_c);
  // f clipped to ±kYieldClip (-kYieldClip at the stress-free origin, +kYieldClip in tension);
  // *locus (if given) receives r, η, η·η of the point when it is admissible (r_c > 0).
  double safe_yield(const SymTensor& stress, const SymTensor& chi, double r_c,
                    Locus* locus = nullptr) const;
  // Rates at y; `locus` = yield_.locus(y.stress, y.chi) when the caller has it; `anchor` (if
  // given) carries p^ξ_c and M_d from one call to the next.
  PlasticRates plastic_rates(const Point& y, const Locus* locus = nullptr,
                             Anchor* anchor = nullptr) const;
  // ψ and M_d at (p, e), from the anchor's series when it is set and close enough
  void dilatancy_terms(double p, double void_ratio, Anchor* anchor, double& psi, double& m_d) const;
  // Euler increment from y over `strain` with the plastic rates r = plastic_rates(y);
  // void_factor = expm1(-tr strain).
  Increment increment(const Point& y, const SymTensor& strain, double void_factor,
                      const PlasticRates& r) const;
  // Returns the final f; *locus receives the final point's r, η, η·η and *has_locus whether
  // they are set (the point admissible, r_c > 0).
  double correct_drift(Point& y, Locus& locus, bool& has_locus, Anchor& anchor) const;
  // f0, f1: f at the start and at the end of the elastic trial (both known to the caller);
  // stress_gradient: ∂f/∂σ at y if the caller has it, else nullptr.
  double elastic_fraction(const Point& y, const SymTensor& strain, double f0, double f1,
                          const SymTensor* stress_gradient) const;
  // Integrates `strain` from y; returns the fraction of `strain` left when the stress path hits
  // the stress-free apex (0 when the whole increment was integrated).
  // volume_factor = exp(-tr strain).
  double integrate(Point& y, const SymTensor& strain, double volume_factor, UpdateInfo& info) const;
  void apex_flow(Point& y, const SymTensor& strain) const;

  ForceChainParameters par_;
  PressureDependentElasticity elastic_;
  YieldFunctionDiPrisco yield_;
  CriticalStateLadeDuncan critical_;
  DilatancyStateDependent dilatancy_;
  // target axis angle θ̂ independent of the Lode angle (θ̂_c = θ̂_e): cos θ̂, sin θ̂ once
  bool constant_theta_hat_;
  double cos_theta_hat_, sin_theta_hat_;
  double inv_b_p_;  // 1/b_p
  // binomial coefficients of (1 + δ)^ξ_c = 1 + Σ_k binomial_[k-1] δ^k, k = 1..8, and the
  // |δ| up to which that sum is p^ξ_c to round-off
  double binomial_[8];
  double power_series_range_;
};

}  // namespace granflow::model::force_chains
