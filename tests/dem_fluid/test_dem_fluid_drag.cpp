// A free sphere in a Lees-Edwards box (fix deform xy erate γ̇ remap v), initially at rest, relaxes
// to the fluid velocity u_x = γ̇ (y - ylo) and to the fluid spin Ω_z = -γ̇/2:
//   v_x(t) = u_x (1 - exp(-t c_p / m)),   ω_z(t) = Ω_z (1 - exp(-t π η d³ / I)),
// with c_p = 3π η d (1-ν) F(ν) (seed Eq. 26 / van der Hoef et al. 2005, written out here
// independently of continuum/model) at the box solid fraction ν, and I = m d²/10.
// The box is small (1.5 d) so that ν = 0.155 and the correlation's correction, (1-ν)F(ν) = 2.8,
// is far from Stokes' 1: using Stokes drag instead would fail the test by a wide margin.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "dem_fluid_harness.hpp"

namespace granflow::dem::test {
namespace {

constexpr double pi = std::numbers::pi;
constexpr double diameter = 1e-3, density = 2500.0, viscosity = 0.01;
constexpr double box = 1.5e-3, y_particle = 1.2e-3, shear_rate = 100.0;
constexpr double dt = 1e-6;
constexpr long steps = 10000;  // t = 10 ms ≈ 2 τ

double van_der_hoef_factor(double nu) {  // F(ν) = 10ν/(1-ν)² + (1-ν)²(1 + 1.5 √ν)
  return 10.0 * nu / ((1.0 - nu) * (1.0 - nu)) +
         (1.0 - nu) * (1.0 - nu) * (1.0 + 1.5 * std::sqrt(nu));
}

TEST(DemFluidDrag, FreeSphereRelaxesToLeesEdwardsFluidVelocityAndSpin) {
  const std::string region = fmt::format(
      "region box prism 0 {L} 0 {L} 0 {L} 0 0 0 units box\ncreate_box 1 box", fmt::arg("L", box));
  const std::string deck =
      deck_preamble(region, dt) +
      fmt::format(R"(create_atoms    1 single 0.0004 {y} 0.00075 units box
set             group all diameter {d} density {rho}
velocity        all set 0 0 0
fix             integr all nve/sphere
fix             gf_shear all deform 1 xy erate {gd} remap v
fix             fl all fluid/le viscosity {eta} permeability seed_eq26 drag yes rotation yes lubrication 5e-5 1e-6
compute         w all property/atom omegaz
compute         wz all reduce sum c_w
variable        t equal time
variable        vx1 equal vx[1]
variable        vy1 equal vy[1]
variable        y1 equal y[1]
variable        wz1 equal c_wz
variable        nu equal f_fl[25]
variable        corr equal f_fl[26]
variable        gdot equal f_fl[31]
fix             out all print 500 "${{t}} ${{vx1}} ${{wz1}} ${{nu}} ${{corr}} ${{gdot}} ${{vy1}} ${{y1}}" file relax.txt screen no
run             {steps}
)",
                  fmt::arg("y", y_particle), fmt::arg("d", diameter), fmt::arg("rho", density),
                  fmt::arg("gd", shear_rate), fmt::arg("eta", viscosity), fmt::arg("steps", steps));
  const auto dir = test_dir("drag_relaxation");
  const RunResult r = run_deck(dir, deck, 1);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto rows = read_table(dir / "relax.txt");
  ASSERT_GE(rows.size(), 19u);

  const double mass = density * pi / 6.0 * diameter * diameter * diameter;
  const double nu = (pi / 6.0 * diameter * diameter * diameter) / (box * box * box);
  const double correction = (1.0 - nu) * van_der_hoef_factor(nu);
  const double drag = 3.0 * pi * viscosity * diameter * correction;
  const double tau = mass / drag;
  const double tau_spin =
      (0.1 * mass * diameter * diameter) / (pi * viscosity * diameter * diameter * diameter);
  const double u = shear_rate * y_particle;  // ylo = 0
  const double spin = -0.5 * shear_rate;
  EXPECT_GT(correction, 2.5);  // the dense-suspension correction is really exercised

  for (const auto& row : rows) {
    const double t = row[0];
    // ν and c_p/(3πηd) are reported exactly as computed here (same closed form, rounding only).
    EXPECT_NEAR(row[3], nu, 1e-12);
    EXPECT_NEAR(row[4] / correction, 1.0, 1e-12);
    EXPECT_NEAR(row[5], shear_rate, 1e-9 * shear_rate);
    EXPECT_EQ(row[6], 0.0);                  // no force across the flow
    EXPECT_NEAR(row[7], y_particle, 1e-15);  // so y (hence u) stays fixed
    // Velocity Verlet applies the drag with the half-step velocity: a forward-Euler relaxation
    // whose rate is off by O(dt/τ) = 2e-4 relative (τ = 5e-3 s); 1e-3 of the fluid velocity
    // bounds the resulting error at any t.
    EXPECT_NEAR(row[1], u * (1.0 - std::exp(-t / tau)), 1e-3 * u) << "t = " << t;
    EXPECT_NEAR(row[2], spin * (1.0 - std::exp(-t / tau_spin)), 1e-3 * std::abs(spin))
        << "t = " << t;
  }
  // Stokes drag (no correction) would be 2.8 times slower: at t = τ it would give 0.30 u, not
  // 0.63 u. Check the middle of the run discriminates.
  const auto& mid = rows[rows.size() / 2];
  const double stokes = u * (1.0 - std::exp(-mid[0] * drag / correction / mass));
  EXPECT_GT(std::abs(mid[1] - stokes), 0.1 * u);
}

}  // namespace
}  // namespace granflow::dem::test
