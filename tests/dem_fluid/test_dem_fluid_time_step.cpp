// Pure tests of the fluid time-step limits (dem_coupling/fixes/fluid_time_step.hpp) and the
// lubrication resistances (lubrication.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "dem_coupling/fixes/fluid_time_step.hpp"
#include "dem_coupling/fixes/lubrication.hpp"

namespace granflow::dem {
namespace {

constexpr double pi = std::numbers::pi;

FluidTimeStepInput reference() {
  FluidTimeStepInput in;
  in.fluid.liquid.viscosity = 0.01;
  in.fluid.minimum_gap = 1e-6;
  in.fluid.maximum_gap = 5e-5;
  in.particle_density = 2500.0;
  in.smallest_radius = in.largest_radius = 5e-4;
  in.solid_fraction = 0.0;
  in.contact_time = 4e-5;
  return in;
}

TEST(DemFluidTimeStep, ClosedFormsForEqualSpheresInTheDiluteLimit) {
  const FluidTimeStepInput in = reference();
  const FluidTimeScales t = fluid_time_scales(in);
  const double d = 1e-3, r = 5e-4, eta = 0.01, rho = 2500.0;
  const double m = rho * pi / 6.0 * d * d * d;
  // Stokes: m / (3π η d) = ρ d² / (18 η)
  EXPECT_NEAR(t.drag / (rho * d * d / (18.0 * eta)), 1.0, 1e-12);
  // rotation: (m d²/10) / (π η d³) = ρ d² / (60 η)
  EXPECT_NEAR(t.rotational_drag / (rho * d * d / (60.0 * eta)), 1.0, 1e-12);
  // normal lubrication: (m/2) h_min / (6π η (r/2)²); the study's 5.5e-5 s for these numbers
  EXPECT_NEAR(t.normal_lubrication / (0.5 * m * 1e-6 / (6.0 * pi * eta * 0.25 * r * r)), 1.0,
              1e-12);
  EXPECT_NEAR(t.normal_lubrication, 5.5e-5, 0.1e-5);  // the study rounded to 2 digits
  // tangential: 1/m_t = 2 (1/m + r²/(0.4 m r²)) = 7/m; c_t = π η R ln(R/h_min) (Ball & Melrose)
  EXPECT_NEAR(t.tangential_lubrication / ((m / 7.0) / (pi * eta * r * std::log(r / 1e-6))), 1.0,
              1e-12);
  EXPECT_EQ(t.contact, 4e-5);
}

TEST(DemFluidTimeStep, LubricationResistancesMatchPublishedEqualSphereForms) {
  const double eta = 0.3, R = 2e-4, h = 3e-6;
  // Ball & Melrose 1997 / LAMMPS pair lubricate (equal spheres, radius R):
  // normal 6π η R (1/(4ξ)) = 6π η R²/(4h), tangential 6π η R (1/6) ln(1/ξ), ξ = h/R.
  EXPECT_NEAR(normal_lubrication_resistance(eta, R, R, h, 1e-9) / (6 * pi * eta * R * R / (4 * h)),
              1.0, 1e-12);
  EXPECT_NEAR(
      tangential_lubrication_resistance(eta, R, R, h, 1e-9) / (pi * eta * R * std::log(R / h)), 1.0,
      1e-12);
  // unequal spheres: the prefactor equals LAMMPS lubricate/poly's 6π η r_i 4β(2+β+2β²)/(15(1+β)³)
  const double ri = 1e-4, rj = 3e-4, beta = rj / ri;
  const double lammps =
      6 * pi * eta * ri * 4 * beta * (2 + beta + 2 * beta * beta) / (15 * std::pow(1 + beta, 3));
  const double xi = 2 * h / (ri + rj);
  EXPECT_NEAR(tangential_lubrication_resistance(eta, ri, rj, h, 1e-9) / (lammps * std::log(1 / xi)),
              1.0, 1e-12);
  // symmetric in i, j (Newton's third law for the pair)
  EXPECT_DOUBLE_EQ(tangential_lubrication_resistance(eta, ri, rj, h, 1e-9),
                   tangential_lubrication_resistance(eta, rj, ri, h, 1e-9));
  // the fused pair evaluation of the fix's loop gives the same resistances
  const PairLubrication fused = pair_lubrication(eta, ri, rj, h, 1e-9, true);
  EXPECT_NEAR(fused.normal / normal_lubrication_resistance(eta, ri, rj, h, 1e-9), 1.0, 1e-14);
  EXPECT_NEAR(fused.tangential / tangential_lubrication_resistance(eta, ri, rj, h, 1e-9), 1.0,
              1e-14);
  EXPECT_EQ(pair_lubrication(eta, ri, rj, h, 1e-9, false).tangential, 0.0);
  // held at h_min below it and for overlaps
  EXPECT_DOUBLE_EQ(normal_lubrication_resistance(eta, ri, rj, -1e-6, 2e-6),
                   normal_lubrication_resistance(eta, ri, rj, 2e-6, 2e-6));
}

TEST(DemFluidTimeStep, DragUsesTheContinuumCorrelationAtTheSolidFraction) {
  FluidTimeStepInput in = reference();
  const double dilute = fluid_time_scales(in).drag;
  in.solid_fraction = 0.55;
  const double dense = fluid_time_scales(in).drag;
  // (1-ν) F(ν) at 0.55: F = 10ν/(1-ν)² + (1-ν)²(1+1.5√ν) (van der Hoef et al. 2005)
  const double nu = 0.55;
  const double F =
      10 * nu / ((1 - nu) * (1 - nu)) + (1 - nu) * (1 - nu) * (1 + 1.5 * std::sqrt(nu));
  EXPECT_NEAR(dilute / dense, (1 - nu) * F, 1e-9 * (1 - nu) * F);
}

TEST(DemFluidTimeStep, ParticleDragIsProportionalToDiameterForEveryCorrelation) {
  // fix fluid/le evaluates c_p(1 m, ν) once per step and scales it by d; this holds because
  // every permeability option is κ = d² f(ν).
  for (const std::string& name : model::permeability_names()) {
    model::LiquidParameters liquid;
    liquid.viscosity = 0.02;
    liquid.permeability = model::parse_permeability(name);
    for (double nu : {0.05, 0.3, 0.58})
      for (double d : {2e-4, 1e-3, 3.7e-3})
        EXPECT_NEAR(model::particle_drag_coefficient(liquid, d, nu) /
                        (d * model::particle_drag_coefficient(liquid, 1.0, nu)),
                    1.0, 1e-14)
            << name << " nu " << nu << " d " << d;
  }
}

TEST(DemFluidTimeStep, SizeRangeTakesTheShortestPair) {
  FluidTimeStepInput in = reference();
  in.smallest_radius = 4.5e-4;
  in.largest_radius = 5.5e-4;
  const FluidTimeScales t = fluid_time_scales(in);
  // brute force over a grid of pairs in the size range: none is shorter than the reported one
  for (int a = 0; a <= 20; ++a)
    for (int b = 0; b <= 20; ++b) {
      FluidTimeStepInput one = in;
      const double ri = 4.5e-4 + a * 0.05e-4, rj = 4.5e-4 + b * 0.05e-4;
      // a "pair" (ri, rj) as a two-size range evaluates the corners (ri,ri), (ri,rj), (rj,rj)
      one.smallest_radius = std::min(ri, rj);
      one.largest_radius = std::max(ri, rj);
      const FluidTimeScales s = fluid_time_scales(one);
      EXPECT_GE(s.normal_lubrication, t.normal_lubrication * (1 - 1e-12));
      EXPECT_GE(s.tangential_lubrication, t.tangential_lubrication * (1 - 1e-12));
    }
  // the drag and the rotation are shortest for the smallest sphere
  FluidTimeStepInput small = in;
  small.largest_radius = small.smallest_radius;
  EXPECT_DOUBLE_EQ(fluid_time_scales(small).drag, t.drag);
}

TEST(DemFluidTimeStep, StableStepAndRefusalNameTheLimit) {
  FluidTimeStepInput in = reference();
  FluidTimeScales t = fluid_time_scales(in);
  // η = 0.01: contact 0.1 × 4e-5 = 4e-6 s is the smallest (τ_r = 1.67e-3 s, τ_n = 5.5e-5 s)
  FluidTimeStep step = stable_fluid_time_step(t);
  EXPECT_EQ(step.limited_by, "contact");
  EXPECT_DOUBLE_EQ(step.dt, 4e-6);
  EXPECT_EQ(check_fluid_time_step(4e-6, t), "");
  // the study's warning: η = 0.1 makes τ_n = 5.5e-6 s, about 1.4 dt at dt = 4e-6 s ... still below
  in.fluid.liquid.viscosity = 0.1;
  t = fluid_time_scales(in);
  step = stable_fluid_time_step(t);
  EXPECT_EQ(step.limited_by, "normal lubrication");
  EXPECT_DOUBLE_EQ(step.dt, 0.2 * t.normal_lubrication);
  EXPECT_EQ(check_fluid_time_step(t.normal_lubrication, t), "");
  const std::string refusal = check_fluid_time_step(1.01 * t.normal_lubrication, t);
  EXPECT_NE(refusal.find("normal lubrication"), std::string::npos) << refusal;
  EXPECT_NE(refusal.find("m_eff h_min / (6 pi eta a^2)"), std::string::npos) << refusal;
  // a step too large for several limits names the most restrictive one it exceeds
  const std::string worst = check_fluid_time_step(1.0, t);
  EXPECT_NE(worst.find("exceeds the normal lubrication limit"), std::string::npos) << worst;
  // contact: refused above 0.2 t_contact
  in.fluid.liquid.viscosity = 1e-4;
  t = fluid_time_scales(in);
  EXPECT_EQ(check_fluid_time_step(0.2 * 4e-5, t), "");
  EXPECT_NE(check_fluid_time_step(0.21 * 4e-5, t).find("contact"), std::string::npos);
  // forces switched off do not limit
  in.fluid.lubrication = in.fluid.drag = in.fluid.rotational_drag = false;
  in.contact_time = std::numeric_limits<double>::infinity();
  t = fluid_time_scales(in);
  EXPECT_EQ(check_fluid_time_step(1e3, t), "");
  EXPECT_TRUE(std::isinf(stable_fluid_time_step(t).dt));
}

TEST(DemFluidTimeStep, PairLoopTermsEqualTheReferenceResistances) {
  // The fix's pair loop (pair_lubrication_terms: one division for 1/r, 1/(r_i + r_j), 1/g and the
  // size factor as 2 - 3a/(r_i + r_j)) against the reference pair_lubrication, over unequal
  // radii, gaps below h_min, inside (h_min, h_max) and overlaps (h < 0). Both are the same
  // formula rounded differently; the gap r - r_i - r_j itself is known to a few ulp of r, i.e. to
  // 4 ε r / max(h, h_min) relative (2e-12 for r = 2 mm, h = 1 µm), plus 1e-14 for the rest.
  const double eta = 0.01, h_min = 1e-6;
  const double radii[][2] = {{4.5e-4, 4.5e-4}, {4.5e-4, 5.5e-4}, {1e-4, 3e-4}, {2e-3, 1e-4}};
  const double gaps[] = {-2e-6, 0.0, 5e-7, 1e-6, 3e-6, 2e-5, 4.9e-5};
  for (const auto& r : radii)
    for (const double h : gaps) {
      const double distance = r[0] + r[1] + h;
      const PairLubricationTerms t = pair_lubrication_terms(eta, r[0], r[1], distance, h_min);
      const PairLubrication ref =
          pair_lubrication(eta, r[0], r[1], distance - r[0] - r[1], h_min, true);
      const double tolerance =
          1e-14 + 4.0 * std::numeric_limits<double>::epsilon() * distance / std::max(h, h_min);
      EXPECT_NEAR(t.inverse_distance * distance, 1.0, 1e-15);
      EXPECT_NEAR(t.normal / ref.normal, 1.0, tolerance) << r[0] << " " << r[1] << " " << h;
      EXPECT_NEAR(t.tangential_prefactor * std::log(t.log_argument) / ref.tangential, 1.0,
                  tolerance)
          << r[0] << " " << r[1] << " " << h;
      // symmetric in i, j (action-reaction)
      const PairLubricationTerms s = pair_lubrication_terms(eta, r[1], r[0], distance, h_min);
      EXPECT_NEAR(s.normal / t.normal, 1.0, 1e-15);
      EXPECT_NEAR(s.tangential_prefactor / t.tangential_prefactor, 1.0, 1e-15);
    }
}

}  // namespace
}  // namespace granflow::dem
