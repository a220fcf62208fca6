// Every combination of the on/off numerics options of the liquid (the cell-averaged volumetric
// rate, the pore-pressure relaxation t_p, the PIC relaxation t_PIC and, on the closed annulus, the
// removal of the mean volumetric rate) keeps the analytic accuracy of Terzaghi and Couette: each
// option is a remedy for a grid mode, none may change the resolved solution. The options share
// node buffers inside a step (the cell sums of the smoothing and the nodal averages of the
// relaxation), so a combination can fail where each option alone passes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "continuum/mpm/problems.hpp"

using namespace granflow::mpm;

namespace {

struct Options {
  bool smoothing, pressure_relaxation, pic_relaxation, closed;
  std::string name() const {
    std::string n = std::string(smoothing ? " smoothing" : "") +
                    (pressure_relaxation ? " t_p" : "") + (pic_relaxation ? " t_PIC" : "") +
                    (closed ? " closed" : "");
    return n.empty() ? "none" : n.substr(1);
  }
};

// All 2^n combinations of the first n options.
std::vector<Options> combinations(int n) {
  std::vector<Options> out;
  for (int m = 0; m < (1 << n); ++m)
    out.push_back({(m & 1) != 0, (m & 2) != 0, (m & 4) != 0, (m & 8) != 0});
  return out;
}

void apply(const Options& o, SolverOptions& s, double t_p, double t_pic) {
  s.threads = 1;
  s.liquid_volumetric_smoothing = o.smoothing;
  s.pressure_relaxation_time = o.pressure_relaxation ? t_p : 0.0;
  if (o.pic_relaxation) s.pic_relaxation_time = t_pic;  // flip stays 1
  s.closed_domain = o.closed;
}

}  // namespace

TEST(MpmNumericsOptions, TerzaghiKeepsItsAnalyticErrorWithEveryCombination) {
  // Open domain (drained top): smoothing × t_p × t_PIC. t_p = 1 s gives a pressure diffusivity
  // h²/t_p = 0.01 m²/s, 1 % of c_v = 0.99 m²/s; t_PIC = 0.05 s is a tenth of the run (T_v = 0.5
  // at 0.5 s), so both act on the solution yet must leave it.
  for (const Options& o : combinations(3)) {
    TerzaghiSpec t;  // h = H/10, as cases/mpm/terzaghi.yaml
    apply(o, t.options, 1.0, 0.05);
    auto s = make_terzaghi(t);
    const TerzaghiConstants k = terzaghi_constants(t);
    double ep_max = 0, es_max = 0;
    try {
      for (double Tv : {0.05, 0.2, 0.5}) {
        const double time = Tv * t.height * t.height / k.cv;
        while (s->time() < time - 0.5 * s->dt()) s->step();
        double u, ue;
        terzaghi_settlement(*s, t, u, ue);
        ep_max = std::max(ep_max, terzaghi_pressure_error(*s, t));
        es_max = std::max(es_max, std::fabs(u - ue) / k.final_settlement);
      }
    } catch (const granflow::core::NumericalFailure& f) {
      ADD_FAILURE() << o.name() << ": " << f.what();
      continue;
    }
    std::printf("terzaghi %-34s pressure RMS error / p0 %.3e, settlement error %.3e\n",
                o.name().c_str(), ep_max, es_max);
    // The bounds of test_mpm_terzaghi at h = H/10 (measured 3.5e-2 and 1.4e-3 without options):
    // the pressure error is dominated by the drained top cell, where p drops to 0 over one cell.
    EXPECT_LT(ep_max, 0.05) << o.name();
    EXPECT_LT(es_max, 0.005) << o.name();
  }
}

TEST(MpmNumericsOptions, CouetteKeepsItsAnalyticErrorWithEveryCombination) {
  // The annulus is closed (both walls impermeable): smoothing × t_p × t_PIC × closed domain.
  // t_p = 0.05 s: its diffusivity h²/t_p ≈ 0.8 m²/s acts on p only, uniform in the exact
  // solution. t_PIC = 0.5 s, a quarter of the run: the PIC part of a step diffuses momentum, a
  // numerical viscosity that grows as t_PIC falls (v_θ error with smoothing 9.5e-3 at 0.05 s,
  // 3.0e-3 at 0.2 s, 1.1e-3 at 0.5 s, measured), a property of the option and not the defect
  // looked for here.
  for (const Options& o : combinations(4)) {
    CouetteSpec c;  // 5 x 32 cells, as cases/mpm/couette.yaml
    c.cells_r = 5;
    c.cells_theta = 32;
    c.options.flip = 1.0;
    apply(o, c.options, 0.05, 0.5);
    auto s = make_couette(c);
    // Viscous diffusion time 1 s: averaged over 1.5-2 s, as test_mpm_couette.
    std::vector<double> vx(s->grid_nodes(), 0.0), vy(s->grid_nodes(), 0.0);
    int samples = 0;
    try {
      while (s->time() < 2.0) {
        s->step();
        if (s->time() < 1.5) continue;
        for (int a = 0; a < s->grid_nodes(); ++a) {
          vx[a] += s->nodes().vx_liquid[a];
          vy[a] += s->nodes().vy_liquid[a];
        }
        ++samples;
      }
    } catch (const granflow::core::NumericalFailure& f) {
      ADD_FAILURE() << o.name() << ": " << f.what();
      continue;
    }
    for (int a = 0; a < s->grid_nodes(); ++a) {
      vx[a] /= samples;
      vy[a] /= samples;
    }
    double et, er;
    couette_error(*s, c, vx, vy, et, er);
    std::printf("couette  %-34s RMS v_theta error / V %.3e, RMS v_r / V %.3e\n", o.name().c_str(),
                et, er);
    // The bounds of test_mpm_couette: no mean radial flow beyond 0.5 % of the wall speed
    // (acoustic remainder, measured 4e-4 with smoothing and 1.7e-3 without; the smoothing's cell
    // rates read back from a buffer the relaxation had overwritten drove 1.6 %), and v_θ within
    // 0.5 % of it on 5 x 32 cells (measured 6.6e-4). The v_θ bound holds for the verified scheme,
    // with the smoothing (cases/mpm/couette.yaml): without it the pressure checkerboard of the
    // cell-constant rate costs 2.7e-2 on this grid with or without the other options.
    EXPECT_LT(er, 5e-3) << o.name();
    if (o.smoothing) {
      EXPECT_LT(et, 5e-3) << o.name();
    }
  }
}
