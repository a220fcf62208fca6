// Wall-clock timing of granflow-dem on a generated Lees-Edwards shear deck.
//   bench_dem_timing [PARTICLES] [STRAIN] [REPEATS]   (defaults 2000 2 2)
// For 1 and 2 ranks: particle-steps/s of the shear stage (LIGGGHTS time from the driver), and
// the harness overhead = (sampled run: LIGGGHTS + harness time) / (unsampled run: one `run`)
// - 1, where the sampled run samples every 0.01 strain (the case default). Best of REPEATS.
#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "core/process.hpp"
#include "dem_coupling/deck/shear_deck.hpp"
#include "dem_coupling/kind/series_table.hpp"

namespace {

struct Timing {
  double liggghts_s = 0, harness_s = 0, particle_steps_per_s = 0;
  long steps = 0, samples = 0;
};

Timing run(const std::filesystem::path& dir, const granflow::dem::ShearDeck& deck, int ranks) {
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "in.granflow") << deck.deck;
  std::ofstream(dir / "particles.data") << deck.data;
  // Started from an argument vector (core/process.hpp), no shell.
  std::vector<std::string> argv;
  if (ranks > 1) argv = {"mpirun", "--oversubscribe", "--allow-run-as-root", "-np", std::to_string(ranks)};
  argv.insert(argv.end(), {GRANFLOW_DEM_DRIVER_PATH, "in.granflow", "-log", "none"});
  granflow::core::ProcessOptions options;
  options.directory = dir;
  options.output = dir / "out.txt";
  const auto result = granflow::core::run_process(argv, options);
  if (!result.ok()) {
    std::fprintf(stderr, "granflow-dem failed (%s), see %s/out.txt\n", result.error.c_str(),
                 dir.c_str());
    std::exit(1);
  }
  const auto stats = granflow::dem::read_series_table(dir / "driver_stats.tsv");
  Timing t;
  t.liggghts_s = stats.at("liggghts_s")[0];
  t.harness_s = stats.at("harness_s")[0];
  t.particle_steps_per_s = stats.at("particle_steps_per_s")[0];
  t.steps = long(stats.at("steps")[0]);
  t.samples = long(stats.at("samples")[0]);
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  const long particles = argc > 1 ? std::atol(argv[1]) : 2000;
  const double strain = argc > 2 ? std::atof(argv[2]) : 2.0;
  const int repeats = argc > 3 ? std::atoi(argv[3]) : 2;
  granflow::dem::ShearDeckParams p;
  p.particles = particles;
  p.shear_rate = 50.0;
  p.solid_fraction = 0.55;
  p.total_strain = strain;
  p.sample_strain = 0.01;
  const auto sampled = granflow::dem::make_shear_deck(p, "particles.data");
  // Unsampled: one chunk (a single `run` of all shear steps, one sample at the end).
  p.sample_strain = strain * 0.999;
  auto unsampled = granflow::dem::make_shear_deck(p, "particles.data");
  const auto root = std::filesystem::temp_directory_path() / "granflow-bench-dem";
  std::printf(
      "| ranks | particles | shear steps | samples | LIGGGHTS s | harness s | "
      "particle-steps/s | unsampled LIGGGHTS s | harness overhead |\n"
      "|---|---|---|---|---|---|---|---|---|\n");
  for (int ranks : {1, 2}) {
    Timing best_s, best_u;
    double best_total = std::numeric_limits<double>::infinity();
    double best_plain = std::numeric_limits<double>::infinity();
    for (int k = 0; k < repeats; ++k) {
      const Timing s = run(root / fmt::format("np{}_sampled_{}", ranks, k), sampled, ranks);
      const Timing u = run(root / fmt::format("np{}_plain_{}", ranks, k), unsampled, ranks);
      if (s.liggghts_s + s.harness_s < best_total) {
        best_total = s.liggghts_s + s.harness_s;
        best_s = s;
      }
      if (u.liggghts_s + u.harness_s < best_plain) {
        best_plain = u.liggghts_s + u.harness_s;
        best_u = u;
      }
    }
    std::printf("| %d | %ld | %ld | %ld | %.3f | %.4f | %.3g | %.3f | %+.1f %% |\n", ranks,
                particles, best_s.steps, best_s.samples, best_s.liggghts_s, best_s.harness_s,
                best_s.particle_steps_per_s, best_plain, 100.0 * (best_total / best_plain - 1.0));
  }
  return 0;
}
