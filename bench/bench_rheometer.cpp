// The rheometer of cases/mpm/rheometer_test1.yaml (seed section 6; docs/rheometer.md): annulus
// 0.08-0.11 m on the polar O-grid, 8 x 96 cells, 2 x 2 points per cell and phase (3072 solid +
// 3072 liquid points), the multi-regime material (force chains + collisional + liquid, T
// conducted), built from the case file exactly as `granflow run` builds it. Each benchmark
// iteration runs the first `steps` steps from t = 0 (set-up outside the timed region), with the
// per-step accumulation of the shear strain the run does: 1000 steps (Δt ≈ 1.16 µs, t ≈ 1.2 ms)
// take the skeleton through the elastic load, the peak of τ̄ (0.58 ms) and into the collapse,
// the part of the run where the force-chain update is plastic. Counters:
//   particle_updates_per_s  (solid + liquid points) × steps / wall time
//   ms_per_step             wall time per step
//   cpu_ms_per_step         CPU time of the main thread per step (what a shared machine's load
//                           does not inflate; with 2 threads the main thread's share)
//   peak_rss_MB             peak resident set of the process so far (getrusage)
// Arguments: threads. Figures and the command: docs/performance.md#rheometer_bench.
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <chrono>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include "continuum/mpm/kind_rheometer.hpp"
#include "continuum/mpm/mpm_kind.hpp"
#include "core/case.hpp"
#include "core/kind_registry.hpp"

using namespace granflow;

namespace {

double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

void BM_Rheometer_Test1(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  const long steps = state.range(1);
  core::KindRegistry registry;
  mpm::register_mpm_kinds(registry);
  const auto path =
      std::filesystem::path(GRANFLOW_SOURCE_DIR) / "cases" / "mpm" / "rheometer_test1.yaml";
  const auto [kind, test] = core::peek_kind(path);
  const auto& entry = registry.find(kind, test, path.string());
  const core::Case c =
      core::Case::load(path, {"numerics.threads=" + std::to_string(threads)}, entry.schema);
  entry.check(c);
  const mpm::RheometerSpec spec = mpm::kind::read_rheometer(c);
  double points = 0, wall = 0, cpu = 0, tau = 0;
  for (auto _ : state) {
    state.PauseTiming();
    mpm::Rheometer rh = mpm::make_rheometer(spec);
    rh.material->set_internal_length(c.number("solid.internal_length"),
                                     c.number("solid.overnonlocal"));
    mpm::Solver& s = *rh.solver;
    points = static_cast<double>(s.solid().size() + s.liquid().size());
    std::vector<double> gamma(s.solid().size(), 0.0);
    state.ResumeTiming();
    const auto w0 = std::chrono::steady_clock::now();
    const double c0 = thread_cpu_seconds();
    for (long k = 0; k < steps; ++k) {
      s.step();
      mpm::accumulate_shear_strain(s, gamma);
    }
    cpu += thread_cpu_seconds() - c0;
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
    state.PauseTiming();
    tau = mpm::rheometer_averages(s, *rh.material, gamma).shear_stress;
    state.ResumeTiming();
  }
  const double n = static_cast<double>(steps) * static_cast<double>(state.iterations());
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  state.counters["particle_updates_per_s"] =
      benchmark::Counter(points * n, benchmark::Counter::kIsRate);
  state.counters["points"] = points;
  state.counters["ms_per_step"] = 1e3 * wall / n;
  state.counters["cpu_ms_per_step"] = 1e3 * cpu / n;
  state.counters["peak_rss_MB"] = static_cast<double>(ru.ru_maxrss) / 1024.0;
  state.counters["tau_Pa"] = tau;  // sanity: τ̄ at the last step (≈ 31 kPa near the peak)
}

}  // namespace

BENCHMARK(BM_Rheometer_Test1)
    ->Args({1, 1000})
    ->Args({2, 1000})
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(2);

BENCHMARK_MAIN();
