// Particle-updates per second (points x steps / wall time) of the double-point MPM on the fixed
// benchmark problems of docs/performance.md (section MPM), with 1 and 2 OpenMP threads:
//   MPM-1: elastic column 1 m x 4 m, h = 0.02 m, 2 x 2 points per cell (40,000 solid points),
//          E = 1e7 Pa, ν = 0.3, ρ = 2000 kg/m³, gravity at t = 0, MUSL, FLIP, Δt = 1e-4 s, 700
//          steps. Sanity counter: base σ_yy (about 89 kPa at step 700).
//   MPM-2: consolidation column, same grid, 40,000 solid + 40,000 liquid points, E = 1e7 Pa,
//          ν = 0, n = 0.3, K_w = 1e8 Pa, k_D = 1e-3 m/s, 10 kPa sudden load, Δt = 1e-5 s,
//          350 steps. Sanity counter: mean p behind the loading wave (about 9.7 kPa).
// Each benchmark iteration is the whole fixed run; set-up is outside the timed region.
// OpenMP wait policy: on an idle machine the libgomp default or OMP_WAIT_POLICY=active (a barrier
// costs 0.3 µs); OMP_WAIT_POLICY=passive costs a futex wake-up of a halted vCPU per fork/join or
// barrier (6-66 µs on the development VM) but is the only sane choice on a shared machine, where
// spinning threads steal the cores of descheduled partners. Figures: docs/performance.md#mpm.
#include <benchmark/benchmark.h>

#include "continuum/mpm/problems.hpp"

using namespace granflow::mpm;

namespace {

void BM_MPM1_ElasticColumn(benchmark::State& state) {
  ColumnSpec c;
  c.width = 1.0;
  c.height = 4.0;
  c.cell = 0.02;
  c.points_per_cell = 2;
  c.density = 2000.0;
  c.young_modulus = 1.0e7;
  c.poisson_ratio = 0.3;
  c.options.fixed_dt = 1e-4;
  c.options.flip = 1.0;
  c.options.scheme = UpdateScheme::musl;
  c.options.threads = static_cast<int>(state.range(0));
  c.options.dt_update_interval = 0;
  const long steps = 700;
  double base = 0, points = 0;
  for (auto _ : state) {
    state.PauseTiming();
    auto s = make_elastic_column(c);
    points = static_cast<double>(s->solid().size());
    state.ResumeTiming();
    s->run_steps(steps);
    state.PauseTiming();
    base = -column_error(*s, c).base_stress;
    state.ResumeTiming();
  }
  state.counters["particle_updates_per_s"] =
      benchmark::Counter(points * steps * state.iterations(), benchmark::Counter::kIsRate);
  state.counters["points"] = points;
  state.counters["base_stress_Pa"] = base;
}

void BM_MPM2_Consolidation(benchmark::State& state) {
  TerzaghiSpec t;
  t.width = 1.0;
  t.height = 4.0;
  t.cell = 0.02;
  t.points_per_cell = 2;
  t.young_modulus = 1.0e7;
  t.poisson_ratio = 0.0;
  t.porosity = 0.3;
  t.grain_density = 2650.0;
  t.liquid_density = 1000.0;
  t.bulk_modulus = 1.0e8;
  t.hydraulic_conductivity = 1.0e-3;
  t.load = 1.0e4;
  t.undrained_start = false;
  t.options.fixed_dt = 1e-5;
  t.options.threads = static_cast<int>(state.range(0));
  t.options.dt_update_interval = 0;
  const long steps = 350;
  double behind = 0, points = 0;
  for (auto _ : state) {
    state.PauseTiming();
    auto s = make_terzaghi(t);
    points = static_cast<double>(s->solid().size() + s->liquid().size());
    state.ResumeTiming();
    s->run_steps(steps);
    state.PauseTiming();
    // Mean pore pressure 0.2-1.0 m below the top: behind the wave front (at ~1.4 m).
    double sum = 0;
    int n = 0;
    for (std::size_t p = 0; p < s->liquid().size(); ++p) {
      const double depth = t.height - s->liquid().y[p];
      if (depth > 0.2 && depth < 1.0) {
        sum += s->liquid().pressure[p];
        ++n;
      }
    }
    behind = n ? sum / n : 0.0;
    state.ResumeTiming();
  }
  state.counters["particle_updates_per_s"] =
      benchmark::Counter(points * steps * state.iterations(), benchmark::Counter::kIsRate);
  state.counters["points"] = points;
  state.counters["pressure_behind_wave_Pa"] = behind;
}

}  // namespace

BENCHMARK(BM_MPM1_ElasticColumn)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(2);
BENCHMARK(BM_MPM2_Consolidation)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(2);

BENCHMARK_MAIN();
