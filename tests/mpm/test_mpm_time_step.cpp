// Time-step control: the critical step of each mechanism against its closed form, the effect of
// mass scaling (√s on the wave limit) and of the drag integration (the drag limit only applies
// to explicit drag).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "continuum/mpm/problems.hpp"

using namespace granflow::mpm;

TEST(MpmTimeStep, WaveLimitIsTheUndrainedPWaveOfTheMixture) {
  TerzaghiSpec t;  // h = 0.1, M = E (ν = 0), n = 0.3, K_w = 1e8, at rest
  t.options.threads = 1;
  auto s = make_terzaghi(t);
  const double M = t.young_modulus, n = t.porosity;
  const double rho = (1 - n) * t.grain_density + n * t.liquid_density;
  const double c_undrained = std::sqrt((M + t.bulk_modulus / n) / rho);
  // Fastest of: undrained mixture wave, drained skeleton wave, sound in the liquid.
  const double c = std::max({c_undrained, std::sqrt(M / ((1 - n) * t.grain_density)),
                             std::sqrt(t.bulk_modulus / t.liquid_density)});
  EXPECT_NEAR(s->limits().wave, t.cell / c, 1e-12 * t.cell / c);         // closed form, round-off
  EXPECT_EQ(s->limits().drag, std::numeric_limits<double>::infinity());  // semi-implicit drag
  EXPECT_NEAR(s->dt(), 0.5 * s->limits().critical(), 1e-15);

  TerzaghiSpec scaled = t;
  scaled.options.mass_scaling = 4.0;
  auto ss = make_terzaghi(scaled);
  EXPECT_NEAR(ss->limits().wave, 2.0 * s->limits().wave, 1e-12);  // c ∝ 1/√s

  TerzaghiSpec expl = t;
  expl.options.drag_integration = DragIntegration::explicit_euler;
  auto se = make_terzaghi(expl);
  const double beta = n * n * t.liquid_density * 9.81 / t.hydraulic_conductivity;
  const double drag = 2.0 / (beta * (1 / (n * t.liquid_density) + 1 / ((1 - n) * t.grain_density)));
  EXPECT_NEAR(se->limits().drag, drag, 1e-9 * drag);
}

TEST(MpmTimeStep, ViscousLimitOfTheLiquid) {
  CouetteSpec c;
  c.options.threads = 1;
  auto s = make_couette(c);
  const auto& g = std::get<PolarGrid>(s->grid());
  const double h = g.min_spacing();
  EXPECT_NEAR(s->limits().viscous, 0.25 * h * h * c.density / c.viscosity, 1e-12);
}
