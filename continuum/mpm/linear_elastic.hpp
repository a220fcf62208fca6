// Isotropic linear elasticity in rate form with the Jaumann objective stress rate:
//   σ̇' = λ tr(D) I + 2 G D + W σ' - σ' W,   D = sym L, W = skew L,
// plane strain (D_zz = 0, σ_zz evolves through λ tr D). λ = E ν/((1+ν)(1-2ν)), G = E/(2(1+ν)).
// Written in the solver's tension-positive convention (docs/model/conventions.md).
#pragma once

#include <string>

#include "continuum/mpm/material_registry.hpp"
#include "continuum/mpm/solid_material.hpp"

namespace granflow::mpm {

// Its parameters, as the `solid` section gives them (SI).
struct LinearElasticParameters {
  double young_modulus = 1.0e7;  // E, Pa
  double poisson_ratio = 0.0;    // ν
  double density = 2650.0;       // ρ_s, grain density, kg/m³
};

class LinearElastic final : public SolidMaterial {
 public:
  static constexpr const char* material_name = "linear_elastic";  // `solid.material`
  explicit LinearElastic(const LinearElasticParameters& p);
  // E (Pa), ν (Poisson ratio), ρ_s grain density (kg/m³).
  LinearElastic(double young_modulus, double poisson_ratio, double grain_density)
      : LinearElastic(LinearElasticParameters{young_modulus, poisson_ratio, grain_density}) {}
  const std::string& name() const override { return name_; }
  double grain_density() const override { return grain_density_; }
  double p_wave_modulus() const override { return lambda_ + 2.0 * shear_modulus_; }
  void update_stress(const StressUpdateView& view, double dt) override;
  bool updates_points_independently() const override { return true; }
  void update_range(const StressUpdateView& view, double dt, std::size_t b, std::size_t e,
                    int t) override;

 private:
  std::string name_ = material_name;
  double lambda_, shear_modulus_, grain_density_;
};

// Its keys of the `solid` section (young_modulus, poisson_ratio, density) and their reading:
// the entry of material_registry().
MaterialEntry linear_elastic_material();
LinearElasticParameters read_linear_elastic(const core::Case& c);

}  // namespace granflow::mpm
