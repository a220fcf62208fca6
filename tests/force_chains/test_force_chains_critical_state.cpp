// Critical state as attractor: drained triaxial tests (constant radial stress) on dense and
// loose samples reach the same stress ratio M_c (Lade-Duncan at the compression Lode angle),
// the same critical void ratio e_cs(p), and zero dilatancy; loose contracts, dense dilates.
// Lode-angle independence of the dilatancy, and the attractor in triaxial extension.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "continuum/model/force_chains/force_chain_model.hpp"
#include "tests/force_chains/strain_drivers.hpp"

namespace fc = granflow::model::force_chains;
using fc::testing::diag;
using fc::testing::p_of;
using fc::testing::q_of;

namespace {
struct DrainedResult {
  double stress_ratio, void_ratio, critical_void_ratio, dilatancy, min_void_ratio, max_void_ratio;
};

DrainedResult drained(const fc::ForceChainModel& model, double e0, double axial_total, int steps,
                      double radial = 100e3) {
  auto s = model.isotropic_state(radial, e0);
  DrainedResult r{0, 0, 0, 0, e0, e0};
  const double d = axial_total / steps;
  for (int i = 0; i < steps; ++i) {
    fc::testing::drained_triaxial_step(model, s, d, radial);
    r.min_void_ratio = std::min(r.min_void_ratio, s.void_ratio);
    r.max_void_ratio = std::max(r.max_void_ratio, s.void_ratio);
  }
  EXPECT_FALSE(s.fluidized);
  r.stress_ratio = q_of(s) / p_of(s);
  r.void_ratio = s.void_ratio;
  r.critical_void_ratio = model.critical_state().critical_void_ratio(p_of(s));
  r.dilatancy = model.dilatancy(s.stress, s.void_ratio);
  return r;
}
}  // namespace

TEST(ForceChainsCriticalState, DenseAndLooseReachTheSameCriticalState) {
  const fc::ForceChainModel model{fc::ForceChainParameters{}};
  const double mc = model.parameters().M_c;
  const auto dense = drained(model, 0.55, 2.0, 2000);
  const auto loose = drained(model, 0.70, 2.0, 2000);
  std::printf("dense: q/p=%.4f e=%.4f e_cs=%.4f D=%.2e; loose: q/p=%.4f e=%.4f e_cs=%.4f D=%.2e\n",
              dense.stress_ratio, dense.void_ratio, dense.critical_void_ratio, dense.dilatancy,
              loose.stress_ratio, loose.void_ratio, loose.critical_void_ratio, loose.dilatancy);
  // M_c is the Lade-Duncan ratio at the compression Lode angle
  EXPECT_NEAR(model.critical_state().stress_ratio(1.0), mc, 1e-12);
  // at ε_a = 2 both are within 0.5 % of M_c and of each other, 0.002 of e_cs (the approach is
  // exponential in strain, see docs/model/force_chains.md; the dense sample is the slower one)
  EXPECT_NEAR(dense.stress_ratio, mc, 5e-3 * mc);
  EXPECT_NEAR(loose.stress_ratio, mc, 5e-3 * mc);
  EXPECT_NEAR(dense.void_ratio, dense.critical_void_ratio, 2e-3);
  EXPECT_NEAR(loose.void_ratio, loose.critical_void_ratio, 2e-3);
  EXPECT_NEAR(dense.void_ratio, loose.void_ratio, 3e-3);  // same e_cs at the same p
  // dilatancy -> 0 (it starts at O(1-10))
  EXPECT_LT(std::abs(dense.dilatancy), 5e-3);
  EXPECT_LT(std::abs(loose.dilatancy), 5e-3);
  // loose contracts (e only decreases from e0 = 0.70), dense dilates past its start
  EXPECT_LT(loose.void_ratio, 0.70 - 0.05);
  EXPECT_GT(dense.void_ratio, 0.55 + 0.03);
}

TEST(ForceChainsCriticalState, DilatancyIsIndependentOfTheLodeAngle) {
  const fc::ForceChainModel model{fc::ForceChainParameters{}};
  const auto& cs = model.critical_state();
  const double mc = model.parameters().M_c;
  for (double e : {0.55, 0.62, 0.70}) {
    for (double normalized : {0.3, 0.9, mc, 1.5}) {
      const double p = 80e3;
      // same η̃, e, p at θ = 0 (compression), θ = π/6 (shear) and θ = π/3 (extension)
      double d_ref = 0.0;
      for (double theta : {0.0, M_PI / 6, M_PI / 3}) {
        const double q = normalized / mc * cs.stress_ratio(std::cos(3 * theta)) * p;
        const Eigen::Matrix3d s = diag(p + 2.0 / 3.0 * q * std::cos(theta),
                                       p + 2.0 / 3.0 * q * std::cos(theta - 2 * M_PI / 3),
                                       p + 2.0 / 3.0 * q * std::cos(theta + 2 * M_PI / 3));
        ASSERT_NEAR(cs.normalized_stress_ratio(s), normalized, 1e-10);
        const double d = model.dilatancy(s, e);
        // from the flow direction itself: D = tr(m)/ε_q(m) (independent path through m)
        fc::ForceChainState st;
        st.stress = s;
        st.r_c = 10 * p;
        st.void_ratio = e;
        const Eigen::Matrix3d m = model.flow_direction(st);
        EXPECT_NEAR(m.trace() / fc::deviatoric_strain(m), d, 1e-9 * (1 + std::abs(d)));
        if (theta == 0.0) d_ref = d;
        EXPECT_NEAR(d, d_ref, 1e-12 * (1 + std::abs(d))) << e << " " << normalized << " " << theta;
      }
      // zero exactly at the critical state (η̃ = M_c, ψ = 0)
    }
  }
  const double p = 120e3;
  const Eigen::Matrix3d at_cs = diag(p + 2.0 / 3.0 * mc * p, p - mc * p / 3, p - mc * p / 3);
  EXPECT_NEAR(model.dilatancy(at_cs, model.critical_state().critical_void_ratio(p)), 0.0, 1e-12);
}

TEST(ForceChainsCriticalState, ExtensionReachesLadeDuncanExtensionRatio) {
  // axial unloading at constant radial stress: triaxial extension, cos3θ = -1
  const fc::ForceChainModel model{fc::ForceChainParameters{}};
  const auto r = drained(model, 0.62, -2.0, 2000);
  const double me = model.critical_state().stress_ratio(-1.0);
  std::printf("extension: q/p=%.4f (M_e=%.4f) e=%.4f e_cs=%.4f D=%.2e\n", r.stress_ratio, me,
              r.void_ratio, r.critical_void_ratio, r.dilatancy);
  EXPECT_NEAR(-r.stress_ratio, me, 5e-3 * me);  // same tolerance as in compression
  EXPECT_NEAR(r.void_ratio, r.critical_void_ratio, 2e-3);
  EXPECT_LT(std::abs(r.dilatancy), 5e-3);
}
