#include "continuum/mpm/multi_regime_material.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "continuum/model/exp_near_zero.hpp"
#include "continuum/mpm/material_points.hpp"
#include "continuum/mpm/solver.hpp"

namespace granflow::mpm {

MultiRegimeMaterial::MultiRegimeMaterial(continuum::MultiRegimeSettings settings,
                                         MultiRegimeInitialState initial)
    : point_(std::move(settings)), initial_(initial) {
  if (!(initial_.effective_pressure >= 0) || !(initial_.ocr >= 1) ||
      !(initial_.granular_temperature >= 0))
    throw std::invalid_argument(
        "multi_regime: need effective_pressure >= 0, ocr >= 1, temperature >= 0");
  max_effective_pressure_ = initial_.effective_pressure;
  const auto& st = point_.settings();
  solid_fraction_limit_ = 0.74;
  if (st.collisional)
    solid_fraction_limit_ =
        std::min(solid_fraction_limit_, st.collisional_parameters.jamming_fraction);
  if (st.liquid)
    solid_fraction_limit_ = std::min(solid_fraction_limit_,
                                     model::maximum_mixture_solid_fraction(st.liquid_parameters));
  solid_fraction_limit_ -= 1e-3;
}

double MultiRegimeMaterial::p_wave_modulus() const {
  if (!point_.settings().force_chains) return 1.0;  // no skeleton: waves from the liquid only
  const auto& f = point_.settings().force_chain_parameters;
  const double p = std::max(max_effective_pressure_, f.pressure_floor);
  const double K = f.bulk_modulus_ref * std::pow(p / f.reference_pressure, f.elastic_exponent);
  return 3.0 * K * (1.0 - f.poisson_ratio) / (1.0 + f.poisson_ratio);
}

void MultiRegimeMaterial::attach(std::size_t begin, std::size_t end) {
  SolidMaterial::attach(begin, end);
  const std::size_t n = end - begin;
  for (auto* a : {&fc_xx_, &fc_yy_, &fc_zz_, &fc_xy_, &chi_xx_, &chi_yy_, &chi_zz_, &chi_xy_, &r_c_,
                  &void_ratio_, &collisional_pressure_, &shear_rate_})
    a->assign(n, 0.0);
}

void MultiRegimeMaterial::set_internal_length(double length, double overnonlocal) {
  if (!(length >= 0) || !(overnonlocal >= 1))
    throw std::invalid_argument("multi_regime: need internal length >= 0, overnonlocal >= 1");
  overnonlocal_ = overnonlocal;
  nonlocal_.reset();
  if (length > 0) nonlocal_ = std::make_unique<NonlocalAverage>(length);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (auto* a : {&built_x_, &built_y_, &built_volume_})
    a->assign(length > 0 ? end_ - begin_ : 0, nan);
}

void MultiRegimeMaterial::initialize(SolidPoints& s) {
  for (std::size_t p = begin_; p < end_; ++p) {
    const std::size_t k = p - begin_;
    const double e = s.porosity[p] / (1.0 - s.porosity[p]);
    const continuum::PointState st = point_.initial_state(
        e, initial_.effective_pressure, initial_.ocr, initial_.granular_temperature);
    const auto& fc = st.force_chains;
    fc_xx_[k] = fc.stress(0, 0);
    fc_yy_[k] = fc.stress(1, 1);
    fc_zz_[k] = fc.stress(2, 2);
    fc_xy_[k] = fc.stress(0, 1);
    chi_xx_[k] = fc.chi(0, 0);
    chi_yy_[k] = fc.chi(1, 1);
    chi_zz_[k] = fc.chi(2, 2);
    chi_xy_[k] = fc.chi(0, 1);
    r_c_[k] = fc.r_c;
    void_ratio_[k] = e;
    s.temperature[p] = st.granular_temperature;
    s.sxx[p] = -fc_xx_[k];
    s.syy[p] = -fc_yy_[k];
    s.szz[p] = -fc_zz_[k];
    s.sxy[p] = -fc_xy_[k];
  }
}

namespace {
// Jaumann rotation of a symmetric plane tensor (zz untouched) by the spin W = [[0, w], [-w, 0]]:
// A += dt (W A - A W): xx += 2 w A_xy dt, yy -= 2 w A_xy dt, xy += w (A_yy - A_xx) dt.
inline void rotate(double& xx, double& yy, double& xy, double w_dt) {
  const double a = xx, b = yy, c = xy;
  xx = a + 2.0 * w_dt * c;
  yy = b - 2.0 * w_dt * c;
  xy = c + w_dt * (b - a);
}
}  // namespace

void MultiRegimeMaterial::update_stress(const StressUpdateView& v, double dt) {
  if (nonlocal_) r_c_start_.assign(r_c_.begin(), r_c_.end());
  begin_ranges(v.threads);
  // Static contiguous parts: on 2 threads the rheometer's first 1000 steps took 2.09 ms per step
  // against 2.28 with schedule(dynamic, 64) and 2.19 with (dynamic, 384) (1 thread: 3.6-3.8 ms;
  // docs/performance.md#rheometer_bench). The plastic points lie in rings, which every θ-part of
  // the annulus holds alike.
  const std::size_t n = end_ - begin_;
#pragma omp parallel num_threads(v.threads) if (v.threads > 1)
  {
    const std::size_t T = static_cast<std::size_t>(omp_get_num_threads());
    const std::size_t t = static_cast<std::size_t>(omp_get_thread_num());
    update_range(v, dt, begin_ + n * t / T, begin_ + n * (t + 1) / T, static_cast<int>(t));
  }
  finish_ranges(v);
  if (nonlocal_) average_softening(v);
}

void MultiRegimeMaterial::begin_ranges(int threads) {
  range_results_.assign(static_cast<std::size_t>(std::max(threads, 1)), RangeResult{});
}

void MultiRegimeMaterial::update_range(const StressUpdateView& v, double dt, std::size_t first,
                                       std::size_t last, int t) {
  const long b = static_cast<long>(begin_);
  long bad = -1;
  double max_p = 0.0;
  long clamped = 0;
  for (long p = static_cast<long>(first); p < static_cast<long>(last); ++p) {
    const std::size_t k = static_cast<std::size_t>(p - b);
    const double Dxx = v.Lxx[p], Dyy = v.Lyy[p], Dxy = 0.5 * (v.Lxy[p] + v.Lyx[p]);
    const double w_dt = 0.5 * (v.Lxy[p] - v.Lyx[p]) * dt;
    continuum::PointState st;
    // mass balance of MultiRegimePoint::advance (ν ∝ exp(tr ε̇ dt), tr ε̇ = -(D_xx + D_yy)), done
    // here for the guard of the closures' domain: a point packed beyond ν_lim (a fluidized
    // skeleton clumping between MPM points) is evaluated at ν_lim; counted and reported
    // (docs/rheometer.md).
    // The force chains' void-ratio factor exp(-tr ε̇ dt) = ν_start/ν_end is the inverse of ν's
    // (a division for the exp of ForceChainModel::update).
    double nu_start = 1.0 - v.porosity[p];
    const double growth = model::exp_near_zero(-(Dxx + Dyy) * dt);
    const double nu_end = nu_start * growth;
    double volume_factor = 1.0 / growth;
    st.solid_fraction = nu_end;
    if (nu_end > solid_fraction_limit_) {
      volume_factor = model::exp_near_zero((Dxx + Dyy) * dt);
      nu_start = solid_fraction_limit_ * volume_factor;
      st.solid_fraction = solid_fraction_limit_;
      ++clamped;
    }
    st.granular_temperature = std::max(v.temperature[p], 0.0);
    auto& fc = st.force_chains;
    rotate(fc_xx_[k], fc_yy_[k], fc_xy_[k], w_dt);
    rotate(chi_xx_[k], chi_yy_[k], chi_xy_[k], w_dt);
    fc.stress << fc_xx_[k], fc_xy_[k], 0, fc_xy_[k], fc_yy_[k], 0, 0, 0, fc_zz_[k];
    fc.chi << chi_xx_[k], chi_xy_[k], 0, chi_xy_[k], chi_yy_[k], 0, 0, 0, chi_zz_[k];
    fc.r_c = r_c_[k];
    fc.void_ratio = 1.0 / nu_start - 1.0;
    // compression-positive strain rate of the model: ε̇ = -D (plane strain, D_zz = 0)
    continuum::PlaneStep out;
    try {
      out = point_.advance_plane(st, -Dxx, -Dyy, -Dxy, dt, volume_factor);
    } catch (const std::exception&) {
      bad = std::max(bad, p);
      continue;
    }
    const Eigen::Matrix3d& s_fc = st.force_chains.stress;
    fc_xx_[k] = s_fc(0, 0);
    fc_yy_[k] = s_fc(1, 1);
    fc_zz_[k] = s_fc(2, 2);
    fc_xy_[k] = 0.5 * (s_fc(0, 1) + s_fc(1, 0));
    chi_xx_[k] = st.force_chains.chi(0, 0);
    chi_yy_[k] = st.force_chains.chi(1, 1);
    chi_zz_[k] = st.force_chains.chi(2, 2);
    chi_xy_[k] = 0.5 * (st.force_chains.chi(0, 1) + st.force_chains.chi(1, 0));
    r_c_[k] = st.force_chains.r_c;
    void_ratio_[k] = st.force_chains.void_ratio;
    collisional_pressure_[k] = out.collisional_pressure;
    // γ̇ = sqrt(2 ε̇':ε̇') (MultiRegimePoint::shear_rate) of the plane strain rate ε̇ = -D
    shear_rate_[k] = out.shear_rate;
    v.temperature[p] = st.granular_temperature;
    if (v.conductivity) {
      // κ_T = ρ_p d f4(ν) T^½ (model::collisional_conductivity; docs/model/closures.md), with
      // the coefficients and T^½ of this step's update
      v.conductivity[p] = 0.0;
      if (point_.settings().collisional) {
        const auto& cp = point_.settings().collisional_parameters;
        v.conductivity[p] = cp.particle_density * cp.diameter * out.f4 * out.sqrt_temperature;
      }
    }
    // σ' of the solver (tension positive) = -(σ_FC + σ_COL + σ_L) (docs/model/conventions.md)
    v.sxx[p] = -out.xx;
    v.syy[p] = -out.yy;
    v.szz[p] = -out.zz;
    v.sxy[p] = -out.xy;
    const double p_fc = s_fc.trace() / 3.0;
    max_p = std::max(max_p, p_fc);
    if (!std::isfinite(out.xx + out.yy + out.zz + out.xy) ||
        !std::isfinite(st.granular_temperature) || st.granular_temperature < 0.0)
      bad = std::max(bad, p);
  }
  RangeResult& r = range_results_[static_cast<std::size_t>(t)];
  r.bad = bad;
  r.max_p = max_p;
  r.clamped = clamped;
}

void MultiRegimeMaterial::finish_ranges(const StressUpdateView& v) {
  long bad = -1;
  double max_p = 0.0;
  for (const RangeResult& r : range_results_) {  // max and integer sums: in any order exact
    bad = std::max(bad, r.bad);
    max_p = std::max(max_p, r.max_p);
    clamped_updates_ += r.clamped;
  }
  max_effective_pressure_ = max_p;
  if (bad >= 0) {
    const std::size_t k = static_cast<std::size_t>(bad) - begin_;
    throw core::NumericalFailure(
        -1, fmt::format("solid point {}", bad), "multi_regime stress/T", v.temperature[bad],
        fmt::format("multi-regime update failed (n = {:.4g}, r_c = {:.4g} Pa, "
                    "T = {:.4g} m²/s²; ν outside the closures' range, or NaN)",
                    v.porosity[bad], r_c_[k], v.temperature[bad]));
  }
}

// Non-local softening of the locus (ℓ > 0). The softening variable of the force chains is the
// locus size: dr_c = (r_c/b_p)[dε^p_v + ξ(ψ) dε^p_q] (docs/rheometer.md, "The force-chain
// hardening law"), i.e. d ln r_c = dκ with the plastic-strain measure dκ = (dε^p_v + ξ dε^p_q)/b_p,
// whose deviatoric part softens a loose skeleton (ξ < 0) and localizes it into bands of the cell
// width. Non-local plasticity replaces κ by its average over ℓ (Bažant & Jirásek 2002, Eq. 1-3
// and §4.1); over-nonlocal (Vermeer & Brinkgreve 1994): κ̂ = m κ̄ + (1 − m) κ. Explicitly, per
// step, with the local update's relative increment δ_i = Δr_c,i / r_c,i (= Δκ_i to O(Δκ²)):
//
//   r_c,i ← r_c,i^start (1 + m δ̄_i + (1 − m) δ_i),   δ̄_i = Σ_j α_ij δ_j (nonlocal_average.hpp),
//
// over the points with a locus at the start of the step (r_c > 0; a fluidized point has no
// plastic flow and regrows its locus locally). The stress was returned to the local locus; the
// next step's return mapping starts from the non-local one (a point whose locus shrank is
// projected back, one whose locus grew unloads elastically): the explicit, one-step-lagged form
// of the non-local consistency condition, as in explicit MPM (Burghardt, Brannon & Guilkey 2012).
void MultiRegimeMaterial::average_softening(const StressUpdateView& v) {
  if (!v.x || !v.y || !v.volume)
    throw std::logic_error("multi_regime: internal length set, but no point positions in the view");
  const std::size_t n = end_ - begin_;
  softening_.resize(n);
  softening_average_.resize(n);
  has_locus_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    has_locus_[k] = r_c_start_[k] > 0.0;
    softening_[k] = has_locus_[k] ? (r_c_[k] - r_c_start_[k]) / r_c_start_[k] : 0.0;
  }
  // after a restart: the lists of the checkpointed build first (bit for bit), then the skin test
  if (nonlocal_->builds() == 0 && n > 0 && std::isfinite(built_x_[0]))
    nonlocal_->build(built_x_.data(), built_y_.data(), built_volume_.data(), n, v.threads);
  if (nonlocal_->update(v.x + begin_, v.y + begin_, v.volume + begin_, n, v.threads)) {
    built_x_ = nonlocal_->built_x();
    built_y_ = nonlocal_->built_y();
    built_volume_ = nonlocal_->built_volume();
  }
  nonlocal_->average(softening_.data(), has_locus_.data(), softening_average_.data(), v.threads);
  const double m = overnonlocal_;
  for (std::size_t k = 0; k < n; ++k)
    if (has_locus_[k])
      r_c_[k] = std::max(
          r_c_start_[k] * (1.0 + m * softening_average_[k] + (1.0 - m) * softening_[k]), 0.0);
}

std::vector<std::pair<std::string, std::vector<double>*>> MultiRegimeMaterial::state() {
  std::vector<std::pair<std::string, std::vector<double>*>> s = {
      {"fc_xx", &fc_xx_},   {"fc_yy", &fc_yy_},          {"fc_zz", &fc_zz_},   {"fc_xy", &fc_xy_},
      {"chi_xx", &chi_xx_}, {"chi_yy", &chi_yy_},        {"chi_zz", &chi_zz_}, {"chi_xy", &chi_xy_},
      {"r_c", &r_c_},       {"void_ratio", &void_ratio_}};
  if (nonlocal_) {  // with ℓ > 0 only: the checkpoint of ℓ = 0 is unchanged
    s.emplace_back("nonlocal_x", &built_x_);
    s.emplace_back("nonlocal_y", &built_y_);
    s.emplace_back("nonlocal_volume", &built_volume_);
  }
  return s;
}

}  // namespace granflow::mpm
