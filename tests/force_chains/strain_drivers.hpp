// Strain-driven material-point drivers for the force-chain tests (compression positive).
// Axis 0 is the axial direction of the triaxial tests.
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "continuum/model/force_chains/force_chain_model.hpp"

namespace granflow::model::force_chains::testing {

inline Eigen::Matrix3d diag(double a, double b, double c) {
  return Eigen::Vector3d(a, b, c).asDiagonal();
}

// Undrained (isochoric) triaxial compression step: Δε = diag(Δε_a, -Δε_a/2, -Δε_a/2).
inline UpdateInfo undrained_triaxial_step(const ForceChainModel& model, ForceChainState& s,
                                          double axial, double temperature = 0.0) {
  return model.update(s, diag(axial, -0.5 * axial, -0.5 * axial), 1.0, temperature);
}

// Drained triaxial step at constant radial stress: the radial strain is solved by a secant
// iteration so that σ_rr returns to `radial_stress` (|residual| < 1e-9 σ_r). `axial_sign` = -1
// gives triaxial extension (axial unloading) at constant radial stress.
inline UpdateInfo drained_triaxial_step(const ForceChainModel& model, ForceChainState& s,
                                        double axial, double radial_stress) {
  auto run = [&](double radial, ForceChainState& out) {
    out = s;
    return model.update(out, diag(axial, radial, radial), 1.0, 0.0);
  };
  const double p = std::max(s.stress.trace() / 3.0, model.parameters().pressure_floor);
  const double k = model.elasticity().bulk_modulus(p);
  const double g = model.elasticity().shear_modulus(p);
  // elastic guess: σ_r unchanged for Δε_r = -ν/(1-ν)... written via K, G
  double x0 = -axial * (k - 2.0 * g / 3.0) / (2.0 * k + 2.0 * g / 3.0);
  ForceChainState t;
  run(x0, t);
  double r0 = t.stress(1, 1) - radial_stress;
  double x1 = x0 - r0 / (2.0 * k + 2.0 * g / 3.0);
  UpdateInfo info = run(x1, t);
  double r1 = t.stress(1, 1) - radial_stress;
  for (int it = 0; it < 60 && std::abs(r1) > 1e-9 * radial_stress; ++it) {
    const double slope = (r1 - r0) / (x1 - x0);
    const double x2 = (slope != 0.0 && std::isfinite(slope)) ? x1 - r1 / slope : x1 * 1.01;
    x0 = x1;
    r0 = r1;
    x1 = x2;
    info = run(x1, t);
    r1 = t.stress(1, 1) - radial_stress;
  }
  s = t;
  return info;
}

inline double p_of(const ForceChainState& s) { return s.stress.trace() / 3.0; }
inline double q_of(const ForceChainState& s) { return s.stress(0, 0) - s.stress(1, 1); }

}  // namespace granflow::model::force_chains::testing
