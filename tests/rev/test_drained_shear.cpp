// REV simple shear drained at constant total normal stress with a step in the shear rate
// (rev/simple_shear.hpp: drainage_length, rate_step_*). The total normal stress p is shared by
// the grains' σ_yy and the excess pore pressure u = r ε̇_yy, r = η0 H² / κ(ν) (lumped Darcy flow
// over the drainage length H; compression positive). Checked:
//   * the steady state is path-independent and drained steady = the constant-pressure steady
//     state (ε̇_yy → 0, so u → 0): a run stepped from γ̇1 to γ̇2 ends where a run at γ̇2 alone ends;
//   * after a step up the point dilates (p_COL rises with γ̇ and unloads the skeleton, whose
//     critical state is looser at lower p'), the inflowing liquid is sucked in (u < 0), so the
//     grains carry more than p (σ_yy = p − u), and the dilation takes longer the longer the
//     drainage path (H² in r).
// The material: the DEM spheres of tests/rev/dem_sphere_settings.hpp in water.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "continuum/model/closures.hpp"
#include "continuum/rev/simple_shear.hpp"
#include "tests/rev/dem_sphere_settings.hpp"

using namespace granflow;

namespace {

constexpr double kNormalStress = 100.0;  // Pa, total
// I = γ̇ d / sqrt(p/ρ_p) = 0.005 γ̇: 0.01 before the step; 0.05 after it (the skeleton
// survives) or 0.2 (it fluidizes: p_COL alone carries p)
constexpr double kSlow = 2.0, kFast = 10.0, kFluidizing = 40.0, kStepStrain = 1.0;

continuum::MultiRegimeSettings wet_spheres() {
  continuum::MultiRegimeSettings s = granflow::testing::dem_sphere_settings();
  s.liquid = true;  // water: η0 = 1 mPa s (the liquid's defaults)
  return s;
}

rev::SimpleShearControl drained(double length) {
  rev::SimpleShearControl c;
  c.control = rev::ShearControl::constant_pressure;
  c.shear_rate = kSlow;
  c.normal_stress = kNormalStress;
  c.void_ratio = 0.78;  // loose: looser than e_cs(100 Pa) = 0.73
  c.drainage_length = length;
  c.rate_step_strain = kStepStrain;
  c.rate_step_shear_rate = kFast;
  c.steady_tolerance = 1e-6;  // per unit strain (as the constant-pressure REV tests)
  c.max_strain = 50;
  c.max_steps = 200000;
  return c;
}

// Strain after the rate step at which ν has covered half of its change from the step to the
// end of the run (-1: never).
double half_dilation_strain(const rev::SimpleShearSeries& s) {
  const auto at_step =
      std::find_if(s.strain.begin(), s.strain.end(), [](double g) { return g >= kStepStrain; });
  const std::size_t i0 = std::size_t(at_step - s.strain.begin());
  const double nu0 = s.solid_fraction[i0], half = 0.5 * (s.solid_fraction.back() + nu0);
  for (std::size_t i = i0; i < s.strain.size(); ++i)
    if (s.solid_fraction[i] <= half) return s.strain[i] - kStepStrain;
  return -1.0;
}

}  // namespace

TEST(DrainedShear, RateStepEndsOnTheSteadyStateOfTheNewRate) {
  const continuum::MultiRegimePoint point(wet_spheres());
  const auto stepped = rev::run_simple_shear(point, drained(0.01));
  rev::SimpleShearControl fast = drained(0.01);  // at the fast rate from the start
  fast.shear_rate = kFast;
  fast.rate_step_strain = INFINITY;
  const auto direct = rev::run_simple_shear(point, fast);
  const auto &a = stepped.steady, &b = direct.steady;
  std::printf("stepped: steady %d at strain %.3f (%ld steps); direct: steady %d at %.3f\n",
              a.reached, a.strain, stepped.steps, b.reached, b.strain);
  ASSERT_TRUE(a.reached && b.reached);
  ASSERT_FALSE(a.fluidized || b.fluidized);
  // the rate step landed on its strain, and the steady state is judged after it
  const auto& g = stepped.series.strain;
  EXPECT_TRUE(std::find(g.begin(), g.end(), kStepStrain) != g.end());
  EXPECT_GT(a.strain, kStepStrain);
  // Each run stops within ~3e-7 of its limit plus σ_FC's drift noise (as in
  // SimpleShearForceChainsPressure): 2e-5 on μ, 1e-6 on ν and T relative.
  std::printf("stepped: mu %.9f nu %.9f T %.9g; direct: mu %.9f nu %.9f T %.9g\n", a.friction,
              a.solid_fraction, a.granular_temperature, b.friction, b.solid_fraction,
              b.granular_temperature);
  EXPECT_NEAR(a.friction / b.friction, 1.0, 2e-5);
  EXPECT_NEAR(a.solid_fraction / b.solid_fraction, 1.0, 1e-6);
  EXPECT_NEAR(a.granular_temperature / b.granular_temperature, 1.0, 1e-6);
  // drained steady: the pore pressure has drained away, σ_yy = p
  EXPECT_NEAR(a.normal_stress / kNormalStress, 1.0, 1e-6);
}

TEST(DrainedShear, StepUpDilatesAgainstTheSuctionOfTheLiquid) {
  const continuum::MultiRegimePoint point(wet_spheres());
  const auto& liquid = point.settings().liquid_parameters;
  const double d = point.settings().collisional_parameters.diameter;
  double previous_half = 0.0;
  for (double length : {0.003, 0.01, 0.03}) {
    auto control = drained(length);
    control.rate_step_shear_rate = kFluidizing;
    control.max_strain = kStepStrain + 2.0;  // the transient only
    control.steady_tolerance = 0.0;
    const auto r = rev::run_simple_shear(point, control);
    const auto& s = r.series;
    double most_suction = 0.0, largest_excess = 0.0;
    for (std::size_t i = 0; i < s.strain.size(); ++i) {
      // the grains' σ_yy and u = r ε̇_yy (r at the step's start ν, so the row's ν is close
      // but not the same: 1e-3 of p covers it) share p
      const double r_now =
          liquid.viscosity * length * length / model::permeability(liquid, d, s.solid_fraction[i]);
      const double u = r_now * s.vertical_strain_rate[i];
      EXPECT_NEAR(s.normal_stress[i] + u, kNormalStress, 1e-3 * kNormalStress) << "row " << i;
      if (s.strain[i] > kStepStrain) {
        most_suction = std::min(most_suction, u);
        largest_excess = std::max(largest_excess, s.normal_stress[i] - kNormalStress);
      }
    }
    const double half = half_dilation_strain(s);
    const auto at_step = std::find(s.strain.begin(), s.strain.end(), kStepStrain);
    const double dilation = s.solid_fraction.back() - s.solid_fraction[at_step - s.strain.begin()];
    std::printf("H = %.3f m: dilation %.5f, half-dilation strain %.4f, largest suction %.4g Pa\n",
                length, dilation, half, most_suction);
    EXPECT_LT(dilation, -1e-3);      // the step up dilates
    EXPECT_LT(most_suction, 0.0);    // the liquid is sucked in ...
    EXPECT_GT(largest_excess, 0.0);  // ... so the grains carry more than p
    ASSERT_GT(half, 0.0);
    EXPECT_GT(half, previous_half);  // a longer drainage path delays the dilation
    previous_half = half;
  }
}

// A damped height (height_resistance R, no liquid): the same law with a constant r = R, a
// viscous piston on a dry point. Every row satisfies σ_yy + R ε̇_yy = p to the mixed control's
// tolerance (R exact here, unlike the drained r(ν) taken at the step's start), a step up dilates
// the point (u = R ε̇_yy < 0 while it does), and the run ends on the constant-pressure steady state
// of the new rate, as the drained one does.
TEST(DampedHeight, DryPointHoldsItsNormalStressThroughTheStep) {
  const continuum::MultiRegimePoint point(granflow::testing::dem_sphere_settings());
  auto control = drained(0.0);
  control.height_resistance = 100.0;  // Pa s: R/M ~ 1e-3 s against 1/γ̇ >= 0.1 s
  control.rate_step_shear_rate = kFast;
  const auto r = rev::run_simple_shear(point, control);
  const auto& s = r.series;
  ASSERT_TRUE(r.steady.reached);
  double most_suction = 0.0;
  for (std::size_t i = 0; i < s.strain.size(); ++i) {
    // the solver's tolerance is 1e-12 p; σ_yy and ε̇ are recomputed from the state: 1e-9 p
    EXPECT_NEAR(s.normal_stress[i] + 100.0 * s.vertical_strain_rate[i], kNormalStress,
                1e-9 * kNormalStress)
        << "row " << i;
    if (s.strain[i] > kStepStrain)
      most_suction = std::min(most_suction, 100.0 * s.vertical_strain_rate[i]);
  }
  EXPECT_LT(most_suction, 0.0);  // the step up dilates the point
  rev::SimpleShearControl fast = drained(0.0);
  fast.shear_rate = kFast;
  fast.rate_step_strain = INFINITY;
  const auto direct = rev::run_simple_shear(point, fast);
  ASSERT_TRUE(direct.steady.reached);
  // as RateStepEndsOnTheSteadyStateOfTheNewRate: 2e-5 on μ, 1e-6 on ν
  EXPECT_NEAR(r.steady.friction / direct.steady.friction, 1.0, 2e-5);
  EXPECT_NEAR(r.steady.solid_fraction / direct.steady.solid_fraction, 1.0, 1e-6);
}
