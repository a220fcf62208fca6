// Contact laws of the generated decks (material.contact_law), checked on a head-on collision of
// two equal spheres run by granflow-dem with the deck's own contact commands
// (contact_law_commands). Linear spring-dashpot (hooke): the closed form of m* x'' + γ_n x' +
// k_n x = 0 gives a velocity-independent restitution e = exp(-γ_n t_c/(2 m*)) and contact time
// t_c = π sqrt(m*/k_n) sqrt(1 + ln² e/π²) (contact_time.hpp; Schäfer, Dippel & Wolf 1996).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>

#include "dem_coupling/deck/contact_time.hpp"
#include "dem_coupling/deck/shear_deck.hpp"
#include "tests/dem/driver_runner.hpp"

namespace {

using granflow::dem::contact_law_commands;
using granflow::dem::ContactLaw;
using granflow::dem::DemMaterial;
using granflow::dem::linear_spring_contact_time;
using granflow::dem::testing::fresh_directory;
using granflow::dem::testing::run_driver;

constexpr double diameter = 1e-3, density = 2500.0;

double effective_mass() {
  return 0.5 * density * std::numbers::pi / 6.0 * diameter * diameter * diameter;
}

struct Collision {
  double restitution = 0;   // from the kinetic energy after / before
  double contact_time = 0;  // samples (one per step) with a contact × dt
  double momentum_x = 0;    // after
};

// Two 1 mm spheres 0.1 mm apart approach at ±v0 along x in a 12 mm box (no shear); the driver
// samples every step.
Collision collide(const std::string& name, const DemMaterial& m, double v0, double dt, long steps) {
  const auto dir = fresh_directory(name);
  std::ofstream(dir / "in.granflow")
      << granflow::dem::testing::driver_deck_header(steps, 1, density)
      << fmt::format(
             R"(region          box block 0 0.012 0 0.012 0 0.012 units box
create_box      1 box
neighbor        0.0002 bin
neigh_modify    delay 0
{contact}timestep        {dt:.17g}
create_atoms    1 single 0.00545 0.006 0.006 units box
create_atoms    1 single 0.00655 0.006 0.006 units box
set             group all diameter {d} density {rho}
group           left id 1
group           right id 2
velocity        left set {v0} 0 0 units box
velocity        right set -{v0} 0 0 units box
fix             integr all nve/sphere
compute         gf_virial all pressure thermo_temp virial
thermo_style    custom step atoms ke c_gf_virial[1]
thermo          0
)",
             fmt::arg("rho", density), fmt::arg("d", diameter),
             fmt::arg("contact", contact_law_commands(m, diameter)), fmt::arg("dt", dt),
             fmt::arg("v0", v0));
  const auto run = run_driver(dir);
  EXPECT_EQ(run.status, 0) << run.output;
  Collision c;
  if (run.series.rows() < 2) return c;
  const auto& temperature = run.series.at("T");
  const auto& contacts = run.series.at("Z");
  long in_contact = 0;
  for (double z : contacts) in_contact += z > 0.0;
  c.restitution = std::sqrt(temperature.back() / temperature.front());
  c.contact_time = double(in_contact) * dt;
  c.momentum_x = run.series.at("momentum_x").back();
  return c;
}

DemMaterial linear_spring(double restitution) {
  DemMaterial m;
  m.diameter = diameter;
  m.particle_density = density;
  m.restitution = restitution;
  m.contact_law = ContactLaw::hooke;
  m.normal_stiffness = 1000.0;  // k_n/(σ d) = 1e4 at σ = 100 Pa, d = 1 mm (the dry sweep's)
  return m;
}

TEST(DemContactLaw, LinearSpringDashpotGivesItsRestitutionAndContactTimeAtAnySpeed) {
  for (double restitution : {0.7, 0.9}) {
    const DemMaterial m = linear_spring(restitution);
    const double t_c =
        linear_spring_contact_time(effective_mass(), m.normal_stiffness, restitution);
    // dt = t_c/200: the contact time is counted in whole steps (±1 step = ±0.5 %; measured
    // -0.5 %) and velocity Verlet's error in the dashpot work is O(γ_n dt/m*) ≈ 2e-3 relative at
    // e = 0.7 (measured ≤ 0.26 %); hence 1 %.
    const double dt = t_c / 200.0;
    for (double v0 : {0.05, 0.2}) {  // approach 0.1 and 0.4 m/s: a linear spring has no speed
      const long steps = std::lround((0.1e-3 / (2.0 * v0) + 2.0 * t_c) / dt);  // gap + contact
      const Collision c = collide(fmt::format("hooke_e{}_v{}", restitution, v0), m, v0, dt, steps);
      EXPECT_NEAR(c.restitution, restitution, 0.01 * restitution) << "e " << restitution;
      EXPECT_NEAR(c.contact_time, t_c, 0.01 * t_c) << "e " << restitution << " v0 " << v0;
      // Equal and opposite contact forces: zero total momentum (round-off of 2 particles).
      EXPECT_NEAR(c.momentum_x, 0.0, 1e-15);
    }
  }
}

TEST(DemContactLaw, HertzContactTimeShortensWithImpactSpeedUnlikeTheLinearSpring) {
  // The second, independent path: the same collision with the Hertz law lasts
  // t_H ∝ v^(-1/5) (contact_time.hpp; Johnson 1985), so a 4× faster approach shortens it by
  // 4^(-1/5) = 0.758 (measured 0.7586). Tolerances: the contact is counted in steps (600 and
  // 450 of them: ±0.2 % each), hence 1 % on the ratio; the elastic t_H ignores the dashpot,
  // which lengthens the contact by ~1 % at e = 0.9 (measured +0.9 %), hence 3 %.
  DemMaterial m;
  m.diameter = diameter;
  m.particle_density = density;
  m.restitution = 0.9;
  const double dt = 2e-7;
  const auto slow = collide("hertz_slow", m, 0.05, dt, std::lround(1.5e-3 / dt));
  const auto fast = collide("hertz_fast", m, 0.2, dt, std::lround(0.5e-3 / dt));
  ASSERT_GT(slow.contact_time, 0.0);
  EXPECT_NEAR(fast.contact_time / slow.contact_time, std::pow(4.0, -0.2), 0.01);
  const double t_h = granflow::dem::hertz_contact_time(0.5 * diameter, density, m.youngs_modulus,
                                                       m.poisson_ratio, 0.1);
  EXPECT_NEAR(slow.contact_time / t_h, 1.0, 0.03);
}

}  // namespace
