// Cost of one multi-regime material-point update (collisional + liquid, T balance) and of one REV
// simple-shear step, for docs/performance.md.
#include <benchmark/benchmark.h>

#include "continuum/rev/simple_shear.hpp"

using namespace granflow;

static continuum::MultiRegimeSettings settings(bool liquid) {
  continuum::MultiRegimeSettings s;
  s.liquid = liquid;
  s.fluctuation_dissipation = liquid;
  return s;
}

static void BM_PointUpdate(benchmark::State& state) {
  const continuum::MultiRegimePoint point(settings(state.range(0) != 0));
  Eigen::Matrix3d rate = Eigen::Matrix3d::Zero();
  rate(0, 1) = rate(1, 0) = -25.0;
  continuum::PointState s{0.55, 4e-4};
  for (auto _ : state) {
    auto parts = point.update(s, rate, 1e-4);
    benchmark::DoNotOptimize(parts);
  }
  state.SetLabel(state.range(0) ? "collisional+liquid" : "collisional");
}
BENCHMARK(BM_PointUpdate)->Arg(0)->Arg(1);

static void BM_SimpleShearToSteady(benchmark::State& state) {
  const continuum::MultiRegimePoint point(settings(false));
  rev::SimpleShearControl control;
  control.control = state.range(0) ? rev::ShearControl::constant_pressure : rev::ShearControl::constant_volume;
  control.normal_stress = 100;
  control.shear_rate = 50;
  long steps = 0;
  for (auto _ : state) {
    const auto r = rev::run_simple_shear(point, control);
    steps += r.steps;
    benchmark::DoNotOptimize(r.steady.granular_temperature);
  }
  state.counters["steps_per_s"] = benchmark::Counter(static_cast<double>(steps), benchmark::Counter::kIsRate);
  state.SetLabel(state.range(0) ? "constant pressure" : "constant volume");
}
BENCHMARK(BM_SimpleShearToSteady)->Arg(0)->Arg(1);

BENCHMARK_MAIN();
