// Solid materials: linear elasticity in Jaumann rate form against Hooke's law (oedometric and
// shear loading), objectivity under a pure rotation, and the registry that `solid.material` of a
// case reaches.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "continuum/mpm/linear_elastic.hpp"
#include "continuum/mpm/material_registry.hpp"
#include "continuum/mpm/solid_material.hpp"
#include "core/case.hpp"
#include "core/kind_registry.hpp"
#include "core/schema.hpp"

using namespace granflow::mpm;
namespace core = granflow::core;

namespace {
struct OnePoint {
  double Lxx = 0, Lxy = 0, Lyx = 0, Lyy = 0, n = 0, T = 0;
  double sxx = 0, syy = 0, szz = 0, sxy = 0;
  StressUpdateView view() { return {&Lxx, &Lxy, &Lyx, &Lyy, &n, &T, &sxx, &syy, &szz, &sxy, 1}; }
};
}  // namespace

TEST(MpmMaterials, LinearElasticFollowsHookesLawInPlaneStrain) {
  const double E = 1e7, nu = 0.3;
  LinearElastic m(E, nu, 2650);
  m.attach(0, 1);
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), G = E / (2 * (1 + nu));
  OnePoint p;
  p.Lyy = -1e-3;  // oedometric compression rate, 1000 steps of 1e-3 s: ε_yy = -1e-3
  for (int i = 0; i < 1000; ++i) m.update_stress(p.view(), 1e-3);
  // Rate form integrated exactly for a constant rate (no rotation): round-off only.
  EXPECT_NEAR(p.syy, (lambda + 2 * G) * -1e-3, 1e-6);
  EXPECT_NEAR(p.sxx, lambda * -1e-3, 1e-6);
  EXPECT_NEAR(p.szz, lambda * -1e-3, 1e-6);
  EXPECT_NEAR(m.p_wave_modulus(), lambda + 2 * G, 1e-6);
  OnePoint q;
  q.Lxy = 1e-4;
  q.Lyx = 1e-4;  // pure shear, no spin
  m.update_stress(q.view(), 1.0);
  EXPECT_NEAR(q.sxy, 2 * G * 1e-4, 1e-9);  // σ_xy = 2 G D_xy
  EXPECT_NEAR(q.sxx, 0.0, 1e-12);
}

TEST(MpmMaterials, JaumannRateRotatesTheStressWithoutStraining) {
  LinearElastic m(1e7, 0.25, 2650);
  m.attach(0, 1);
  OnePoint p;
  p.sxx = -100.0;
  p.syy = -300.0;
  // Spin W_xy = 1 rad/s, no stretching: the stress tensor only rotates, so its invariants stay.
  p.Lxy = 1.0;
  p.Lyx = -1.0;
  const double tr0 = p.sxx + p.syy, det0 = p.sxx * p.syy - p.sxy * p.sxy;
  for (int i = 0; i < 1000; ++i) m.update_stress(p.view(), 1e-4);  // 0.1 rad
  // Forward Euler on a rotation: the invariants drift at O(Δθ² n) = 1e-5 relative.
  EXPECT_NEAR(p.sxx + p.syy, tr0, 1e-9);
  EXPECT_NEAR((p.sxx * p.syy - p.sxy * p.sxy) / det0, 1.0, 2e-5);
  EXPECT_GT(std::fabs(p.sxy), 10.0);  // it did rotate (sin(0.2) x 100 Pa ≈ 20 Pa)
}

// The registry is what `solid.material` reaches: its names are the schema's choices, the case's
// name selects the material, the material reads its own keys (with the problem's defaults), and a
// name or a default the registry does not know is refused.
TEST(MpmMaterials, CaseSelectsTheMaterialByNameAndItReadsItsOwnKeys) {
  const MaterialRegistry r = material_registry();
  core::Schema schema = core::kind_header("mpm", "material_test", "a solid section only");
  auto& solid = schema.section("solid", "solid points");
  r.declare(solid, {{"young_modulus", "2.0e6"}, {"density", "1800"}});
  const core::Field* material = solid.child("material");
  ASSERT_NE(material, nullptr);
  EXPECT_EQ(material->choice_names(), r.names());
  EXPECT_EQ(material->default_text().value_or(""), r.names().front());
  const auto c =
      core::Case::parse("kind: mpm\ntest: material_test\nsolid:\n  poisson_ratio: 0.25\n",
                        "material.yaml", {}, schema);
  // The problem's defaults and the case's value reach the typed parameters.
  const LinearElasticParameters p = read_linear_elastic(c);
  EXPECT_EQ(p.young_modulus, 2.0e6);
  EXPECT_EQ(p.poisson_ratio, 0.25);
  EXPECT_EQ(p.density, 1800.0);
  auto m = r.create(c);
  EXPECT_EQ(m->name(), c.string("solid.material"));
  EXPECT_EQ(m->grain_density(), 1800.0);
  // λ + 2G = E (1-ν)/((1+ν)(1-2ν)) of those parameters: the material was built from them.
  EXPECT_DOUBLE_EQ(m->p_wave_modulus(), 2.0e6 * 0.75 / (1.25 * 0.5));
  try {
    r.at("plastic");
    FAIL();
  } catch (const std::invalid_argument& e) {
    for (const auto& name : r.names())  // lists the valid names
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
  }
  core::Schema bad = core::kind_header("mpm", "material_test", "a typo in a default");
  EXPECT_THROW(r.declare(bad.section("solid", "solid points"), {{"young_modulu", "1"}}),
               std::logic_error);
}

// The solver updates an independent material from inside its parallel region, each thread over
// its part of the points (update_range); the parts must give the whole update bit for bit.
TEST(MpmMaterials, LinearElasticRangesEqualTheWholeUpdateBitForBit) {
  const std::size_t n = 7;
  std::vector<double> L[4], s[2][4], porosity(n, 0.4), T(n, 0.0);
  for (auto& l : L) l.resize(n);
  for (std::size_t p = 0; p < n; ++p) {
    L[0][p] = 1e-3 * std::sin(1.0 + p);
    L[1][p] = 2e-3 * std::cos(2.0 * p);
    L[2][p] = -1e-3 * std::sin(0.5 * p);
    L[3][p] = 5e-4 * (p % 3);
  }
  for (auto& copy : s)
    for (int c = 0; c < 4; ++c) copy[c].assign(n, -1e3 * (c + 1));
  auto view = [&](int k) {
    return StressUpdateView{L[0].data(),
                            L[1].data(),
                            L[2].data(),
                            L[3].data(),
                            porosity.data(),
                            T.data(),
                            s[k][0].data(),
                            s[k][1].data(),
                            s[k][2].data(),
                            s[k][3].data(),
                            1};
  };
  LinearElastic whole(1e7, 0.3, 2650), parts(1e7, 0.3, 2650);
  whole.attach(0, n);
  parts.attach(0, n);
  ASSERT_TRUE(parts.updates_points_independently());
  for (int step = 0; step < 20; ++step) {
    whole.update_stress(view(0), 1e-2);
    parts.begin_ranges(3);
    parts.update_range(view(1), 1e-2, 5, 7, 2);  // any order: the parts are independent
    parts.update_range(view(1), 1e-2, 0, 2, 0);
    parts.update_range(view(1), 1e-2, 2, 5, 1);
    parts.finish_ranges(view(1));
  }
  for (int c = 0; c < 4; ++c)
    for (std::size_t p = 0; p < n; ++p) EXPECT_EQ(s[0][c][p], s[1][c][p]) << c << " " << p;
  EXPECT_NE(s[0][3][1], -4e3);  // the stress moved (the test cannot pass on an idle update)
}
