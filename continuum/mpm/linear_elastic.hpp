// Isotropic linear elasticity in rate form with the Jaumann objective stress rate:
//   σ̇' = λ tr(D) I + 2 G D + W σ' - σ' W,   D = sym L, W = skew L,
// plane strain (D_zz = 0, σ_zz evolves through λ tr D). λ = E ν/((1+ν)(1-2ν)), G = E/(2(1+ν)).
#pragma once

#include <string>

#include "continuum/mpm/solid_material.hpp"

namespace granflow::mpm {

class LinearElastic final : public SolidMaterial {
 public:
  // E (Pa), ν (Poisson ratio), ρ_s grain density (kg/m³).
  LinearElastic(double young_modulus, double poisson_ratio, double grain_density);
  const std::string& name() const override { return name_; }
  double grain_density() const override { return grain_density_; }
  double p_wave_modulus() const override { return lambda_ + 2.0 * shear_modulus_; }
  void update_stress(const StressUpdateView& view, double dt) override;

 private:
  std::string name_ = "linear_elastic";
  double lambda_, shear_modulus_, grain_density_;
};

}  // namespace granflow::mpm
