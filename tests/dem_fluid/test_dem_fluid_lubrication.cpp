// Two equal spheres pushed together by a constant force F0 in a liquid of viscosity η, with
// normal lubrication only (fix fluid/le ... drag no rotation no, tangential lubrication acts only
// on sliding and stays zero here). Reynolds' squeeze law F0 = 6π η a² (-dh/dt) / h gives
//   h(t) = h0 exp(-k t),  k = F0 / (6π η a²)   (a = R/2, inertia neglected).
// With the sphere masses, m_eff dV/dt = F0 - 6π η a² V / h, V = -dh/dt, m_eff = m/2; this ODE is
// integrated independently (RK4) and the driver's gap history must follow it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "dem_fluid_harness.hpp"

namespace granflow::dem::test {
namespace {

constexpr double pi = std::numbers::pi;
constexpr double diameter = 1e-3, density = 2500.0, viscosity = 10.0;
constexpr double h0 = 1e-4, h_min = 2e-6, h_max = 2e-4;
constexpr double reduced_radius = 0.25 * diameter;
constexpr double squeeze = 6.0 * pi * viscosity * reduced_radius * reduced_radius;  // N s
constexpr double rate = 500.0;                                                      // k, 1/s
constexpr double force = rate * squeeze;                                            // F0, N
constexpr double dt = 5e-8;    // s; τ_n(h_min) = m_eff h_min / (6π η a²) = 1.1e-7 s
constexpr long steps = 92000;  // t = 4.6 ms = ln(10)/k: the gap closes from h0 to ~h0/10

std::string reynolds_deck(bool two_ranks, double time_step = dt) {
  const double x1 = 0.005 - 0.5 * (diameter + h0), x2 = 0.005 + 0.5 * (diameter + h0);
  std::string box = two_ranks ? "processors 2 1 1\n" : "";  // x split at 0.005: one sphere each
  box += "region box block 0 0.01 0 0.01 0 0.01 units box\ncreate_box 1 box";
  return deck_preamble(box, time_step) +
         fmt::format(R"(create_atoms    1 single {x1:.17g} 0.005 0.005 units box
create_atoms    1 single {x2:.17g} 0.005 0.005 units box
set             group all diameter {d} density {rho}
group           a id 1
group           b id 2
velocity        a set {v:.17g} 0 0
velocity        b set {mv:.17g} 0 0
fix             integr all nve/sphere
fix             fl all fluid/le viscosity {eta} permeability seed_eq26 drag no rotation no lubrication {hmax} {hmin}
fix             fa a addforce {f:.17g} 0 0
fix             fb b addforce {mf:.17g} 0 0
variable        gap equal x[2]-x[1]-{d}
variable        t equal time
variable        pairs equal f_fl[27]
fix             out all print 4000 "${{t}} ${{gap}} ${{pairs}}" file gap.txt screen no
run             {steps}
)",
                     fmt::arg("x1", x1), fmt::arg("x2", x2), fmt::arg("d", diameter),
                     fmt::arg("rho", density), fmt::arg("v", 0.5 * rate * h0),
                     fmt::arg("mv", -0.5 * rate * h0), fmt::arg("eta", viscosity),
                     fmt::arg("hmax", h_max), fmt::arg("hmin", h_min), fmt::arg("f", force),
                     fmt::arg("mf", -force), fmt::arg("steps", steps));
}

// h(t) of m_eff dV/dt = F0 - c(h) V, dh/dt = -V, V(0) = k h0 (the quasi-steady start), RK4
// with 1 ns steps, advanced from one requested time to the next (times must not decrease).
class InertialGap {
 public:
  double at(double t_end) {
    const double mass = density * pi / 6.0 * diameter * diameter * diameter;
    const double effective_mass = 0.5 * mass;
    auto rhs = [&](double h, double V, double& dh, double& dV) {
      dh = -V;
      dV = (force - squeeze / std::max(h, h_min) * V) / effective_mass;
    };
    const int n = int(std::ceil((t_end - t_) / 1e-9));
    const double s = n > 0 ? (t_end - t_) / n : 0.0;
    for (int i = 0; i < n; ++i) {
      double k1h, k1v, k2h, k2v, k3h, k3v, k4h, k4v;
      rhs(h_, V_, k1h, k1v);
      rhs(h_ + 0.5 * s * k1h, V_ + 0.5 * s * k1v, k2h, k2v);
      rhs(h_ + 0.5 * s * k2h, V_ + 0.5 * s * k2v, k3h, k3v);
      rhs(h_ + s * k3h, V_ + s * k3v, k4h, k4v);
      h_ += s / 6.0 * (k1h + 2 * k2h + 2 * k3h + k4h);
      V_ += s / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v);
    }
    t_ = std::max(t_, t_end);
    return h_;
  }

 private:
  double t_ = 0.0, h_ = h0, V_ = rate * h0;
};

std::vector<std::vector<double>> run_reynolds(const std::string& name, int ranks) {
  const auto dir = test_dir(name);
  const RunResult r = run_deck(dir, reynolds_deck(ranks > 1), ranks);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return read_table(dir / "gap.txt");
}

TEST(DemFluidLubrication, TwoSpheresFollowReynoldsGapHistory) {
  const auto rows = run_reynolds("reynolds_1rank", 1);
  ASSERT_GE(rows.size(), 20u);
  const double mass = density * pi / 6.0 * diameter * diameter * diameter;
  const double lag = rate * (0.5 * mass) * h0 / squeeze;  // k τ_n(h0) = 2.8e-3
  InertialGap inertial_gap;
  for (const auto& row : rows) {
    const double t = row[0], gap = row[1];
    EXPECT_EQ(row[2], 1.0) << "exactly one lubricated pair at t = " << t;
    // Against the inertial ODE: the explicit integration's lag is O(dt/τ_n(h)) per relaxation,
    // and the quasi-steady start keeps the relaxation small: 1e-4 relative (measured 3e-5).
    EXPECT_NEAR(gap / inertial_gap.at(t), 1.0, 1e-4) << "t = " << t;
    // Against Reynolds' law: the spheres' inertia delays the gap by at most k τ_n(h0) in
    // relative terms (first order: k τ_n(h0) (1 - h/h0)), 2.8e-3 here; the closed form itself
    // must hold to that bound, and the deviation must have inertia's sign: the spheres keep
    // some of their earlier, faster approach, so the gap is smaller than Reynolds'.
    const double reynolds = h0 * std::exp(-rate * t);
    EXPECT_LE(std::abs(gap / reynolds - 1.0), lag) << "t = " << t;
    EXPECT_LE(gap, reynolds * (1.0 + 1e-12)) << "t = " << t;
  }
  EXPECT_LT(rows.back()[1], 0.12 * h0);  // the gap did close by a factor ~10
}

TEST(DemFluidLubrication, PairSplitAcrossRanksGivesTheSameGapHistory) {
  const auto one = run_reynolds("reynolds_1rank_ref", 1);
  const auto two = run_reynolds("reynolds_2ranks", 2);
  ASSERT_EQ(one.size(), two.size());
  ASSERT_GE(one.size(), 20u);
  for (size_t i = 0; i < one.size(); ++i) {
    // Same arithmetic on each side (the pair is computed by both owners, each applying its half):
    // only the printed 15 digits may differ.
    EXPECT_NEAR(two[i][1], one[i][1], 1e-12 * h0) << "row " << i;
    EXPECT_EQ(two[i][2], 1.0) << "the pair counts once in total (1/2 per rank), row " << i;
  }
}

TEST(DemFluidLubrication, UnstableTimeStepIsRefusedNamingTheLimit) {
  // τ_n(h_min) = m_eff h_min / (6π η a²) = 1.11e-7 s: dt = 2e-7 s must be refused before any step
  const auto dir = test_dir("reynolds_unstable_dt");
  const RunResult r = run_deck(dir, reynolds_deck(false, 2e-7), 1);
  EXPECT_NE(r.exit_code, 0);
  std::ifstream log(dir / "log.txt");
  std::stringstream text;
  text << log.rdbuf() << r.output;
  EXPECT_NE(text.str().find("exceeds the normal lubrication limit"), std::string::npos)
      << text.str();
  EXPECT_NE(text.str().find("m_eff h_min / (6 pi eta a^2)"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir / "gap.txt") &&
               !read_table(dir / "gap.txt").empty());  // no step was taken
}

TEST(DemFluidLubrication, PairForcesAndVirialsMatchTheClosedForms) {
  // Two equal spheres (R = 0.5 mm) along x at gap h = 20 µm, approaching at U and sliding at V
  // (no spin): F_n = -6π η a² U / h (a = R/2) and, for equal spheres, F_t = -π η R ln(R/h) V
  // (Ball & Melrose 1997). Sphere 1 is at lower x, so Δx = x1 - x2 = -r and the virials are
  // W_xx = Δx F_x = c_n U r (repulsive: positive pressure) and W_xy = Δx F_y = c_t V r.
  constexpr double R = 0.5 * diameter, h = 2e-5, U = 0.01, V = 0.03, eta = 0.2;
  const double r = 2 * R + h;
  const double x1 = 0.005 - 0.5 * r, x2 = 0.005 + 0.5 * r;
  const std::string deck =
      deck_preamble("region box block 0 0.01 0 0.01 0 0.01 units box\ncreate_box 1 box", 1e-8) +
      fmt::format(R"(create_atoms    1 single {x1:.17g} 0.005 0.005 units box
create_atoms    1 single {x2:.17g} 0.005 0.005 units box
set             group all diameter {d} density {rho}
group           a id 1
group           b id 2
velocity        a set {u:.17g} {v:.17g} 0
velocity        b set {mu:.17g} {mv:.17g} 0
fix             integr all nve/sphere
fix             fl all fluid/le viscosity {eta} permeability seed_eq26 drag no rotation no lubrication 5e-5 1e-6
run             0
variable        pn equal f_fl[1]
variable        pt equal f_fl[10]
variable        pnxy equal f_fl[4]
variable        np equal f_fl[27]
variable        diss equal f_fl[30]
print           "${{pn}} ${{pt}} ${{pnxy}} ${{np}} ${{diss}}" file pair.txt
)",
                  fmt::arg("x1", x1), fmt::arg("x2", x2), fmt::arg("d", diameter),
                  fmt::arg("rho", density), fmt::arg("u", 0.5 * U), fmt::arg("v", 0.5 * V),
                  fmt::arg("mu", -0.5 * U), fmt::arg("mv", -0.5 * V), fmt::arg("eta", eta));
  const auto dir = test_dir("pair_closed_forms");
  const RunResult run = run_deck(dir, deck, 1);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto rows = read_table(dir / "pair.txt");
  ASSERT_EQ(rows.size(), 1u);
  const double volume = 1e-6;  // (0.01 m)³
  const double cn = 6 * pi * eta * (R / 2) * (R / 2) / h;
  const double ct = pi * eta * R * std::log(R / h);
  // closed forms to round-off (the printed values carry 15-16 digits)
  EXPECT_NEAR(rows[0][0] / (cn * U * r / volume), 1.0, 1e-12);
  EXPECT_NEAR(rows[0][1] / (ct * V * r / volume), 1.0, 1e-12);
  EXPECT_NEAR(rows[0][2], 0.0, 1e-12 * rows[0][0]);  // the normal force has no y part
  EXPECT_EQ(rows[0][3], 1.0);
  EXPECT_NEAR(rows[0][4] / (cn * U * U + ct * V * V), 1.0, 1e-12);
}

TEST(DemFluidLubrication, BadFixArgumentsAreRefusedWithTheExpectedValues) {
  const std::string base =
      deck_preamble("region box block 0 0.01 0 0.01 0 0.01 units box\ncreate_box 1 box", 1e-7) +
      "create_atoms 1 single 0.005 0.005 0.005 units box\nset group all diameter 0.001 density "
      "2500\nfix integr all nve/sphere\n";
  const std::pair<const char*, const char*> cases[] = {
      {"viscosity 0.01 permeability darcy", "seed_eq26"},  // lists the valid correlation names
      {"viscosity 0.01", "permeability NAME"},
      {"viscosity -1 permeability seed_eq26", "viscosity must be > 0"},
      {"viscosity 0.01 permeability seed_eq26 lubrication 1e-6 5e-5", "0 < HMIN < HMAX"},
      {"viscosity 0.01 permeability seed_eq26 lubrication 6e-4 1e-6", "below the smallest radius"},
      {"viscosity 0.01 permeability seed_eq26 swirl yes", "unknown keyword swirl"},
  };
  int k = 0;
  for (const auto& [arguments, expected] : cases) {
    const auto dir = test_dir("bad_arguments_" + std::to_string(k++));
    const RunResult r = run_deck(dir, base + "fix fl all fluid/le " + arguments + "\nrun 1\n", 1);
    EXPECT_NE(r.exit_code, 0) << arguments;
    std::ifstream log(dir / "log.txt");
    std::stringstream text;
    text << log.rdbuf() << r.output;
    EXPECT_NE(text.str().find(expected), std::string::npos) << arguments << "\n" << text.str();
  }
}

// `reach skin`: the list reach for h_max comes from the skin and the fix forces the rebuilds.
// Two spheres approach head-on at 1 m/s from a 330 µm gap with a 10 µm deck skin (h_max = 50 µm):
// LAMMPS' own check on the raised 60 µm skin would rebuild only every 60 µm of approach (at gaps
// 330, 270, ..., 90, 30 µm) and miss the pair for 50 > h > 30 µm (checked: 160 failures); the fix's
// check at half the deck skin must list it as soon as h < h_max, and the gap history (approach,
// lubrication, Hertz bounce) must be the one of the default reach through contact_distance_factor.
std::vector<std::vector<double>> run_approach(const std::string& name, const std::string& reach) {
  const std::string deck =
      deck_preamble("region box block 0 0.01 0 0.01 0 0.01 units box\ncreate_box 1 box", 1e-7) +
      fmt::format(R"(neighbor        0.00001 bin
create_atoms    1 single 0.004335 0.005 0.005 units box
create_atoms    1 single 0.005665 0.005 0.005 units box
set             group all diameter 0.001 density 2500
group           a id 1
group           b id 2
velocity        a set 0.5 0 0
velocity        b set -0.5 0 0
fix             integr all nve/sphere
fix             fl all fluid/le viscosity 0.01 permeability seed_eq26 drag no rotation no lubrication 5e-5 1e-6 {reach}
variable        gap equal x[2]-x[1]-0.001
variable        pairs equal f_fl[27]
fix             out all print 10 "${{gap}} ${{pairs}}" file gap.txt screen no
run             4000
)",
                  fmt::arg("reach", reach));
  const RunResult r = run_deck(test_dir(name), deck, 1);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return read_table(test_dir(name) / "gap.txt");
}

TEST(DemFluidLubrication, ReachBySkinListsEveryPairWithinHmax) {
  const auto factor = run_approach("approach_factor", "");
  const auto skin = run_approach("approach_skin", "reach skin");
  ASSERT_EQ(factor.size(), 400u);  // steps 10, 20, ..., 4000
  ASSERT_EQ(skin.size(), factor.size());
  int lubricated_samples = 0;
  double closest = 1.0;
  for (std::size_t k = 0; k < skin.size(); ++k) {
    const double gap = skin[k][0];
    closest = std::min(closest, gap);
    // one pair exactly while h < h_max (the force is zero from h_max on), in both modes
    EXPECT_EQ(skin[k][1], gap < 5e-5 ? 1.0 : 0.0) << "gap " << gap;
    EXPECT_EQ(factor[k][1], skin[k][1]) << "gap " << gap;
    lubricated_samples += gap < 5e-5;
    // the same forces in the same order: round-off of the positions (1e-3 m) only, 1e-15 m
    EXPECT_NEAR(skin[k][0], factor[k][0], 1e-15) << "sample " << k;
  }
  EXPECT_GT(lubricated_samples, 20);  // the pair was lubricated for a while...
  EXPECT_LT(closest, 0.0);            // ...and the spheres collided (Hertz overlap)
}

}  // namespace
}  // namespace granflow::dem::test
