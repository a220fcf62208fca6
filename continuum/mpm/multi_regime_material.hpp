// The multi-regime model (continuum::MultiRegimePoint: σ = σ_FC + σ_COL + σ_L with the granular
// temperature T; seed Eq. 7, 19, 24; docs/model/multi_regime.md, §6) as an MPM solid material. One
// call per step over the material's range of points; the state lives in this object's own arrays
// (structure of arrays, indexed by point - begin): σ_FC (xx, yy, zz, xy), the yield-locus axis χ
// (xx, yy, zz, xy), r_c and e. T is the solver's solid-point array (carried by the points, remapped
// and conducted by the solver).
//
// Coupling to the double-point solver (docs/rheometer.md):
//  * signs (docs/model/conventions.md): the model is compression positive, ε̇ = -D; the solver's
//    effective stress σ' (tension positive) is -(σ_FC + σ_COL + σ_L): the skeleton,
//    collisional and mixture-viscous parts act on the solid phase; the pore pressure and the
//    liquid's own η0 viscous stress stay on the liquid points;
//  * the solid fraction of a point at the start of the step is 1 - n of the solver (V_s / V), so
//    e never drifts from the point volumes; advance() moves it by exp(tr ε̇ dt) over the step, the
//    solver's own volume update to O(dt²);
//  * objectivity: σ_FC and χ are rotated with the spin W (Jaumann) before the update, as the
//    linear elastic material does;
//  * plane strain: ε̇_zz = 0, the zz components evolve with the model;
//  * internal length (set_internal_length, ℓ > 0): the softening of the locus is averaged
//    non-locally over ℓ (update_stress, multi_regime_material.cpp; nonlocal_average.hpp); ℓ = 0
//    (the default) is the local model, bit for bit, at no cost.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "continuum/mpm/material_points.hpp"
#include "continuum/mpm/nonlocal_average.hpp"
#include "continuum/mpm/solid_material.hpp"
#include "continuum/multi_regime/multi_regime_point.hpp"

namespace granflow::mpm {

// Isotropic initial state of every point of the material (the end of a drained isotropic
// consolidation): void ratio e (from the point porosity when < 0), p' = σ_FC, OCR, T.
struct MultiRegimeInitialState {
  double effective_pressure = 50.0e3;  // p', Pa (compression positive)
  double ocr = 1.0;                    // r_c / (√3 p')
  double granular_temperature = 0.0;   // T, m²/s²
};

class MultiRegimeMaterial final : public SolidMaterial {
 public:
  MultiRegimeMaterial(continuum::MultiRegimeSettings settings, MultiRegimeInitialState initial);
  const std::string& name() const override { return name_; }
  double grain_density() const override {
    return point_.settings().collisional_parameters.particle_density;
  }
  // Largest constrained modulus over the points at the last update: (3K(p) (1-ν))/(1+ν) of the
  // skeleton's pressure-dependent elasticity (force_chains) at the largest mean σ_FC.
  double p_wave_modulus() const override;
  // Sizes the state arrays; the initial state is set by initialize() once porosities are known.
  void attach(std::size_t begin, std::size_t end) override;
  // Sets the state of every point from the initial state and its porosity, and writes σ' and T
  // into the solid-point arrays (tension positive).
  void initialize(SolidPoints& points);
  void update_stress(const StressUpdateView& view, double dt) override;
  // Independent point updates unless the softening is averaged non-locally (ℓ > 0).
  bool updates_points_independently() const override { return !nonlocal_; }
  void begin_ranges(int threads) override;
  void update_range(const StressUpdateView& view, double dt, std::size_t b, std::size_t e,
                    int t) override;
  void finish_ranges(const StressUpdateView& view) override;
  std::vector<std::pair<std::string, std::vector<double>*>> state() override;
  // Internal length ℓ (m) of the non-local softening and the over-nonlocal factor m (1: plain
  // non-local average, which still lets the softening localize into one point spacing; 2: the
  // over-nonlocal form of Vermeer & Brinkgreve 1994, a zone width ∝ ℓ, tests/mpm
  // test_mpm_nonlocal); ℓ = 0 switches it off. The solver must pass the point positions and
  // volumes in the view (StressUpdateView::x, y, volume).
  void set_internal_length(double length, double overnonlocal = 2.0);
  double internal_length() const { return nonlocal_ ? nonlocal_->length() : 0.0; }
  const NonlocalAverage* nonlocal() const { return nonlocal_.get(); }

  const continuum::MultiRegimePoint& point() const { return point_; }
  // Per point (index - begin): r_c (Pa), e, σ_FC and σ_COL means (Pa), shear rate γ̇ (1/s).
  const std::vector<double>& locus_size() const { return r_c_; }
  const std::vector<double>& void_ratio() const { return void_ratio_; }
  const std::vector<double>& collisional_pressure() const { return collisional_pressure_; }
  const std::vector<double>& shear_rate() const { return shear_rate_; }
  // Point updates evaluated at the closures' packing limit ν_lim (ν would have exceeded it).
  long clamped_updates() const { return clamped_updates_; }
  double solid_fraction_limit() const { return solid_fraction_limit_; }

 private:
  std::string name_ = "multi_regime";
  continuum::MultiRegimePoint point_;
  MultiRegimeInitialState initial_;
  // force-chain state (compression positive), per point
  std::vector<double> fc_xx_, fc_yy_, fc_zz_, fc_xy_;
  std::vector<double> chi_xx_, chi_yy_, chi_zz_, chi_xy_;
  std::vector<double> r_c_, void_ratio_;
  // diagnostics of the last update
  std::vector<double> collisional_pressure_, shear_rate_;
  double max_effective_pressure_ = 0.0;
  double solid_fraction_limit_ = 0.74;  // ν_lim: below ν_c and the η(ν) maximum packing
  long clamped_updates_ = 0;
  // each thread's results of update_range, combined by finish_ranges: the last failed point,
  // the largest mean σ_FC, the clamped updates (one cache line per thread)
  struct alignas(64) RangeResult {
    long bad = -1;
    double max_p = 0.0;
    long clamped = 0;
  };
  std::vector<RangeResult> range_results_;
  // non-local softening (ℓ > 0 only): r_c at the start of the step, relative increment of the
  // local update, its average, and which points have a locus (r_c > 0)
  std::unique_ptr<NonlocalAverage> nonlocal_;
  double overnonlocal_ = 2.0;
  std::vector<double> r_c_start_, softening_, softening_average_;
  std::vector<std::uint8_t> has_locus_;
  // positions and volumes of the last neighbour-list build, checkpointed (state()) so that a
  // restart rebuilds the same lists; NaN until the first build
  std::vector<double> built_x_, built_y_, built_volume_;
  void average_softening(const StressUpdateView& view);
};

}  // namespace granflow::mpm
