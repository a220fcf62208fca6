// Conservation: the mass of each phase is carried by its points (exactly constant), the nodal
// masses add up to it (partition of unity), and the total momentum of both phases changes only by
// the external impulse (internal, pressure and drag forces cancel in the sum), for a free
// two-phase block with non-uniform stress, pressure and relative velocity. Also: the OpenMP
// parallel maps give the single-thread result to round-off, deterministically.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "continuum/mpm/linear_elastic.hpp"
#include "continuum/mpm/setup.hpp"
#include "continuum/mpm/solver.hpp"
#include "tests/mpm/two_phase_block.hpp"

using namespace granflow::mpm;

namespace {
std::unique_ptr<Solver> free_block(DragIntegration drag, UpdateScheme scheme, double gravity,
                                   int threads, ShapeKind shape = ShapeKind::linear) {
  SolverOptions o;
  o.threads = threads;
  o.drag_integration = drag;
  o.scheme = scheme;
  o.gravity_y = -gravity;
  o.flip = 0.95;
  o.shape = shape;
  o.gimp_half_length_x = o.gimp_half_length_y = 0.025;
  auto s = granflow::mpm::testing::two_phase_block(o);
  const SolidPoints& sp = s->solid();
  LiquidPoints& lp = s->liquid();
  for (std::size_t p = 0; p < lp.size(); ++p) lp.vx[p] = -0.3 * sp.vy[p];
  s->initialize();
  return s;
}

double momentum_y(const Solver& s) {
  double a, b, c, d;
  s.total_momentum(Phase::solid, a, b);
  s.total_momentum(Phase::liquid, c, d);
  return b + d;
}
double momentum_x(const Solver& s) {
  double a, b, c, d;
  s.total_momentum(Phase::solid, a, b);
  s.total_momentum(Phase::liquid, c, d);
  return a + c;
}
}  // namespace

TEST(MpmConservation, MassPerPhaseIsExactAndNodalMassesAddUp) {
  auto s = free_block(DragIntegration::semi_implicit, UpdateScheme::musl, 9.81, 1);
  const double ms = s->total_mass(Phase::solid), ml = s->total_mass(Phase::liquid);
  s->run_steps(100);
  EXPECT_EQ(s->total_mass(Phase::solid), ms);  // exactly: point masses never change
  EXPECT_EQ(s->total_mass(Phase::liquid), ml);
  double nodal_s = 0, nodal_l = 0;
  for (int a = 0; a < s->grid_nodes(); ++a) {
    nodal_s += s->nodes().mass_solid[a];
    nodal_l += s->nodes().mass_liquid[a];
  }
  // Partition of unity: Σ_a Σ_p N_a(x_p) m_p = Σ_p m_p, to summation round-off.
  EXPECT_NEAR(nodal_s / ms, 1.0, 1e-12);
  EXPECT_NEAR(nodal_l / ml, 1.0, 1e-12);
}

TEST(MpmConservation, TotalMomentumChangesOnlyByGravity) {
  for (auto drag : {DragIntegration::semi_implicit, DragIntegration::explicit_euler}) {
    for (auto scheme : {UpdateScheme::musl, UpdateScheme::usl}) {
      for (double g : {0.0, 9.81}) {
        // USL takes the stress from the velocities of nearly empty edge nodes, the cell-crossing
        // weakness MUSL was made for (Sulsky et al. 1995): the falling block breaks up in USL.
        if (scheme == UpdateScheme::usl && g > 0) continue;
        auto s = free_block(drag, scheme, g, 1);
        const double M = s->total_mass(Phase::solid) + s->total_mass(Phase::liquid);
        const double px0 = momentum_x(*s), py0 = momentum_y(*s);
        double liquid_px0, dummy;
        s->total_momentum(Phase::liquid, liquid_px0, dummy);
        s->run_steps(200);
        // Round-off scale: the momentum of the initial motion, |P| ~ M x 0.2 m/s, x 1e-12.
        const double tol = 1e-12 * M * 0.2 * 200;
        EXPECT_NEAR(momentum_x(*s), px0, tol);
        EXPECT_NEAR(momentum_y(*s), py0 - M * g * s->time(), tol);
        // The phases did exchange momentum (drag, buoyancy): the test is not trivial.
        double liquid_px, unused;
        s->total_momentum(Phase::liquid, liquid_px, unused);
        EXPECT_GT(std::fabs(liquid_px - liquid_px0), 1e3 * tol);
      }
    }
  }
}

TEST(MpmConservation, GimpConservesMomentumToo) {
  auto s = free_block(DragIntegration::semi_implicit, UpdateScheme::musl, 9.81, 1, ShapeKind::gimp);
  const double M = s->total_mass(Phase::solid) + s->total_mass(Phase::liquid);
  const double py0 = momentum_y(*s);
  s->run_steps(100);
  EXPECT_NEAR(momentum_y(*s), py0 - M * 9.81 * s->time(), 1e-12 * M * 0.2 * 100);
}

TEST(MpmConservation, TwoThreadsReproduceOneThread) {
  auto one = free_block(DragIntegration::semi_implicit, UpdateScheme::musl, 9.81, 1);
  auto two = free_block(DragIntegration::semi_implicit, UpdateScheme::musl, 9.81, 2);
  auto again = free_block(DragIntegration::semi_implicit, UpdateScheme::musl, 9.81, 2);
  one->run_steps(40);
  two->run_steps(40);
  again->run_steps(40);
  for (std::size_t p = 0; p < one->liquid().size(); ++p) {
    // Only the order of the nodal sums differs: agreement to round-off growth over 40 steps.
    EXPECT_NEAR(two->liquid().pressure[p], one->liquid().pressure[p], 1e-6);
    EXPECT_NEAR(two->solid().sxx[p], one->solid().sxx[p], 1e-6);
    // Same thread count: bit-for-bit (fixed chunking and fixed reduction order).
    EXPECT_EQ(again->liquid().pressure[p], two->liquid().pressure[p]);
    EXPECT_EQ(again->solid().x[p], two->solid().x[p]);
  }
}

TEST(MpmFailures, LostPointAndNonFiniteStressStopWithStepPointAndVariable) {
  auto s = free_block(DragIntegration::semi_implicit, UpdateScheme::musl, 0.0, 1);
  // Throw the whole block to the left: at 100 m/s it leaves the 2 m grid within ~30 steps.
  for (auto& v : s->solid().vx) v = -100.0;
  for (auto& v : s->liquid().vx) v = -100.0;
  try {
    s->run_steps(200);
    FAIL() << "a point that left the grid was not reported";
  } catch (const granflow::core::NumericalFailure& f) {
    EXPECT_GT(f.step, 0);
    EXPECT_NE(f.point.find("point"), std::string::npos) << f.what();
    EXPECT_EQ(f.variable, "position");
    EXPECT_NE(std::string(f.what()).find("lost point"), std::string::npos);
  }
  auto t = free_block(DragIntegration::semi_implicit, UpdateScheme::musl, 0.0, 1);
  t->solid().sxx[5] = std::numeric_limits<double>::quiet_NaN();
  try {
    t->run_steps(5);
    FAIL() << "a NaN stress was not reported";
  } catch (const granflow::core::NumericalFailure& f) {
    EXPECT_EQ(f.step, 1);
    EXPECT_NE(f.what(), std::string());
  }
}

TEST(MpmConservation, TwoPhaseAnnulusOnThePolarGridConservesMomentum) {
  // Double point on the O-grid: solid and liquid in the annulus between radial cells 2 and 6 of
  // 8, no walls, a translation plus a rotation and a non-uniform pressure; the total momentum
  // of both phases is kept to round-off (Σ_a ∇N_a = 0 on the isoparametric quads too).
  SolverOptions o;
  o.threads = 1;
  LiquidOptions l;
  l.bulk_modulus = 1e7;
  l.viscosity = 0.1;
  l.hydraulic_conductivity = 1e-4;
  const PolarGrid g(0.5, 1.3, 8, 48);
  Solver s(g, o, l);
  const int mat = s.add_material(std::make_unique<LinearElastic>(1e6, 0.25, 2650.0));
  add_solid_annulus(s, g, 2, 6, 2, 2, mat, 0.4);
  add_liquid_annulus(s, g, 2, 6, 2, 2, 0.4);
  for (std::size_t p = 0; p < s.solid().size(); ++p) {
    s.solid().vx[p] = 0.3 - 0.5 * s.solid().y[p];
    s.solid().vy[p] = 0.5 * s.solid().x[p];
    s.solid().sxx[p] = -2e3 * s.solid().x[p] * s.solid().x[p];
  }
  for (std::size_t p = 0; p < s.liquid().size(); ++p) {
    s.liquid().vy[p] = -0.2;
    s.liquid().pressure[p] = 1e3 * (1.0 + s.liquid().y[p]);
  }
  s.initialize();
  const double M = s.total_mass(Phase::solid) + s.total_mass(Phase::liquid);
  const double px0 = momentum_x(s), py0 = momentum_y(s);
  double lpx0, lpy0;
  s.total_momentum(Phase::liquid, lpx0, lpy0);
  s.run_steps(50);
  EXPECT_NEAR(momentum_x(s), px0, 1e-12 * M * 50);  // round-off scale M x 1 m/s x steps
  EXPECT_NEAR(momentum_y(s), py0, 1e-12 * M * 50);
  double lpx, lpy;
  s.total_momentum(Phase::liquid, lpx, lpy);
  EXPECT_GT(std::fabs(lpy - lpy0), 1e-6 * M);  // the phases exchanged momentum
}
