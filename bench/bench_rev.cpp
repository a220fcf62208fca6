// Cost of one multi-regime material-point update (collisional + liquid, T balance; and the full
// update with force chains), of one REV simple-shear run and of one undrained triaxial case, for
// docs/performance.md#rev.
#include <benchmark/benchmark.h>

#include "continuum/rev/element_test.hpp"
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
  continuum::PointState s;
  s.solid_fraction = 0.55;
  s.granular_temperature = 4e-4;
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
  control.control =
      state.range(0) ? rev::ShearControl::constant_pressure : rev::ShearControl::constant_volume;
  control.normal_stress = 100;
  control.shear_rate = 50;
  long steps = 0;
  for (auto _ : state) {
    const auto r = rev::run_simple_shear(point, control);
    steps += r.steps;
    benchmark::DoNotOptimize(r.steady.granular_temperature);
  }
  state.counters["steps_per_s"] =
      benchmark::Counter(static_cast<double>(steps), benchmark::Counter::kIsRate);
  state.SetLabel(state.range(0) ? "constant pressure" : "constant volume");
}
BENCHMARK(BM_SimpleShearToSteady)->Arg(0)->Arg(1);

// All terms (σ_FC + σ_COL + σ_L, Λ): the loose sand of cases/rev/triaxial_undrained_rate1.yaml.
static continuum::MultiRegimeSettings all_terms() {
  continuum::MultiRegimeSettings s;
  s.force_chains = true;
  s.liquid = true;
  s.fluctuation_dissipation = true;
  s.collisional_parameters.diameter = 2.3e-3;
  s.collisional_parameters.particle_density = 2650;
  s.collisional_parameters.restitution = 0.8;
  s.collisional_parameters.jamming_fraction = 0.64;
  s.liquid_parameters.maximum_packing = 0.64;
  return s;
}

// One full advance() (ν, σ_FC with sub-stepping, exact T update, σ_COL, σ_L) from a state on the
// hardening branch of an undrained triaxial path (ε_d = 0.01, plastic), at Δε_d = 5e-5 (the
// case's step). Arg 0: plastic solid skeleton; arg 1: fluidized skeleton (ε_d = 0.08). The state
// is restored each iteration (a 0.3 kB copy, included in the time).
static void BM_FullPointUpdate(benchmark::State& state) {
  const continuum::MultiRegimePoint point(all_terms());
  const double dt = 5e-5, rate_d = 1.0;
  Eigen::Matrix3d rate = Eigen::Vector3d(rate_d, -0.5 * rate_d, -0.5 * rate_d).asDiagonal();
  continuum::PointState start = point.initial_state(0.70, 50e3, 1.0, 0.0);
  const int warm = state.range(0) ? 1600 : 200;
  for (int i = 0; i < warm; ++i) point.advance(start, rate, dt);
  long substeps = 0;
  for (auto _ : state) {
    continuum::PointState s = start;
    auto parts = point.advance(s, rate, dt);
    substeps += parts.force_chain_update.substeps;
    benchmark::DoNotOptimize(parts);
  }
  state.counters["substeps_per_update"] =
      benchmark::Counter(static_cast<double>(substeps), benchmark::Counter::kAvgIterations);
  state.SetLabel(state.range(0) ? "all terms, fluidized" : "all terms, plastic skeleton");
}
BENCHMARK(BM_FullPointUpdate)->Arg(0)->Arg(1);

// The seed's section 4 undrained triaxial (2400 steps to ε_d = 0.12, radial stress solved per
// step, K_w = 2.2 GPa).
static void BM_UndrainedTriaxialCase(benchmark::State& state) {
  const continuum::MultiRegimePoint point(all_terms());
  rev::TriaxialControl control;
  rev::TriaxialStage stage;
  stage.deviatoric_strain_rate = 1.0;
  stage.duration = 0.12;
  stage.steps = 2400;
  control.stages.push_back(stage);
  long updates = 0;
  for (auto _ : state) {
    const auto r = rev::run_triaxial(point, control);
    updates += r.solver_evaluations;
    benchmark::DoNotOptimize(r.liquefaction_strain);
  }
  state.counters["point_updates_per_s"] =
      benchmark::Counter(static_cast<double>(updates), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_UndrainedTriaxialCase)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
