// The FLIP/PIC blend per unit time (SolverOptions::pic_relaxation_time, docs/mpm.md "FLIP/PIC
// blend"). Per step the point velocity becomes v ← f (v + Δt a) + (1 − f) v_PIC. For a point
// velocity field the grid does not see at all (its mass-weighted projection on every node is zero),
// a = 0 and v_PIC = 0, the points do not move, and the step is exactly v ← f v: after a time t the
// field is f^(t/Δt) v0. With a per-step fraction f fixed, that is exp(t ln f / Δt), a decay rate
// ∝ 1/Δt (the numerical viscosity of the PIC part grows as Δt shrinks, e.g. with a stiffer K_w).
// With f = exp(−Δt/t_PIC) it is exp(−t/t_PIC) for every Δt.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <stdexcept>

#include "continuum/mpm/linear_elastic.hpp"
#include "continuum/mpm/setup.hpp"
#include "continuum/mpm/solver.hpp"

using namespace granflow::mpm;

namespace {
constexpr double cell = 0.1;  // m
constexpr int cells_x = 6, cells_y = 2;

// A dry, nearly stress-free block (E = 1 Pa: no stress builds up over the test) filling the grid
// with `per_cell` × 3 points per cell, at rest, with a fixed Δt.
std::unique_ptr<Solver> block(double dt, double flip, double pic_time, int per_cell_x) {
  SolverOptions o;
  o.threads = 1;
  o.fixed_dt = dt;
  o.flip = flip;
  o.pic_relaxation_time = pic_time;
  auto s = std::make_unique<Solver>(CartesianGrid(0, 0, cell, cell, cells_x, cells_y), o);
  s->add_material(std::make_unique<LinearElastic>(1.0, 0.3, 2650.0));
  add_solid_rectangle(*s, {0, 0, cells_x * cell, cells_y * cell, per_cell_x * cells_x, 3 * cells_y},
                      0, 0.4);
  return s;
}

// Three points per cell in x at ξ = 1/6, 1/2, 5/6 with v_x ∝ (1, −2, 1): the linear shape
// functions of the cell's two x-nodes weigh them (5/6, 1/2, 1/6) and (1/6, 1/2, 5/6), and both
// weighted sums vanish, so every node gets zero momentum (the field lies in the null space of the
// point-to-grid map) while its energy is carried by the points.
std::unique_ptr<Solver> null_mode(double dt, double flip, double pic_time) {
  auto s = block(dt, flip, pic_time, 3);
  SolidPoints& sp = s->solid();
  for (std::size_t p = 0; p < sp.size(); ++p) {
    const int k = static_cast<int>(std::floor(sp.x[p] / (cell / 3.0)));  // sub-cell column
    sp.vx[p] = k % 3 == 1 ? -2.0 : 1.0;
  }
  s->initialize();
  return s;
}

double rms_vx(const Solver& s) {
  double sum = 0;
  for (double v : s.solid().vx) sum += v * v;
  return std::sqrt(sum / static_cast<double>(s.solid().size()));
}

// rms v_x after `time` from the null mode (rms 2^½ at t = 0), relative to the start.
double decay(double dt, double flip, double pic_time, double time) {
  auto s = null_mode(dt, flip, pic_time);
  const double v0 = rms_vx(*s);
  const long steps = std::lround(time / dt);
  s->run_steps(steps);
  EXPECT_NEAR(s->time(), time, 1e-12);
  // The grid never sees the mode: nodal velocities are zero up to the round-off of the
  // 9-term sums of O(1) momenta (1e-17 measured; 1e-14 leaves room for other compilers).
  for (double x : s->nodes().vx_solid) EXPECT_NEAR(x, 0.0, 1e-14);
  return rms_vx(*s) / v0;
}
}  // namespace

TEST(MpmPicRelaxation, NullModeDecaysAsExpOfTimeOverTpicForAnyTimeStep) {
  const double t_pic = 2e-3, time = 4e-3;  // 2 relaxation times
  for (double dt : {1e-5, 4e-5}) {
    // exp(−Δt/t_PIC)^(t/Δt) = exp(−t/t_PIC): equal for both Δt, to the round-off of 100-400
    // products.
    EXPECT_NEAR(decay(dt, 1.0, t_pic, time), std::exp(-time / t_pic), 1e-12) << "dt " << dt;
  }
}

TEST(MpmPicRelaxation, PerStepFractionDecaysAtARateProportionalToOneOverTimeStep) {
  // The per-step fraction that equals t_PIC = 2 ms at Δt = 10 µs, used at 10 and 40 µs: over the
  // same 4 ms the mode decays by f^400 = e^-2 and by f^100 = e^-0.5 (a quarter of the rate).
  const double f = std::exp(-1e-5 / 2e-3), time = 4e-3;
  EXPECT_NEAR(decay(1e-5, f, 0.0, time), std::exp(-2.0), 1e-12);
  EXPECT_NEAR(decay(4e-5, f, 0.0, time), std::exp(-0.5), 1e-12);
}

TEST(MpmPicRelaxation, ResolvedShearModeDecaysAtTheSameRatePerUnitTime) {
  // A shear mode the grid does resolve, v_x = A sin(2π y / λ) across 2 cells, 2 × 3 points per
  // cell: PIC relaxes only its part that the grid cannot represent, at a rate (1 − s)/t_PIC with s
  // the grid's reproduction factor of the mode (< 1). The amplitude is tiny (1e-9 m/s: the points
  // move ~1e-12 of a cell, so the maps stay those of t = 0 and the step is linear). Then per step
  // v ← [f + (1 − f) s] v and over a time t the factor is exp(−(1 − s) t/t_PIC) (1 + O(Δt/t_PIC)).
  const double t_pic = 1e-3, time = 1e-3;
  auto run = [&](double dt, double flip, double pic_time) {
    auto s = block(dt, flip, pic_time, 2);
    SolidPoints& sp = s->solid();
    const double lambda = cells_y * cell;
    for (std::size_t p = 0; p < sp.size(); ++p)
      sp.vx[p] = 1e-9 * std::sin(2.0 * M_PI * sp.y[p] / lambda);
    s->initialize();
    const double v0 = rms_vx(*s);
    s->run_steps(std::lround(time / dt));
    return rms_vx(*s) / v0;
  };
  const double fine = run(1e-5, 1.0, t_pic), coarse = run(4e-5, 1.0, t_pic);
  // It decays (the grid does not reproduce the mode exactly) but more slowly than the null mode.
  EXPECT_LT(fine, 0.999);
  EXPECT_GT(fine, std::exp(-time / t_pic));
  // Same decay for Δt = 10 and 40 µs: the log-decay agrees to O(Δt/t_PIC) = 4 % of itself.
  EXPECT_NEAR(std::log(coarse) / std::log(fine), 1.0, 0.04);
  // The per-step fraction of t_PIC at 10 µs, used at 40 µs: about a quarter of the log-decay, the
  // dependence on Δt that t_PIC removes. Not exactly 1/4: the sine is a mixture of the grid's
  // eigenmodes, which decay at different rates, and the rms mixes them (measured 0.277).
  const double f = std::exp(-1e-5 / t_pic);
  const double per_step_coarse = run(4e-5, f, 0.0);
  EXPECT_NEAR(std::log(per_step_coarse) / std::log(fine), 0.25, 0.05);
}

TEST(MpmPicRelaxation, FlipAndRelaxationTimeAreExclusive) {
  SolverOptions o;
  o.flip = 0.99;
  o.pic_relaxation_time = 1e-3;
  EXPECT_THROW(Solver(CartesianGrid(0, 0, cell, cell, 2, 2), o), std::invalid_argument);
  o.flip = 1.0;
  o.pic_relaxation_time = -1.0;
  EXPECT_THROW(Solver(CartesianGrid(0, 0, cell, cell, 2, 2), o), std::invalid_argument);
}
