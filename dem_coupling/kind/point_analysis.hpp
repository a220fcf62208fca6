// Analysis of one DEM point (dem_kind.cpp): the series granflow-dem wrote (series.tsv,
// profile.tsv) into result.h5 under `group`, then the steady values with their standard errors
// and the steadiness checks (kind/steady_checks.hpp) as PointResult::values, the names of
// summary.json without the "steady." prefix (docs/dem_dataset.md).
//   start: the latest MSER-5 truncation of σ_yy, τ, φ, T (statistics/steady_state.hpp);
//   means and standard errors: statistics::correlated_mean of series[start:];
//   μ = <τ>/<σ_yy>, its error that of the linearised residual τ − μ σ_yy over <σ_yy> (delta
//   method); I from <σ_yy>, e from <φ> (kind/steady_checks.hpp, steady_window);
//   strain.target_error: the achieved errors against the targets (steady_checks.hpp,
//   target_status) on the whole series, i.e. the values granflow-dem stopped on.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/run.hpp"
#include "dem_coupling/deck/shear_deck.hpp"
#include "dem_coupling/kind/seed_statistics.hpp"

namespace granflow::dem {

struct PointResult {
  std::map<std::string, double> values;  // summary names without "steady." prefix
  // strain.target_error only: the run length and the errors against the targets, summary names
  // without the "strain." prefix: used, max, target_met, and per observable with a target
  // target_error.NAME, achieved_error.NAME, target_met.NAME (NAME of target_observables).
  std::map<std::string, double> run_length;
  std::vector<std::string> notes;     // for the log (targets met)
  std::vector<std::string> warnings;  // for the log (not steady, off the target, target missed)
  double steps = 0, dt = 0, particles = 0, wall = 0, particle_steps_per_s = 0;
};

PointResult analyse_point(core::RunContext& ctx, const std::filesystem::path& dir,
                          const std::string& group, const ShearDeckParams& p,
                          const ShearDeck& deck);

// A sweep over dem.seed: per group of conditions that differ only in the seed, the mean over the
// seeds and its between-seed standard error of μ, φ, e, T, σ_yy, p, τ, I, Z
// (kind/seed_statistics.hpp) to summary.json (seeds.NAME.G, seeds.NAME_err.G,
// seeds.NAME_scatter_ratio.G, seeds.count.G), result.h5 (/seeds, one row per group) and the log.
// `results` are in condition order; nothing is written when `groups` is empty.
void write_seed_statistics(core::RunContext& ctx, const std::vector<SeedGroup>& groups,
                           const std::vector<PointResult>& results);

}  // namespace granflow::dem
