// The inertial rheology of frictionless spheres (Peyneau & Roux 2008, Phys. Rev. E 78, 011307,
// "Frictionless bead packs have macroscopic friction, but no dilatancy"):
//   μ(I) = μ_0 + c I^α,
//   φ(I) = φ_RCP − b I^β,
// power laws from finite quasi-static limits: μ_0 ≈ 0.10 (internal friction angle ≈ 5.8°) and
// φ_RCP ≈ 0.639, the random close packing fraction (no dilatancy in the quasi-static limit). The
// GDR MiDi form (gdr_midi_law.hpp) does not describe frictionless spheres: its μ(I) saturates
// and its φ(I) is linear, both regular at I = 0, while the power laws have an infinite slope
// there for α, β < 1. The fitted parameter vectors are θ_μ = (μ_0, c, α), θ_φ = (φ_RCP, b, β).
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace granflow::dem {

struct PeyneauRouxLaw {
  static constexpr const char* name = "peyneau_roux";
  static constexpr const char* reference = "Peyneau & Roux 2008";
  static constexpr const char* friction_formula = "μ(I) = μ_0 + c I^α";
  static constexpr const char* solid_fraction_formula = "φ(I) = φ_RCP − b I^β";
  static constexpr const char* friction_parameters[] = {"mu_0", "c", "alpha"};
  static constexpr const char* solid_fraction_parameters[] = {"phi_rcp", "b", "beta"};
  static double friction(double inertial, const Eigen::VectorXd& theta) {
    return theta[0] + theta[1] * std::pow(inertial, theta[2]);
  }
  static double solid_fraction(double inertial, const Eigen::VectorXd& theta) {
    return theta[0] - theta[1] * std::pow(inertial, theta[2]);
  }
};

}  // namespace granflow::dem
