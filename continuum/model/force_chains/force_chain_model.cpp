// Force-chain model: stress update. Equations: docs/model/force_chains.md; integration after
// Sloan, Abbo & Sheng (2001), "Refined explicit integration of elastoplastic models with
// automatic error control", Eng. Comput. 18:121-154 (modified Euler pair, drift correction).
#include "continuum/model/force_chains/force_chain_model.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace granflow::model::force_chains {

namespace {
constexpr double kInvSqrt3 = 0.57735026918962576;
constexpr double kThird = 1.0 / 3.0;
constexpr double kSqrtThreeHalves = 1.2247448713915890;  // sqrt(3/2)
constexpr double kSqrtTwoThirds = 0.81649658092772603;   // sqrt(2/3)
// f is clipped to ±kYieldClip for the root searches; it is dimensionless and O(1..10) on and
// near the locus, so the clip only acts at the stress-free origin (-) and in tension (+).
constexpr double kYieldClip = 1.0e3;
// The stress-free apex is reached when r <= kApexRatio r_c: far below the smallest r/r_c of the
// locus inside the no-tension cone, exp(-17.25/(3β_f(γ-3))) at σ_3 = 0 in compression for an
// isotropic axis (0.03 for the defaults, 3e-5 for β_f = 0.5, γ = 4.1).
constexpr double kApexRatio = 1.0e-9;
}  // namespace

ForceChainModel::ForceChainModel(ForceChainParameters parameters)
    : par_((validate(parameters), parameters)),
      elastic_(par_),
      yield_(par_),
      critical_(par_),
      dilatancy_(par_),
      constant_theta_hat_(par_.theta_hat_c == par_.theta_hat_e),
      cos_theta_hat_(std::cos(par_.theta_hat_e)),
      sin_theta_hat_(std::sin(par_.theta_hat_e)),
      inv_b_p_(1.0 / par_.b_p) {
  // C(ξ, k) = ξ (ξ-1) ... (ξ-k+1)/k!, k = 1..8, and the range of δ in which the first term left
  // out, |C(ξ, 9)| |δ|⁹, stays below 1e-17 (a tenth of the round-off of p^ξ; 1e-2 for ξ_c = 0.7,
  // where |C(0.7, 9)| = 0.006)
  double c = 1.0;
  for (int k = 1; k <= 9; ++k) {
    c *= (par_.xi_c - (k - 1)) / k;
    if (k <= 8) binomial_[k - 1] = c;
  }
  power_series_range_ = c == 0.0 ? 1e-2 : std::min(1e-2, std::pow(1e-17 / std::abs(c), 1.0 / 9.0));
}

void ForceChainModel::dilatancy_terms(double p, double void_ratio, Anchor* anchor, double& psi,
                                      double& m_d) const {
  // Taylor series about the anchor's p0 and x0 (set by the last direct pow resp. exp of this
  // integration), truncated below round-off:
  //   p^ξ = p0^ξ (1 + δ)^ξ = p0^ξ (1 + Σ_{k<=8} C(ξ, k) δ^k),  δ = p/p0 - 1, |δ| <= range
  //   M_c exp(x) = M_d0 exp(Δx) = M_d0 Σ_{k<=4} Δx^k/k!,     Δx = x - x0, |Δx| <= 1e-3
  // (the first exp term left out, Δx⁵/120 <= 1e-17)
  const double pp = std::max(p, 0.0);
  double p_power;
  const double d = anchor && anchor->p_set ? pp * anchor->inv_p - 1.0 : 1.0;
  if (std::abs(d) <= power_series_range_) {
    const double* b = binomial_;  // Estrin's scheme: four independent pairs
    const double d2 = d * d, d4 = d2 * d2;
    const double low = (b[0] + b[1] * d) * d + (b[2] + b[3] * d) * d * d2;
    const double high = (b[4] + b[5] * d) + (b[6] + b[7] * d) * d2;
    p_power = anchor->p_power * (1.0 + (low + high * d * d4));
  } else {
    p_power = std::pow(pp, critical_.pressure_exponent());
    if (anchor && pp > 0.0) {
      anchor->p_set = true;
      anchor->inv_p = 1.0 / pp;
      anchor->p_power = p_power;
    }
  }
  psi = critical_.state_parameter_from_power(void_ratio, p_power);
  const double x = dilatancy_.ratio_exponent(psi);
  const double dx = anchor && anchor->x_set ? x - anchor->x : 1.0;
  if (std::abs(dx) <= 1e-3) {
    m_d = anchor->m_d * (1.0 + dx * (1.0 + dx * (0.5 + dx * (1.0 / 6.0 + dx * (1.0 / 24.0)))));
  } else {
    m_d = par_.M_c * std::exp(x);
    if (anchor) {
      anchor->x_set = true;
      anchor->x = x;
      anchor->m_d = m_d;
    }
  }
}

double ForceChainModel::deviatoric_hardening(double psi) const {
  return -(psi > 0.0 ? par_.xi_psi : par_.xi_psi_dense) * psi;
}

ForceChainState ForceChainModel::isotropic_state(double p, double void_ratio, double ocr) const {
  ForceChainState s;
  s.stress = p * Tensor::Identity();
  s.chi = kInvSqrt3 * Tensor::Identity();
  s.r_c = std::sqrt(3.0) * p * std::max(ocr, 1.0);
  s.void_ratio = void_ratio;
  s.fluidized = s.r_c < par_.fluidization_size;
  if (s.fluidized) {
    s.r_c = 0.0;
    s.stress.setZero();
  }
  return s;
}

bool ForceChainModel::admissible(const SymTensor& stress, const SymTensor& chi, double r_c) {
  // r > 0 for the locus to be defined, and the no-tension cutoff σ_3 >= 0: grains in contact
  // carry no tension, and beyond σ_3 = 0 (q/p > 3 in compression) the cubic term of the locus
  // opens it (see docs/model/force_chains.md §2). The tolerance 1e-12 absorbs round-off.
  return double_contraction(stress, chi) > kApexRatio * r_c && is_compressive(stress, 1e-12);
}

double ForceChainModel::safe_yield(const SymTensor& stress, const SymTensor& chi, double r_c,
                                   Locus* locus) const {
  if (!(r_c > 0.0)) return -kYieldClip;
  if (admissible(stress, chi, r_c)) {
    Locus l = yield_.locus(stress, chi);
    const double f = std::clamp(yield_.value(l, r_c), -kYieldClip, kYieldClip);
    if (locus) *locus = l;
    return f;
  }
  // at (or beyond) the apex: the origin itself is inside, any other point is in tension
  return norm(stress) <= kApexRatio * r_c ? -kYieldClip : kYieldClip;
}

double ForceChainModel::yield_value(const ForceChainState& state) const {
  return safe_yield(SymTensor::from(state.stress), SymTensor::from(state.chi), state.r_c);
}

double ForceChainModel::dilatancy(const Tensor& stress, double void_ratio) const {
  return dilatancy_.dilatancy(critical_.normalized_stress_ratio(stress),
                              critical_.state_parameter(void_ratio, mean_stress(stress)));
}

Tensor ForceChainModel::flow_direction(const ForceChainState& state) const {
  const Point y{SymTensor::from(state.stress), SymTensor::from(state.chi),
                SymTensor::from(state.plastic_strain), state.r_c, state.void_ratio};
  return plastic_rates(y).m.matrix();
}

ForceChainModel::PlasticRates ForceChainModel::plastic_rates(const Point& y, const Locus* locus,
                                                             Anchor* anchor) const {
  const Locus l = locus ? *locus : yield_.locus(y.stress, y.chi);
  const YieldFunctionDiPrisco::Gradients g = yield_.gradients(l, y.stress, y.chi);
  const double p = kThird * y.stress.trace();
  const SymTensor s = deviator(y.stress);
  // ψ and M_d = M_c exp(n_d ψ) first: their pow and exp depend on p and e only and run beside
  // the chain of cos 3θ and η̃ below
  double psi, m_d;
  dilatancy_terms(p, y.void_ratio, anchor, psi, m_d);
  // invariants of s once: s:s, q = sqrt(3/2 s:s), |s| = sqrt(2/3) q, and cos 3θ =
  // (3√3/2) J3/J2^{3/2} = 9 J3/(s:s q) = 6 J3 q/(s:s)² with J2 = s:s/2 and q² = (3/2) s:s
  // (stress_invariants.hpp; the division beside the square root); 1/(s:s)² also gives
  // 1/|s| = sqrt(3/2)/q = sqrt(2/3) q s:s/(s:s)²
  const double ss = double_contraction(s, s);
  const double q = std::sqrt(1.5 * ss);
  const double inv_ss2 = ss > 0.0 ? 1.0 / (ss * ss) : 0.0;
  const double c3 = ss > 0.0 ? std::clamp(6.0 * determinant(s) * q * inv_ss2, -1.0, 1.0) : 1.0;
  const double normalized_ratio = critical_.normalized_stress_ratio_q(p, q, c3);
  PlasticRates r;
  r.n = g.d_stress;
  // m = (α I + β n_dev)/|m|, α = d_0 (M_d - η̃)/3, β |n_dev| = η̃ sqrt(3/2) (dilatancy header):
  // n_dev is traceless, so |m|² = 3α² + (3/2) η̃², tr m = 3α/|m| and ε_q(m) = η̃/|m|
  const SymTensor n_dev = deviator(g.d_stress);
  const double nn = double_contraction(n_dev, n_dev);
  const double norm_dev = std::sqrt(nn);
  const double alpha = kThird * dilatancy_.volumetric_coefficient_at(m_d, normalized_ratio);
  const double beta_norm = nn > 0.0 ? normalized_ratio * kSqrtThreeHalves : 0.0;  // β|n_dev|
  const double m_norm2 = 3.0 * alpha * alpha + beta_norm * beta_norm;             // |m|²
  double m_trace = std::sqrt(3.0), m_shear = 0.0;  // tr m, ε_q(m); m = I/√3 if m = 0
  double m_dev = 0.0;                              // m = (tr m / 3) I + m_dev n_dev
  if (m_norm2 > 0.0) {
    // 1/(|m| |n_dev|) = sqrt(x)/x, x = |m|² |n_dev|² (square root and division side by side)
    const double x = nn > 0.0 ? m_norm2 * nn : m_norm2;
    const double inv = std::sqrt(x) / x;
    const double inv_m = nn > 0.0 ? norm_dev * inv : inv;
    m_dev = beta_norm * inv;
    m_trace = 3.0 * alpha * inv_m;
    m_shear = kSqrtTwoThirds * beta_norm * inv_m;  // sqrt(2/3) |dev m|
  }
  r.m = (m_dev * n_dev).add_identity(kThird * m_trace);
  // isotropic hardening: dr_c/dλ = (r_c/b_p)(m_v + ξ(ψ) m_q)
  const double xi = deviatoric_hardening(psi);
  const double size_rate_per_r_c = inv_b_p_ * (m_trace + xi * m_shear);
  r.size_rate = y.r_c * size_rate_per_r_c;
  // rotational hardening: dχ/dλ = c_p (χ̂ - χ) projected on the tangent of |χ| = 1
  const double s_norm = kSqrtTwoThirds * q;
  SymTensor chi_target = SymTensor::identity(kInvSqrt3);
  if (s_norm > 1e-12 * std::abs(p) && s_norm > 0.0) {
    // θ̂ = θ̂_e + (θ̂_c - θ̂_e)(1 + cos 3θ)/2; constant (cos, sin from the constructor) when
    // θ̂_c = θ̂_e, as in the defaults
    double cos_theta = cos_theta_hat_, sin_theta = sin_theta_hat_;
    if (!constant_theta_hat_) {
      const double theta =
          par_.theta_hat_e + (par_.theta_hat_c - par_.theta_hat_e) * 0.5 * (1.0 + c3);
      cos_theta = std::cos(theta);
      sin_theta = std::sin(theta);
    }
    // χ̂ = cos θ̂ I/√3 + sin θ̂ s/|s|
    chi_target =
        (sin_theta * kSqrtTwoThirds * q * ss * inv_ss2 * s).add_identity(cos_theta * kInvSqrt3);
  }
  r.chi_rate = par_.c_p * (chi_target - y.chi);
  r.chi_rate -= double_contraction(r.chi_rate, y.chi) * y.chi;
  // H = -(∂f/∂r_c dr_c/dλ + ∂f/∂χ : dχ/dλ) with ∂f/∂r_c = -A/r_c: the r_c of dr_c/dλ cancels
  const double hardening =
      yield_.log_coefficient() * size_rate_per_r_c - double_contraction(g.d_axis, r.chi_rate);
  r.bulk_modulus = elastic_.bulk_modulus(p);
  // D:m = K tr(m) I + 2G dev(m), dev(m) = m_dev n_dev
  r.stiffness_m = (2.0 * elastic_.shear_to_bulk() * r.bulk_modulus * m_dev * n_dev)
                      .add_identity(r.bulk_modulus * m_trace);
  const double n_d_m = double_contraction(r.n, r.stiffness_m);
  // Softening beyond the elastic stiffness (n:D:m + H <= 0) has no strain-driven solution; the
  // denominator is kept >= 1% of n:D:m (documented as a limiter in docs/model/force_chains.md).
  r.denominator = std::max(n_d_m + hardening, 1e-2 * std::abs(n_d_m));
  if (!(r.denominator > 0.0)) r.denominator = 1e-300;
  return r;
}

ForceChainModel::Increment ForceChainModel::increment(const Point& y, const SymTensor& strain,
                                                      double void_factor,
                                                      const PlasticRates& r) const {
  Increment inc;
  inc.void_ratio = (1.0 + y.void_ratio) * void_factor;
  const SymTensor elastic_stress = elastic_.apply_with_modulus(r.bulk_modulus, strain);
  const double dlambda = std::max(double_contraction(r.n, elastic_stress) / r.denominator, 0.0);
  inc.stress = combine(1.0, elastic_stress, -dlambda, r.stiffness_m);
  inc.chi = dlambda * r.chi_rate;
  inc.plastic_strain = dlambda * r.m;
  inc.r_c = dlambda * r.size_rate;
  return inc;
}

double ForceChainModel::correct_drift(Point& y, Locus& locus, bool& has_locus,
                                      Anchor& anchor) const {
  has_locus = false;
  if (!(y.r_c > 0.0) || !admissible(y.stress, y.chi, y.r_c))
    return safe_yield(y.stress, y.chi, y.r_c);
  locus = yield_.locus(y.stress, y.chi);
  has_locus = true;
  double f0 = yield_.value(locus, y.r_c);
  for (int it = 0; it < 4 && std::abs(f0) > par_.yield_tolerance; ++it) {
    const PlasticRates r = plastic_rates(y, &locus, &anchor);
    // consistent correction: move σ, r_c, χ along the plastic flow (Sloan et al. 2001, §4)
    const double dlambda = f0 / r.denominator;
    Point c = y;
    c.stress -= dlambda * r.stiffness_m;
    c.r_c = std::max(y.r_c + dlambda * r.size_rate, 0.5 * y.r_c);
    c.chi += dlambda * r.chi_rate;
    c.chi *= 1.0 / norm(c.chi);
    c.plastic_strain += dlambda * r.m;
    Locus lc;
    lc.r = 0.0;  // set (r > 0) by safe_yield when c is admissible
    double f1 = safe_yield(c.stress, c.chi, c.r_c, &lc);
    if (!(std::abs(f1) < std::abs(f0))) {
      // normal correction: σ only, along ∂f/∂σ
      c = y;
      c.stress -= (f0 / double_contraction(r.n, r.n)) * r.n;
      lc.r = 0.0;
      f1 = safe_yield(c.stress, c.chi, c.r_c, &lc);
      if (!(std::abs(f1) < std::abs(f0))) return f0;
    }
    y = c;
    has_locus = lc.r > 0.0;
    if (has_locus) locus = lc;
    f0 = f1;
  }
  return f0;
}

double ForceChainModel::elastic_fraction(const Point& y, const SymTensor& strain, double f0,
                                         double f1, const SymTensor* stress_gradient) const {
  auto f_at = [&](double alpha) {
    return safe_yield(elastic_.finite_update(y.stress, alpha * strain), y.chi, y.r_c);
  };
  const double ftol = par_.yield_tolerance;
  double lo = 0.0, f_lo = f0, hi = 1.0, f_hi = f1;
  if (f0 > -ftol) {  // starting on the locus: loading or elastic unloading first?
    SymTensor n;
    if (stress_gradient) {
      n = *stress_gradient;
    } else {
      const Locus l = yield_.locus(y.stress, y.chi);
      n = yield_.gradients(l, y.stress, y.chi).d_stress;
    }
    const SymTensor elastic_stress =
        elastic_.apply_with_modulus(elastic_.bulk_modulus(kThird * y.stress.trace()), strain);
    if (double_contraction(n, elastic_stress) >= 0.0) return 0.0;
    constexpr int kScan = 16;  // unloading then reloading inside the increment
    bool found = false;
    for (int j = 1; j <= kScan; ++j) {
      const double a = double(j) / kScan, fa = f_at(a);
      if (!found) {
        if (fa < -ftol) {
          lo = a;
          f_lo = fa;
          found = true;
        }
      } else if (fa > ftol) {
        hi = a;
        f_hi = fa;
        break;
      } else {
        lo = a;
        f_lo = fa;
      }
    }
    if (!found) return 0.0;
  }
  // Illinois (modified regula falsi) on [lo, hi] with f_lo < 0 < f_hi
  double alpha = lo;
  for (int it = 0; it < 60; ++it) {
    alpha = hi - f_hi * (hi - lo) / (f_hi - f_lo);
    if (!(alpha > lo && alpha < hi)) alpha = 0.5 * (lo + hi);
    const double fa = f_at(alpha);
    if (std::abs(fa) <= ftol || hi - lo < 1e-15) break;
    if (fa < 0) {
      lo = alpha;
      f_lo = fa;
      f_hi *= 0.5;
    } else {
      hi = alpha;
      f_hi = fa;
      f_lo *= 0.5;
    }
  }
  return alpha;
}

double ForceChainModel::integrate(Point& y, const SymTensor& strain, double volume_factor,
                                  UpdateInfo& info) const {
  const SymTensor trial = elastic_.finite_update(y.stress, strain);
  const double f_trial = safe_yield(trial, y.chi, y.r_c);
  if (f_trial <= par_.yield_tolerance) {
    y.stress = trial;
    y.void_ratio = (1.0 + y.void_ratio) * volume_factor - 1.0;
    info.yield_value = f_trial;
    return 0.0;
  }
  // r, η, η·η of y: set by safe_yield and correct_drift, reused by plastic_rates(y)
  Locus locus_y;
  bool has_locus = false;
  Anchor anchor;  // p^ξ_c and M_d of the last pow/exp, for the series of the later rates
  const double f0 = safe_yield(y.stress, y.chi, y.r_c, &locus_y);
  // from the stress-free state straight into tension: all contact loss
  if (norm(y.stress) <= kApexRatio * y.r_c && !admissible(trial, y.chi, y.r_c)) return 1.0;
  // On the locus the loading test needs ∂f/∂σ at y, and the first sub-step the rates at y when
  // it loads (α = 0): both from one plastic_rates(y). |f0| < kYieldClip: y is admissible.
  PlasticRates rates_y;
  bool rates_at_y = false;
  if (f0 > -par_.yield_tolerance && std::abs(f0) < kYieldClip) {
    rates_y = plastic_rates(y, &locus_y, &anchor);
    rates_at_y = true;
  }
  const double alpha = elastic_fraction(y, strain, f0, f_trial, rates_at_y ? &rates_y.n : nullptr);
  if (alpha > 0.0) {
    y.stress = elastic_.finite_update(y.stress, alpha * strain);
    y.void_ratio = (1.0 + y.void_ratio) * std::exp(-alpha * strain.trace()) - 1.0;
    rates_at_y = false;
  }
  const SymTensor rest = (1.0 - alpha) * strain;
  const bool fixed = par_.fixed_substeps > 0;
  const double stol = par_.stress_tolerance;
  // The first sub-step is the whole increment (the update depends on the state and the increment
  // only, not on the history of earlier sub-step sizes, so a stationary path stays stationary).
  double t = 0.0, dt = fixed ? 1.0 / par_.fixed_substeps : 1.0;
  bool last_failed = false;
  int attempts = 0;
  double dt_budget = 0.0;  // once max_substeps is spent: the rest in at most 64 forced steps
  auto at_apex = [](const Point& z) { return !admissible(z.stress, z.chi, z.r_c); };
  // z + w (a + b), one pass per tensor
  auto add = [](const Point& z, const Increment& a, const Increment* b, double w) {
    Point out;
    for (int i = 0; i < 6; ++i) {
      out.stress.c[i] = z.stress.c[i] + w * (a.stress.c[i] + (b ? b->stress.c[i] : 0.0));
      out.chi.c[i] = z.chi.c[i] + w * (a.chi.c[i] + (b ? b->chi.c[i] : 0.0));
      out.plastic_strain.c[i] =
          z.plastic_strain.c[i] + w * (a.plastic_strain.c[i] + (b ? b->plastic_strain.c[i] : 0.0));
    }
    out.r_c = std::max(z.r_c + w * (a.r_c + (b ? b->r_c : 0.0)), 0.0);
    out.void_ratio = z.void_ratio + w * (a.void_ratio + (b ? b->void_ratio : 0.0));
    return out;
  };
  while (t < 1.0 - 1e-12) {
    if (++attempts == par_.max_substeps) {
      info.substep_budget_exhausted = true;
      dt_budget = (1.0 - t) / 64.0;
      dt = std::max(dt, dt_budget);
    }
    const bool last_chance = fixed || attempts >= par_.max_substeps || dt < 1e-9;
    const SymTensor sub = dt * rest;
    // 1 + e changes by the factor exp(-tr sub) over the sub-step (the same for both stages)
    const double void_factor = std::expm1(-sub.trace());
    // the rates at y are the same for every attempt from y (rejected sub-steps retry from it)
    if (!rates_at_y) {
      rates_y = plastic_rates(y, has_locus ? &locus_y : nullptr, &anchor);
      rates_at_y = true;
    }
    const Increment k1 = increment(y, sub, void_factor, rates_y);
    const Point y1 = add(y, k1, nullptr, 1.0);
    Point next = y1;
    double error = 0.0;
    // r_c <= 0 inside the pair means the step overshot the collapse of the locus
    bool apex = at_apex(y1), overshoot = !(y1.r_c > 0.0);
    if (!apex && !overshoot) {
      const Increment k2 = increment(y1, sub, void_factor, plastic_rates(y1, nullptr, &anchor));
      next = add(y, k1, &k2, 0.5);
      apex = at_apex(next);
      overshoot = !(next.r_c > 0.0);
      // local error of the Euler/modified-Euler pair: stress and r_c relative, χ absolute (unit);
      // the squares of the three measures compared, one square root
      const double stress_scale2 = std::max(double_contraction(next.stress, next.stress),
                                            par_.pressure_floor * par_.pressure_floor);
      const double size_scale = std::max(next.r_c, par_.fluidization_size);
      const SymTensor d_stress = k2.stress - k1.stress, d_chi = k2.chi - k1.chi;
      const double d_size = (k2.r_c - k1.r_c) / size_scale;
      error = 0.5 * std::sqrt(std::max({double_contraction(d_stress, d_stress) / stress_scale2,
                                        d_size * d_size, double_contraction(d_chi, d_chi)}));
      if (!std::isfinite(error)) overshoot = true;
    }
    if ((apex || overshoot) && !last_chance) {  // shorten the step to approach the apex/collapse
      dt *= 0.25;
      ++info.rejected_substeps;
      last_failed = true;
      continue;
    }
    if (overshoot) {  // forced: the locus collapsed within this sub-step -> fluidization
      y.r_c = 0.0;
      info.plastic = true;
      return 0.0;
    }
    if (apex) return (1.0 - alpha) * (1.0 - t);  // the rest is contact loss at the apex
    if (!last_chance && error > stol) {
      ++info.rejected_substeps;
      dt *= std::max(0.9 * std::sqrt(stol / error), 0.1);
      last_failed = true;
      continue;
    }
    y = next;
    y.chi *= 1.0 / norm(y.chi);
    rates_at_y = false;
    t += dt;
    ++info.substeps;
    info.plastic = true;
    if (y.r_c < par_.fluidization_size) return 0.0;  // fluidized: the caller clears σ
    info.yield_value = correct_drift(y, locus_y, has_locus, anchor);
    if (!fixed) {
      double factor = error > 0.0 ? 0.9 * std::sqrt(stol / error) : 1.1;
      factor = std::clamp(factor, 0.1, last_failed ? 1.0 : 1.1);
      dt *= factor;
      last_failed = false;
    }
    dt = std::min(std::max(dt, dt_budget), 1.0 - t);
  }
  return 0.0;
}

void ForceChainModel::apex_flow(Point& y, const SymTensor& strain) const {
  // All the remaining strain is plastic separation at the stress-free apex; r_c follows the
  // hardening law with that plastic strain (dilation and looser-than-critical shear soften).
  y.stress = SymTensor::zero();
  y.plastic_strain += strain;
  const double psi = critical_.state_parameter(y.void_ratio, 0.0);
  const SymTensor e = deviator(strain);  // ε_q = sqrt(2/3 e:e)
  const double strain_q = std::sqrt(2.0 / 3.0 * double_contraction(e, e));
  const double exponent = (strain.trace() + deviatoric_hardening(psi) * strain_q) / par_.b_p;
  y.r_c *= std::exp(std::clamp(exponent, -700.0, 50.0));
  y.void_ratio = (1.0 + y.void_ratio) * std::exp(-strain.trace()) - 1.0;
}

UpdateInfo ForceChainModel::update(ForceChainState& state, const Eigen::Matrix3d& strain_increment,
                                   double /*dt*/, double granular_temperature,
                                   double volume_factor) const {
  if (!strain_increment.allFinite())
    throw std::invalid_argument("force_chains: non-finite strain increment");
  // 1 + e_new = (1 + e) exp(-Δε_v) must stay above 1 (e >= 0: no grain interpenetration), i.e.
  // Δε_v < ln(1 + e); tested on (1 + e) exp(-Δε_v) itself (the exp serves e_new, no log)
  if (!(volume_factor > 0.0)) volume_factor = std::exp(-strain_increment.trace());
  if (!((1.0 + std::max(state.void_ratio, 0.0)) * volume_factor > 1.0))
    throw std::invalid_argument(
        "force_chains: volumetric strain increment compacts the skeleton "
        "beyond zero void ratio");
  UpdateInfo info;
  const double void_ratio_new = std::max((1.0 + state.void_ratio) * volume_factor - 1.0, 0.0);
  const Tensor plastic_strain_old = state.plastic_strain;

  if (!state.fluidized && state.r_c < par_.fluidization_size) {
    state.fluidized = true;
    info.became_fluid = true;
  }
  if (state.fluidized) {
    // No enduring contacts: σ_FC = 0, χ frozen. Regrowth (docs/model/force_chains.md §5):
    // dr_c = w(T) K_r <dε_v>, w(T) = max(0, 1 - T/T_r), only for e <= e_max.
    const double w =
        std::max(0.0, 1.0 - std::max(granular_temperature, 0.0) / par_.regrowth_temperature);
    const double compaction = std::max(strain_increment.trace(), 0.0);
    if (state.void_ratio <= par_.e_max && !info.became_fluid)
      state.r_c += w * par_.regrowth_modulus * compaction;
    else
      state.r_c = 0.0;
    state.stress.setZero();
    state.plastic_strain += strain_increment;
    state.void_ratio = void_ratio_new;
    if (state.r_c >= par_.resolidification_size) {
      state.fluidized = false;
      info.resolidified = true;
    }
    info.yield_value = -kYieldClip;
    info.plastic_volumetric_strain = strain_increment.trace();
    return info;
  }

  Point y{SymTensor::from(state.stress), SymTensor::from(state.chi),
          SymTensor::from(state.plastic_strain), state.r_c, state.void_ratio};
  SymTensor remaining = SymTensor::from(strain_increment);
  for (int pass = 0; pass < 3; ++pass) {
    // exp(-tr) of the whole increment on the first pass, of the rest after contact loss
    const double left =
        integrate(y, remaining, pass == 0 ? volume_factor : std::exp(-remaining.trace()), info);
    if (y.r_c < par_.fluidization_size || left <= 0.0) break;
    info.contact_loss = true;
    y.stress = SymTensor::zero();
    remaining *= left;
    if (remaining.trace() > 0.0 && pass < 2) continue;  // compaction: reload from the origin
    apex_flow(y, remaining);
    break;
  }
  state.chi = y.chi.matrix();
  state.plastic_strain = y.plastic_strain.matrix();
  state.void_ratio = void_ratio_new;
  if (y.r_c < par_.fluidization_size) {
    state.fluidized = true;
    state.r_c = 0.0;
    state.stress.setZero();
    info.became_fluid = true;
    info.yield_value = -kYieldClip;
  } else {
    state.r_c = y.r_c;
    state.stress = y.stress.matrix();
    if (info.contact_loss) info.yield_value = safe_yield(y.stress, y.chi, y.r_c);
  }
  info.plastic_volumetric_strain = (state.plastic_strain - plastic_strain_old).trace();
  if (!(state.stress.allFinite() && state.chi.allFinite() && std::isfinite(state.r_c)))
    throw std::runtime_error("force_chains: non-finite stress, axis or r_c after update");
  return info;
}

}  // namespace granflow::model::force_chains
