// Time per force-chain update (ForceChainModel::update) on one core: elastic step inside the
// locus, plastic steps of an MPM-size (1e-6) and a REV-size (1e-4) strain increment, and the
// fluidized state. Target: <= 2 µs for the full material-point update.
#include <benchmark/benchmark.h>

#include "continuum/model/force_chains/force_chain_model.hpp"

namespace fc = granflow::model::force_chains;

namespace {
Eigen::Matrix3d undrained(double a) { return Eigen::Vector3d(a, -a / 2, -a / 2).asDiagonal(); }

void BM_ElasticStep(benchmark::State& st) {
  const fc::ForceChainModel model{fc::ForceChainParameters{}};
  auto s = model.isotropic_state(50e3, 0.7, 4.0);  // overconsolidated: stays inside the locus
  Eigen::Matrix3d de = undrained(1e-6);
  de(0, 1) = de(1, 0) = 3e-7;
  long n = 0;
  for (auto _ : st) {
    const auto info = model.update(s, (n++ & 1) ? -de : de, 1e-5, 0.0);  // cyclic, elastic
    benchmark::DoNotOptimize(info);
  }
}
BENCHMARK(BM_ElasticStep);

// Undrained shear of the loose sand, restarted every `restart` updates before it fluidizes
// (the state copy is ~250 bytes, negligible against the update).
void plastic(benchmark::State& st, double increment, long restart) {
  const fc::ForceChainModel model{fc::ForceChainParameters{}};
  const auto start = model.isotropic_state(50e3, 0.7);
  auto s = start;
  long n = 0, substeps = 0, updates = 0;
  for (auto _ : st) {
    if (++n % restart == 0) s = start;
    const auto info = model.update(s, undrained(increment), 1e-5, 0.0);
    substeps += info.substeps;
    ++updates;
    benchmark::DoNotOptimize(info);
  }
  st.counters["substeps_per_update"] = double(substeps) / double(updates);
}
void BM_PlasticStepMpm(benchmark::State& st) { plastic(st, 1e-6, 20000); }  // ε_d up to 0.02
void BM_PlasticStepRev(benchmark::State& st) { plastic(st, 1e-4, 200); }    // ε_d up to 0.02
BENCHMARK(BM_PlasticStepMpm);
BENCHMARK(BM_PlasticStepRev);

void BM_FluidizedStep(benchmark::State& st) {
  const fc::ForceChainModel model{fc::ForceChainParameters{}};
  fc::ForceChainState s;
  s.fluidized = true;
  for (auto _ : st) {
    const auto info = model.update(s, undrained(1e-6), 1e-5, 1.0);
    benchmark::DoNotOptimize(info);
  }
}
BENCHMARK(BM_FluidizedStep);
}  // namespace

BENCHMARK_MAIN();
