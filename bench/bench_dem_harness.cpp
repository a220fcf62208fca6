// Cost of one extraction-harness sample (kinetic stress, T, phi, profile) per particle.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "dem_coupling/extraction/shear_sample.hpp"

namespace {

void BM_HarnessSample(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0.0, 0.01);
  std::vector<double> x(3 * n), v(3 * n), m(n, 1e-6), r(n, 5e-4);
  for (auto& c : x) c = u(rng);
  for (auto& c : v) c = u(rng);
  granflow::dem::SampleSums sums(10);
  const granflow::dem::ShearFrame frame{20.0, 0.0, 0.01};
  const granflow::dem::ParticleView view{n, x.data(), v.data(), m.data(), r.data()};
  for (auto _ : state) {
    sums.clear();
    granflow::dem::accumulate_particles(view, frame, sums);
    auto s = granflow::dem::finalize_sample(sums, {}, {0.01, 0.01, 0.01, 0.0}, frame, 2500.0);
    benchmark::DoNotOptimize(s.temperature);
  }
  state.SetItemsProcessed(state.iterations() * n);
}
BENCHMARK(BM_HarnessSample)->Arg(1000)->Arg(10000);

}  // namespace

BENCHMARK_MAIN();
