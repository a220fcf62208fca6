// Time of one full collisional + liquid closure evaluation at a material point: coefficients
// (g0, ε, f1..f4, J, M), L, p, viscosity, Γ, conductivity, η(ν), κ, β, per-particle drag, Λ.
// Target: under 200 ns. Figures: docs/performance.md#closures.
#include <benchmark/benchmark.h>

#include <array>
#include <cstddef>

#include "continuum/model/closures.hpp"

namespace gm = granflow::model;

namespace {

struct Options {
  gm::RadialDistributionKind g0;
  gm::CorrelationLengthKind L;
  gm::MixtureViscosityKind eta;
  gm::PermeabilityKind kappa;
};

// range(0): option set. 0 = case-file defaults (Chialvo-Sundaresan g0 and ε, L = d, Boyer,
// seed Eq. 26); 1 = Torquato, Jenkins L, Krieger-Dougherty, Ergun; 2 = Carnahan-Starling, L = d,
// Einstein, Kozeny-Carman.
constexpr std::array<Options, 3> option_sets{{
    {gm::RadialDistributionKind::chialvo_sundaresan, gm::CorrelationLengthKind::diameter,
     gm::MixtureViscosityKind::boyer, gm::PermeabilityKind::seed_eq26},
    {gm::RadialDistributionKind::torquato, gm::CorrelationLengthKind::jenkins,
     gm::MixtureViscosityKind::krieger_dougherty, gm::PermeabilityKind::ergun},
    {gm::RadialDistributionKind::carnahan_starling, gm::CorrelationLengthKind::diameter,
     gm::MixtureViscosityKind::einstein, gm::PermeabilityKind::kozeny_carman},
}};

void configure(const benchmark::State& state, gm::CollisionalParameters& p,
               gm::LiquidParameters& l) {
  const auto& o = option_sets[static_cast<std::size_t>(state.range(0))];
  p.radial_distribution = o.g0;
  p.correlation_length = o.L;
  l.mixture_viscosity = o.eta;
  l.permeability = o.kappa;
  l.maximum_packing = 0.585;
  p.jamming_fraction = 0.587;
}

// One full evaluation; every result goes through DoNotOptimize.
inline void evaluate(const gm::CollisionalParameters& p, const gm::LiquidParameters& l, double nu,
                     double T, double shear_rate) {
  const auto c = gm::collisional_coefficients(p, nu);
  const double L = gm::correlation_length(p, c, shear_rate, T);
  benchmark::DoNotOptimize(L);
  benchmark::DoNotOptimize(gm::collisional_pressure(p, c, T));
  benchmark::DoNotOptimize(gm::collisional_viscosity(p, c, T));
  benchmark::DoNotOptimize(gm::collisional_dissipation(p, c, T, L));
  benchmark::DoNotOptimize(gm::collisional_conductivity(p, c, T));
  benchmark::DoNotOptimize(gm::mixture_viscosity(l, nu));
  benchmark::DoNotOptimize(gm::permeability(l, p.diameter, nu));
  benchmark::DoNotOptimize(gm::drag_coefficient(l, p.diameter, nu));
  benchmark::DoNotOptimize(gm::particle_drag_coefficient(l, p.diameter, nu));
  benchmark::DoNotOptimize(gm::liquid_fluctuation_dissipation(l, p.diameter, nu, c.g0, T));
}

// Fixed ν = range(1)/1000 (inputs made opaque each iteration so nothing is hoisted).
void BM_FullEvaluationFixedNu(benchmark::State& state) {
  gm::CollisionalParameters p;
  gm::LiquidParameters l;
  configure(state, p, l);
  double nu = static_cast<double>(state.range(1)) / 1000.0;
  double T = 1e-3, shear_rate = 10.0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(nu);
    benchmark::DoNotOptimize(T);
    benchmark::DoNotOptimize(shear_rate);
    evaluate(p, l, nu, T, shear_rate);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_FullEvaluationFixedNu)->ArgsProduct({{0, 1, 2}, {10, 300, 500, 580}});

// ν varying every call over (0.005, 0.58) and T over 4 decades (branches of Torquato, Jenkins
// L and the guards change from call to call).
void BM_FullEvaluationVaryingNu(benchmark::State& state) {
  gm::CollisionalParameters p;
  gm::LiquidParameters l;
  configure(state, p, l);
  constexpr std::size_t count = 1024;
  std::array<double, count> nus{}, temperatures{};
  for (std::size_t i = 0; i < count; ++i) {
    nus[i] = 0.005 + 0.575 * static_cast<double>((i * 389) % count) / count;
    temperatures[i] = 1e-5 * static_cast<double>(1 + (i * 97) % 10000);
  }
  std::size_t i = 0;
  for (auto _ : state) {
    evaluate(p, l, nus[i], temperatures[i], 10.0);
    i = (i + 1) % count;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_FullEvaluationVaryingNu)->Arg(0)->Arg(1)->Arg(2);

}  // namespace

BENCHMARK_MAIN();
