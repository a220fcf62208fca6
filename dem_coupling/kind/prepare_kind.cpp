#include "dem_coupling/kind/prepare_kind.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "core/file_io.hpp"
#include "core/process.hpp"
#include "core/sweep_scheduler.hpp"
#include "dem_coupling/deck/preparation_deck.hpp"
#include "dem_coupling/dem_kind.hpp"
#include "dem_coupling/kind/dem_columns.hpp"
#include "dem_coupling/kind/launch.hpp"
#include "dem_coupling/kind/series_table.hpp"

namespace granflow::dem {

namespace {

// Columns of prepared.tsv reported in summary.json (prepared.KEY, short keys) and /prepared (one
// row per seed), named as dem_columns::preparation (driver/prepare_stage.cpp writes them).
constexpr const char* reported[] = {
    "phi",        "p",
    "sigma_yy",   "Z",
    "Z_nr",       "nonrattler_fraction",
    "fabric_xx",  "fabric_yy",
    "fabric_zz",  "fabric_xy",
    "fabric_xz",  "fabric_yz",
    "anisotropy", "energy_ratio",
    "overlap",    "lx",
    "particles",  "step",
};

// The dataset row of a preparation column (dem_columns::preparation); a column of neither keeps
// its own name without a unit.
core::Column preparation_column(const std::string& key) {
  if (const DemColumn* row = find_dem_column(dem_columns::preparation, key)) return row->column;
  return {nullptr, "1", nullptr};
}

core::Schema prepare_schema() {
  core::Schema s = core::kind_header(
      "dem_prepare", "",
      "A DEM packing at rest at the mean stress p0 (LIGGGHTS via granflow-dem): isotropic "
      "compression of a granular gas with the preparation friction μ_prep by a servo on the box, "
      "relaxation to rest; the state (φ0, p0, Z0, rattlers, fabric) is written for the kind: dem "
      "runs that start from it (start.preparation).");
  // The shear's material and run keys, one description for both (shear_schema), without the
  // contact friction (preparation.friction here; the shear's material.particle_friction there).
  const core::Schema shear = shear_schema();
  auto copy = [&](const std::string& section, const std::vector<std::string>& skip) {
    const core::Field* from = shear.child(section);
    core::Field to(from->key(), from->type(), from->unit(), from->doc());
    // The material has no defaults for its sizes: a missing section is a case error.
    if (from->is_required() || section == "material") to.required();
    for (const core::Field& child : from->children())
      if (std::find(skip.begin(), skip.end(), child.key()) == skip.end()) to.add(child);
    s.add(std::move(to));
  };
  copy("material", {"particle_friction"});
  copy("dem", {"compression_steps"});
  auto& prep = s.section("preparation", "the state to prepare and when it is at rest");
  prep.required();
  prep.number("pressure", "Pa", "target mean stress p0 = tr(σ)/3").required().greater_than(0);
  prep.number("friction", "",
              "contact friction during the preparation μ_prep (0: the densest random packing; "
              "the shearing friction: a loose one)")
      .default_value("0")
      .at_least(0);
  prep.number("tolerance", "", "prepared when |p - p0| <= tolerance × p0")
      .default_value("0.02")
      .greater_than(0)
      .at_most(0.5);
  prep.number("kinetic_energy_ratio", "",
              "prepared when the kinetic energy (translation + rotation) <= ratio × the elastic "
              "energy of the contacts")
      .default_value("1e-4")
      .greater_than(0);
  prep.number("compression_inertial_number", "",
              "largest compression rate ε̇ of the box edges as ε̇ d / sqrt(p0/ρ_p) (faster "
              "compressions of frictional spheres give looser packings)")
      .default_value("0.01")
      .greater_than(0)
      .at_most(1);
  prep.integer("update_every", "time steps between servo updates").default_value("50").at_least(1);
  prep.integer("settle", "consecutive servo updates that must meet both criteria")
      .default_value("5")
      .at_least(1);
  prep.integer("max_steps", "time steps after which a preparation not at rest fails (exit 3)")
      .default_value("2000000")
      .at_least(1)
      .limited_by("max_steps");
  auto& statistics = s.section("statistics", "several packings");
  statistics
      .integer("seeds",
               "prepares packings for dem.seed, dem.seed + 1, ..., dem.seed + N - 1 (seed_S/ "
               "directories; a kind: dem run with statistics.seeds N starts seed S from seed_S)")
      .default_value("1")
      .at_least(1)
      .at_most(64);
  return s;
}

PreparationParams read_preparation(const core::Case& c, long seed) {
  PreparationParams p;
  // The shear reader fills the material and run keys; the shear-only keys keep their defaults.
  ShearDeckParams& g = p.sample;
  g.material = read_dem_material(c, c.number("preparation.friction"));
  g.particles = c.integer("dem.particles");
  g.seed = static_cast<unsigned long>(seed);
  g.dt_safety = c.number("dem.time_step_safety");
  g.impact_speed_factor = c.number("dem.impact_speed_factor");
  p.pressure = c.number("preparation.pressure");
  p.tolerance = c.number("preparation.tolerance");
  p.energy_ratio = c.number("preparation.kinetic_energy_ratio");
  p.compression_inertial_number = c.number("preparation.compression_inertial_number");
  p.update_every = c.integer("preparation.update_every");
  p.settle = c.integer("preparation.settle");
  p.max_steps = c.integer("preparation.max_steps");
  return p;
}

void check_prepare(const core::Case& c) {
  if (c.string("material.contact_law") == "hooke" && !c.has("material.normal_stiffness"))
    c.fail("material.normal_stiffness",
           "missing required key for contact_law: hooke; expected k_n > 0 [N/m]");
  if (c.integer("preparation.settle") * c.integer("preparation.update_every") >
      c.integer("preparation.max_steps"))
    c.fail("preparation.max_steps", "at least preparation.settle × preparation.update_every");
  // The box at the densest φ a preparation reaches (max_solid_fraction) must hold 4 d_max.
  ShearDeckParams g = read_preparation(c, c.integer("dem.seed")).sample;
  g.solid_fraction = max_solid_fraction;
  for (const auto& [path, expected] : check_shear_params(g))
    if (path.rfind("material.", 0) == 0 || path.rfind("dem.", 0) == 0) c.fail(path, expected);
}

int run_prepare(core::RunContext& ctx) {
  const core::Case& c = ctx.run_case;
  const long seeds = c.integer("statistics.seeds");
  const long first_seed = c.integer("dem.seed");
  const int ranks = static_cast<int>(c.integer("dem.ranks"));
  int code = core::exit_ok;
  std::vector<std::map<std::string, double>> prepared;
  auto compute = [&](const core::ConditionContext& cc) {
    const long seed = first_seed + long(cc.index);
    const PreparationParams p = read_preparation(c, seed);
    const PreparationDeck deck = make_preparation_deck(p, "particles.data");
    const auto dir = prepared_seed_directory(cc.run_directory, seed);
    std::filesystem::create_directories(dir);
    core::write_text_file(dir / "in.granflow", deck.deck);
    core::write_text_file(dir / "particles.data", deck.data);
    const auto command = driver_command(ranks, "in.granflow");
    cc.log->info(
        "seed {}: {} particles, μ_prep = {:g}, to p0 = {:g} Pa (±{:g} %), at rest when "
        "kinetic/elastic energy <= {:g}; Δt = {:.4g} s, compression at most ε̇ = {:.4g} 1/s; "
        "rerun by hand: cd {} && {} > liggghts.out 2>&1",
        seed, p.sample.particles, p.sample.material.particle_friction, p.pressure,
        100.0 * p.tolerance, p.energy_ratio, deck.sample.dt, deck.max_rate,
        core::shell_quote(dir.string()), core::shell_line(command));
    const auto t0 = std::chrono::steady_clock::now();
    const int status = run_in_directory(command, dir, dir / "liggghts.out", [] {});
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return core::Packer().integer(status).number(wall).take();
  };
  auto absorb = [&](std::size_t n, const std::string& bytes) {
    const long seed = first_seed + long(n);
    const auto dir = prepared_seed_directory(ctx.directory.path(), seed);
    core::Unpacker packed(bytes);
    const int status = static_cast<int>(packed.integer());
    const double wall = packed.number();
    const std::string group = fmt::format("/seeds/{}", n);
    const SeriesTable history = read_series_table(dir / "prepare.tsv");
    for (const std::string& key : history.names) {
      const core::Column column = preparation_column(key);
      ctx.result.write(group + "/series/" + (column.name ? column.name : key), history.at(key),
                       column.unit,
                       std::string(column.description ? column.description : key) +
                           " (preparation history, one row per servo update)");
    }
    ctx.result.attribute(group, "seed", double(seed));
    ctx.summary.set(fmt::format("cost.seed_wall_s.{}", n), wall);
    std::map<std::string, double> row;
    if (status == 0) {
      const SeriesTable t = read_series_table(dir / "prepared.tsv");
      for (const char* name : reported)
        if (t.rows() == 1 && t.columns.count(name)) row[name] = t.at(name)[0];
    }
    if (row.empty()) {
      const std::string error = first_error_line(dir / "liggghts.out");
      ctx.log->error("seed {}: granflow-dem exited with status {}: {} (full output in {})", seed,
                     status, error.empty() ? "(no ERROR line)" : error,
                     (dir / "liggghts.out").string());
      if (code == core::exit_ok) code = status == 3 ? core::exit_numerical : core::exit_external;
    } else {
      ctx.log->info(
          "seed {}: prepared in {:.0f} steps ({:.1f} s): φ0 = {:.4f}, p0 = {:.4g} Pa, σ_yy = "
          "{:.4g} Pa, Z = {:.3f}, Z* = {:.3f} (non-rattlers {:.3f}), fabric anisotropy {:.3g}, "
          "kinetic/elastic energy {:.2g}",
          seed, row["step"], wall, row["phi"], row["p"], row["sigma_yy"], row["Z"], row["Z_nr"],
          row["nonrattler_fraction"], row["anisotropy"], row["energy_ratio"]);
      if (seeds > 1)
        for (const auto& [name, value] : row)
          ctx.summary.set(fmt::format("prepared.{}.{}", name, n), value);
    }
    prepared.push_back(row);
  };
  if (!core::run_conditions(ctx, std::size_t(seeds), compute, absorb)) return core::exit_ok;
  // /prepared: one row per seed; summary: the mean over the seeds and its standard error
  // (between-seed standard deviation / sqrt(N); 0 for one seed).
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const char* name : reported) {
    std::vector<double> column;
    double sum = 0.0, sum2 = 0.0, count = 0.0;
    for (const auto& row : prepared) {
      const auto it = row.find(name);
      column.push_back(it == row.end() ? nan : it->second);
      if (it == row.end()) continue;
      sum += it->second;
      sum2 += it->second * it->second;
      count += 1.0;
    }
    const core::Column named = preparation_column(name);
    ctx.result.write(std::string("/prepared/") + named.name, column, named.unit, named.description);
    if (count == 0.0) continue;
    const double mean = sum / count;
    const double var =
        count > 1.0 ? std::max(0.0, (sum2 - count * mean * mean) / (count - 1.0)) : 0.0;
    ctx.summary.set(std::string("prepared.") + name, mean);
    ctx.summary.set(std::string("prepared.") + name + "_err", std::sqrt(var / count));
  }
  ctx.result.attribute("/prepared", "target_pressure", c.number("preparation.pressure"));
  ctx.result.attribute("/prepared", "friction", c.number("preparation.friction"));
  ctx.summary.set("prepared.target_pressure", c.number("preparation.pressure"));
  ctx.summary.set("prepared.friction", c.number("preparation.friction"));
  ctx.summary.set("prepared.tolerance", c.number("preparation.tolerance"));
  ctx.summary.set("prepared.kinetic_energy_ratio_max",
                  c.number("preparation.kinetic_energy_ratio"));
  ctx.summary.set("prepared.seeds", double(seeds));
  ctx.result.flush();
  return code;
}

}  // namespace

std::filesystem::path prepared_seed_directory(const std::filesystem::path& run_dir, long seed) {
  return run_dir / fmt::format("seed_{}", seed);
}

void register_prepare_kind(core::KindRegistry& registry) {
  core::KindEntry entry{"dem_prepare",
                        "",
                        "DEM packing at rest at a mean stress p0 (loose or dense by the "
                        "preparation friction), the start of transient kind: dem runs",
                        prepare_schema(),
                        check_prepare,
                        run_prepare,
                        "cases/dem/prepare_loose.yaml"};
  entry.distributes_conditions = true;
  registry.add(std::move(entry));
}

}  // namespace granflow::dem
