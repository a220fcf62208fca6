// The dense inertial rheology of frictional spheres (docs/dem_dataset.md):
//   μ(I) = μ_s + (μ_2 − μ_s)/(1 + I_0/I)   (GDR MiDi 2004, Eur. Phys. J. E 14, 341; Jop,
//                                           Forterre & Pouliquen 2006, Nature 441, 727),
//   φ(I) = φ_c − a I                        (da Cruz et al. 2005, Phys. Rev. E 72, 021309).
// μ_s and φ_c are the I → 0 (quasi-static, critical-state) limits. The fitted parameter vectors
// are θ_μ = (μ_s, μ_2, I_0) and θ_φ = (φ_c, a).
#pragma once

#include <Eigen/Core>

namespace granflow::dem {

inline double inertial_friction_law(double inertial, double mu_s, double mu_2, double i_0) {
  return mu_s + (mu_2 - mu_s) / (1.0 + i_0 / inertial);
}

struct GdrMidiLaw {
  static constexpr const char* name = "gdr_midi";
  static constexpr const char* reference =
      "GDR MiDi 2004; Jop et al. 2006 (mu); da Cruz et al. 2005 (phi)";
  static constexpr const char* friction_formula = "μ(I) = μ_s + (μ_2 − μ_s)/(1 + I_0/I)";
  static constexpr const char* solid_fraction_formula = "φ(I) = φ_c − a I";
  static constexpr const char* friction_parameters[] = {"mu_s", "mu_2", "I_0"};
  static constexpr const char* solid_fraction_parameters[] = {"phi_c", "a"};
  static double friction(double inertial, const Eigen::VectorXd& theta) {
    return inertial_friction_law(inertial, theta[0], theta[1], theta[2]);
  }
  static double solid_fraction(double inertial, const Eigen::VectorXd& theta) {
    return theta[0] - theta[1] * inertial;
  }
};

}  // namespace granflow::dem
