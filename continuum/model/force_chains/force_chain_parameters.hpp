// Parameters of the force-chain (σ_FC) model: docs/model/force_chains.md lists each one with its
// meaning, unit, default and source. SI units; stresses compression-positive.
//
// Names follow the literature: di Prisco, Nova & Lanier (1993) for the yield locus and the
// hardening (β_f, γ, b_p, ξ, c_p, θ̂_c, θ̂_e, as in TOCHNOG group_materi_plasti_diprisco), Li &
// Wang (1998) / Li & Dafalias (2000) for the critical-state line and the state parameter ψ
// (e_Γ, λ_c, ξ_c, d_0, n_d). The defaults are the loose/medium sand of the seed paper's section 4
// (e0 = 0.70 is loose, p'0 = 50 kPa); see the document for how they were chosen.
#pragma once

#include <stdexcept>
#include <string>

namespace granflow::model::force_chains {

struct ForceChainParameters {
  // ---- pressure-dependent elasticity: K = K_ref (max(p, p_floor)/p_ref)^n, constant ν -------
  double bulk_modulus_ref = 40.0e6;     // K_ref, Pa, bulk modulus at p = p_ref
  double reference_pressure = 100.0e3;  // p_ref, Pa
  double elastic_exponent = 0.5;        // n, -, 0 <= n < 1
  double poisson_ratio = 0.25;          // ν_poisson, -
  double pressure_floor = 100.0;        // p_floor, Pa: K stays K(p_floor) > 0 below it

  // ---- yield locus, di Prisco et al. (1993) ------------------------------------------------
  // f = 3 β_f (γ-3) ln(r/r_c) - γ J3η + (9/4)(γ-1) J2η
  double beta_f = 1.5;  // β_f, -
  double gamma = 4.1;   // γ, - (> 3 for a closed locus; seed Table 3 "γ")

  // ---- hardening ------------------------------------------------------------------------------
  // dr_c = (r_c/b_p) [dε^p_v + ξ(ψ) dε^p_q],  ξ(ψ) = -ξ_ψ ψ (ψ > 0), -ξ_ψ,d ψ (ψ < 0)
  double b_p = 0.005;         // b_p, -, plastic compressibility (ε^p_v per e-fold of r_c)
  double xi_psi = 12.0;       // ξ_ψ, -, deviatoric softening of looser-than-critical states
  double xi_psi_dense = 3.0;  // ξ_ψ,d, -, deviatoric hardening of denser-than-critical states
  // rotational hardening dχ = c_p |dε^p| (χ̂ - χ), χ̂ at angle θ̂(Lode) from the isotropic axis
  double c_p = 10.0;           // c_p, -
  double theta_hat_c = 0.157;  // θ̂_c, rad, target axis angle in triaxial compression
  double theta_hat_e = 0.157;  // θ̂_e, rad, target axis angle in triaxial extension

  // ---- critical state (Lade-Duncan in the deviatoric plane) --------------------------------
  double M_c = 1.25;                        // critical stress ratio q/p in triaxial compression, -
  double e_Gamma = 0.66;                    // e_Γ, critical void ratio at p = 0
  double lambda_c = 0.03;                   // λ_c, -
  double xi_c = 0.7;                        // ξ_c, -: e_cs = e_Γ - λ_c (p/p_atm)^ξ_c
  double atmospheric_pressure = 101.325e3;  // p_atm, Pa
  double e_min = 0.45;                      // void-ratio bounds used in ψ (and for regrowth)
  double e_max = 1.0;

  // ---- state-dependent dilatancy, Lode-angle independent -----------------------------------
  // D = dε^p_v/dε^p_q = d_0 (M_c exp(n_d ψ) - η̃)/η̃,  η̃ = M_c q/(p M(θ))
  double d_0 = 0.3;  // d_0, -
  double n_d = 2.0;  // n_d, -

  // ---- fluidization and regrowth (granflow rule, docs/model/force_chains.md §5) -------------
  double fluidization_size = 1000.0;      // r_c below which force chains vanish, Pa
  double resolidification_size = 2000.0;  // r_c at which a regrowing skeleton is solid again, Pa
  double regrowth_modulus = 2.0e6;        // K_r, Pa: dr_c = w(T) K_r <dε_v> while fluidized
  double regrowth_temperature = 1.0e-4;   // T_r, m²/s²: w(T) = max(0, 1 - T/T_r)

  // ---- integration (Sloan, Abbo & Sheng 2001, modified Euler + drift correction) ------------
  double stress_tolerance = 1.0e-5;  // STOL, relative local error per sub-step
  double yield_tolerance = 1.0e-8;   // FTOL, |f| accepted as "on the locus" (f dimensionless)
  int fixed_substeps = 0;            // > 0: that many equal sub-steps, no error control
  int max_substeps = 2000;           // per update; beyond it the last sub-step is accepted
};

// Throws std::invalid_argument naming the first parameter out of its range.
inline void validate(const ForceChainParameters& p) {
  auto require = [](bool ok, const char* name, const char* expected) {
    if (!ok)
      throw std::invalid_argument(std::string("force_chains.") + name + ": expected " + expected);
  };
  require(p.bulk_modulus_ref > 0, "bulk_modulus_ref", "> 0 Pa");
  require(p.reference_pressure > 0, "reference_pressure", "> 0 Pa");
  require(p.elastic_exponent >= 0 && p.elastic_exponent < 1, "elastic_exponent", "in [0, 1)");
  require(p.poisson_ratio > -1 && p.poisson_ratio < 0.5, "poisson_ratio", "in (-1, 0.5)");
  require(p.pressure_floor > 0, "pressure_floor", "> 0 Pa");
  require(p.beta_f > 0, "beta_f", "> 0");
  require(p.gamma > 3, "gamma", "> 3 (closed yield locus)");
  require(p.b_p > 0, "b_p", "> 0");
  require(p.xi_psi >= 0, "xi_psi", ">= 0");
  require(p.xi_psi_dense >= 0, "xi_psi_dense", ">= 0");
  require(p.c_p >= 0, "c_p", ">= 0");
  require(p.theta_hat_c >= 0 && p.theta_hat_c < 1.5, "theta_hat_c", "in [0, 1.5) rad");
  require(p.theta_hat_e >= 0 && p.theta_hat_e < 1.5, "theta_hat_e", "in [0, 1.5) rad");
  require(p.M_c > 0 && p.M_c < 3, "M_c", "in (0, 3)");
  require(p.lambda_c >= 0, "lambda_c", ">= 0");
  require(p.xi_c > 0, "xi_c", "> 0");
  require(p.atmospheric_pressure > 0, "atmospheric_pressure", "> 0 Pa");
  require(p.e_min > 0 && p.e_max > p.e_min, "e_min/e_max", "0 < e_min < e_max");
  require(p.d_0 > 0, "d_0", "> 0");
  require(p.fluidization_size > 0, "fluidization_size", "> 0 Pa");
  require(p.resolidification_size >= p.fluidization_size, "resolidification_size",
          ">= fluidization_size");
  require(p.regrowth_modulus >= 0, "regrowth_modulus", ">= 0 Pa");
  require(p.regrowth_temperature > 0, "regrowth_temperature", "> 0 m²/s²");
  require(p.stress_tolerance > 0, "stress_tolerance", "> 0");
  require(p.yield_tolerance > 0, "yield_tolerance", "> 0");
  require(p.fixed_substeps >= 0, "fixed_substeps", ">= 0");
  require(p.max_substeps >= 1, "max_substeps", ">= 1");
}

}  // namespace granflow::model::force_chains
