// granflow-dem: runs a granflow shear deck in Debian's LIGGGHTS 3.8.0 and samples the
// extraction harness.
//
//   granflow-dem DECK [--series FILE] [--profile FILE] [--stats FILE] [LIGGGHTS options]
//   (LIGGGHTS options: -log FILE, -screen none, -echo ..., -var NAME VALUE ...)
//
// 1. constructs the LIGGGHTS instance and applies the triclinic workaround (liggghts_access.cpp)
//    and registers granflow's own fix styles (fix_styles.cpp);
// 2. reads DECK (sample preparation; defines the gf_* parameters and fix gf_shear);
//    A preparation deck (gf_prepare_pressure; deck/preparation_deck.hpp) runs the preparation
//    stage instead (driver/prepare_stage.hpp) and stops;
// 2b. adds the starting velocity fluctuations: Gaussian, granular temperature
//    gf_initial_temperature about the streaming profile, zero total momentum (add_fluctuations);
// 3. runs the shear stage in chunks of gf_sample_every steps (`run N start S stop E pre no`,
//    so fix deform's tilt stays continuous inside a segment) and after each chunk samples
//    the atom arrays through the instance (lammps_extract_atom, the pair's neighbour list) and
//    the contact virial and the contact network (driver/contact_probe.hpp: Z without rattlers,
//    fabric), reduces the sums over ranks (one MPI_Allreduce) and rank 0 appends a
//    row to the series file (flushed, so a run stopped by an error keeps what it wrote). The
//    virial is the mean over every step of the chunk when the deck defines fix gf_stress
//    (ave/time 1 n n over compute gf_virial; dry decks), else compute gf_virial at the sample's
//    step; the kinetic part, T, φ and Z are taken at the sample's step;
// 4. under constant normal stress, every gf_servo_every steps rescales the box height with
//    NormalStressServo (dry: with the carry of the clipped demand, so that it holds the mean
//    σ_yy): fix gf_shear is redefined with `y final` for the next segment. With
//    gf_servo_move_every = M > 0 (immersed decks) the height moves during the first M steps of
//    the segment and is then held (fix gf_shear back to `xy erate` only), and the servo averages
//    σ_yy over the held part only: in a viscous suspension σ_yy responds at once to the dilation
//    rate (lubrication and drag resist it), so a stress measured while the box moves is biased
//    by -η_n ε̇ and the loop locks into a period-2 cycle (docs/dem_fluid.md, servo).
// 4b. with gf_drainage_length or gf_height_resistance (a drained or damped shear), fix drainage
//    holds the total σ_yy = gf_normal_stress every step and fix gf_shear is reissued at every
//    sample (its tilt rate follows the height); with gf_rate_step_steps the shear rate steps to
//    gf_rate_step_shear_rate there (driver/shear_schedule.hpp: the profile's change added);
// 5. with gf_check_every in the deck (strain.target_error), every gf_check_every steps rank 0
//    evaluates the steady window and its errors on the series so far (stopping_rule.hpp, the
//    kind's own functions), broadcasts the decision, and the shear stops once the targets have
//    been met at gf_confirm_checks consecutive checks; else it runs to gf_total_steps
//    (strain.max). The shear is then run in segments of gf_check_every steps at constant volume
//    (of gf_servo_every steps under the servo, as without targets), so a stopped run is step for
//    step the start of a fixed run of its length under the servo.
// Exit codes: 0 ok, 1 LIGGGHTS error (LIGGGHTS exits itself), 2 bad arguments/deck,
// 3 numerical failure (NaN/Inf or negative T in a sample).
#include <mpi.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <optional>
#include <string>
#include <vector>

#include "dem_coupling/deck/driver_parameters.hpp"
#include "dem_coupling/driver/atom_view.hpp"
#include "dem_coupling/driver/contact_probe.hpp"
#include "dem_coupling/driver/initial_fluctuations.hpp"
#include "dem_coupling/driver/prepare_stage.hpp"
#include "dem_coupling/driver/sample_parts.hpp"
#include "dem_coupling/driver/series_output.hpp"
#include "dem_coupling/driver/shear_schedule.hpp"
#include "dem_coupling/driver/shear_stop.hpp"
#include "dem_coupling/driver/stopping_rule.hpp"
#include "dem_coupling/extraction/normal_stress_servo.hpp"
#include "dem_coupling/extraction/shear_sample.hpp"
#include "dem_coupling/extraction/snapshots.hpp"
#include "dem_coupling/fix_styles.hpp"
#include "dem_coupling/fixes/fix_fluid_le.hpp"
#include "dem_coupling/liggghts_access.hpp"
#include "domain.h"
#include "force.h"
#include "lammps.h"
#include "library.h"
#include "lmptype.h"
#include "modify.h"
#include "neigh_list.h"
#include "pair.h"
#include "update.h"

namespace {

using granflow::dem::ShearSample;
using granflow::dem::write_profile_row;
using granflow::dem::write_series_header;
using granflow::dem::write_series_row;
using Clock = std::chrono::steady_clock;

struct Options {
  std::string deck;
  std::string series = "series.tsv";
  std::string profile = "profile.tsv";
  std::string stats = "driver_stats.tsv";
  std::vector<std::string> liggghts_args{"granflow-dem"};
};

// CPU time of this process (s): the cost measure that a loaded machine disturbs least.
double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

[[noreturn]] void usage_error(int rank, const std::string& message) {
  if (rank == 0) std::fprintf(stderr, "ERROR: granflow-dem: %s\n", message.c_str());
  MPI_Finalize();
  std::exit(2);
}

Options parse(int argc, char** argv, int rank) {
  Options o;
  if (argc < 2 || argv[1][0] == '-')
    usage_error(rank,
                "usage: granflow-dem DECK [--series F] [--profile F] [--stats F] "
                "[LIGGGHTS options]  |  granflow-dem --header NAME=VALUE ...");
  o.deck = argv[1];
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage_error(rank, "option " + a + " needs a value");
      return argv[++i];
    };
    if (a == "--series")
      o.series = value();
    else if (a == "--profile")
      o.profile = value();
    else if (a == "--stats")
      o.stats = value();
    else
      o.liggghts_args.push_back(a);  // -log F, -screen none, -var N V, ... go to LIGGGHTS
  }
  return o;
}

// An equal-style variable of the deck; missing variables are a deck error.
double deck_variable(void* handle, const char* name, int rank) {
  void* p = lammps_extract_variable(handle, const_cast<char*>(name), nullptr);
  if (p == nullptr) usage_error(rank, std::string("deck does not define variable ") + name);
  double* value = static_cast<double*>(p);
  const double v = *value;
  std::free(value);  // equal-style values are malloc'ed by library.cpp
  return v;
}

// An optional equal-style variable of the deck: its value, or `absent` when the deck has none.
double optional_deck_variable(void* handle, const char* name, double absent) {
  void* p = lammps_extract_variable(handle, const_cast<char*>(name), nullptr);
  if (p == nullptr) return absent;
  const double v = *static_cast<double*>(p);
  std::free(p);
  return v;
}

// Entry k (0-based) of fix gf_stress's global vector: the interval-mean contact virial P^vir_k
// (xx yy zz xy xz yz). The value is malloc'ed by library.cpp.
double stress_average_entry(void* handle, int k) {
  double* value = static_cast<double*>(lammps_extract_fix(handle, "gf_stress", 0, 1, k, 0));
  const double v = *value;
  std::free(value);
  return v;
}

// Stops the run (all ranks see the same global sample) with exit code 3.
void check_sample(const ShearSample& s, int rank) {
  const std::pair<const char*, double> checked[] = {{"sigma_yy", s.normal_stress},
                                                    {"tau", s.shear_stress},
                                                    {"T", s.temperature},
                                                    {"phi", s.solid_fraction},
                                                    {"Z", s.coordination}};
  for (const auto& [name, value] : checked) {
    if (std::isfinite(value) && !(std::string(name) == "T" && value < 0.0)) continue;
    if (rank == 0)
      std::fprintf(stderr,
                   "ERROR: granflow-dem: numerical failure at step %ld (strain %.4g), whole "
                   "sample: %s = %g\n",
                   s.step, s.strain, name, value);
    MPI_Finalize();
    std::exit(3);
  }
}

}  // namespace

int main(int argc, char** argv) {
  // granflow-dem --header NAME=VALUE ...: the deck header this program reads, for hand-written
  // decks (bench/dem_fluid_bench.py), from the one definition the deck writer uses.
  if (argc >= 2 && std::string(argv[1]) == "--header") {
    try {
      const auto p = granflow::dem::driver_parameters_from_words({argv + 2, argv + argc});
      std::fputs(
          (granflow::dem::driver_parameter_lines(p) + granflow::dem::granular_atom_setup()).c_str(),
          stdout);
      return 0;
    } catch (const std::invalid_argument& e) {
      std::fprintf(stderr, "granflow-dem --header: %s\n", e.what());
      return 2;
    }
  }
  MPI_Init(&argc, &argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  Options opt = parse(argc, argv, rank);

  std::vector<char*> largv;
  for (auto& a : opt.liggghts_args) largv.push_back(a.data());
  void* handle = nullptr;
  lammps_open(static_cast<int>(largv.size()), largv.data(), MPI_COMM_WORLD, &handle);
  auto* lmp = static_cast<LAMMPS_NS::LAMMPS*>(handle);
  granflow::dem::apply_triclinic_workaround(*lmp);
  granflow::dem::register_custom_fix_styles(*lmp);

  if (rank == 0) {
    if (std::FILE* probe = std::fopen(opt.deck.c_str(), "r"))
      std::fclose(probe);
    else
      usage_error(rank, "cannot open deck " + opt.deck);
  }
  lammps_file(handle, opt.deck.c_str());
  // Preparation decks (deck/preparation_deck.hpp): the preparation stage instead of the shear.
  if (void* p =
          lammps_extract_variable(handle, const_cast<char*>("gf_prepare_pressure"), nullptr)) {
    std::free(p);
    const int code = granflow::dem::run_preparation(handle, *lmp, rank);
    lammps_close(handle);
    MPI_Finalize();
    return code;
  }

  // Optional (decks before the starting-state keys have none): the starting fluctuations.
  if (void* p =
          lammps_extract_variable(handle, const_cast<char*>("gf_initial_temperature"), nullptr)) {
    const double t0 = *static_cast<double*>(p);
    std::free(p);
    const auto seed =
        static_cast<std::uint64_t>(std::llround(deck_variable(handle, "gf_velocity_seed", rank)));
    if (!(t0 >= 0.0) || !std::isfinite(t0))
      usage_error(rank, "deck: gf_initial_temperature must be finite and >= 0");
    const double applied = granflow::dem::add_fluctuations(handle, t0, seed);
    if (rank == 0)
      std::printf(
          "granflow-dem: shear starts from the streaming profile + fluctuations of T0 = "
          "%.6g m^2/s^2 (zero total momentum)\n",
          applied);
  }

  const double shear_rate = deck_variable(handle, "gf_shear_rate", rank);
  const long total_steps = std::lround(deck_variable(handle, "gf_total_steps", rank));
  const long sample_every = std::lround(deck_variable(handle, "gf_sample_every", rank));
  const bool constant_pressure = deck_variable(handle, "gf_constant_pressure", rank) != 0.0;
  const long servo_every = std::lround(deck_variable(handle, "gf_servo_every", rank));
  const int bins = static_cast<int>(std::lround(deck_variable(handle, "gf_profile_bins", rank)));
  const double particle_density = deck_variable(handle, "gf_particle_density", rank);
  bool wet = false;
  if (void* p = lammps_extract_variable(handle, const_cast<char*>("gf_viscosity"), nullptr)) {
    wet = true;
    std::free(p);
  }
  // optional: 0 = move over the whole segment
  const long servo_move_every =
      std::lround(optional_deck_variable(handle, "gf_servo_move_every", 0.0));
  std::optional<granflow::dem::NormalStressServo> servo;
  if (constant_pressure)
    servo.emplace(deck_variable(handle, "gf_normal_stress", rank),
                  deck_variable(handle, "gf_servo_gain", rank),
                  deck_variable(handle, "gf_servo_max_strain", rank),
                  wet ? 0.0 : 50.0);  // carry of the clipped demand: dry only (the servo's header)
  if (sample_every < 1 || total_steps < sample_every || (servo && servo_every % sample_every))
    usage_error(rank,
                "deck: need 1 <= gf_sample_every <= gf_total_steps and gf_servo_every a "
                "multiple of gf_sample_every");
  if (servo_move_every < 0 || servo_move_every % sample_every ||
      (servo_move_every > 0 && servo_move_every >= servo_every))
    usage_error(rank,
                "deck: gf_servo_move_every must be 0 or a multiple of gf_sample_every below "
                "gf_servo_every");
  // Optional (strain.target_error): the targets, the check interval and (d γ̇)² of the frozen
  // check (deck/driver_parameters.hpp); checks end on segment ends.
  std::optional<granflow::dem::StoppingRule> rule;
  long check_every = 0;
  if (void* p = lammps_extract_variable(handle, const_cast<char*>("gf_check_every"), nullptr)) {
    check_every = std::lround(*static_cast<double*>(p));
    std::free(p);
    granflow::dem::ErrorTargets targets;
    for (std::size_t k = 0; k < targets.error.size(); ++k)
      targets.error[k] = deck_variable(
          handle, ("gf_target_" + std::string(granflow::dem::target_observables[k])).c_str(), rank);
    targets.confirm_checks = int(std::lround(deck_variable(handle, "gf_confirm_checks", rank)));
    if (targets.confirm_checks < 1) usage_error(rank, "deck: gf_confirm_checks must be >= 1");
    rule.emplace(targets, deck_variable(handle, "gf_temperature_scale", rank));
    if (check_every < 1 || check_every % (servo ? servo_every : sample_every))
      usage_error(rank,
                  "deck: gf_check_every must be a multiple of gf_servo_every (servo) or of "
                  "gf_sample_every");
  }
  // Optional: a step in the shear rate (driver/shear_schedule.hpp), and the total σ_yy =
  // gf_normal_stress held every step by fix drainage: drained over gf_drainage_length, or a
  // damped height of resistance gf_height_resistance (k = 1/R; dry decks too).
  const granflow::dem::ShearSchedule schedule{
      shear_rate, std::lround(optional_deck_variable(handle, "gf_rate_step_steps", 0.0)),
      optional_deck_variable(handle, "gf_rate_step_shear_rate", 0.0)};
  const double shear_drainage_length = optional_deck_variable(handle, "gf_drainage_length", 0.0);
  const double height_resistance = optional_deck_variable(handle, "gf_height_resistance", 0.0);
  const bool drained = shear_drainage_length > 0.0 || height_resistance > 0.0;
  if (schedule.has_step() && (servo || rule || schedule.step_steps % sample_every ||
                              schedule.step_steps >= total_steps || !(schedule.step_rate > 0.0)))
    usage_error(rank,
                "deck: gf_rate_step_steps must be a multiple of gf_sample_every below "
                "gf_total_steps, gf_rate_step_shear_rate > 0, without the servo or "
                "gf_check_every");
  if (drained && (servo || rule || (shear_drainage_length > 0.0 && !wet) ||
                  (shear_drainage_length > 0.0 && height_resistance > 0.0)))
    usage_error(rank,
                "deck: gf_drainage_length (an immersed deck: gf_viscosity) or "
                "gf_height_resistance, not both, without the servo or gf_check_every");
  if (lmp->force->pair == nullptr) usage_error(rank, "deck defines no pair style");
  if (wet && lmp->modify->find_fix("gf_fluid") < 0)
    usage_error(rank, "deck defines gf_viscosity but no fix gf_fluid (fluid/le)");
  // Dry decks define `fix gf_stress all ave/time 1 n n c_gf_virial[1..6]` (n = gf_sample_every):
  // the contact virial averaged over every step of the interval that ends at each sample, read
  // instead of the instant (and so also by the servo). Its windows end on multiples of n.
  const bool averaged_virial = lmp->modify->find_fix("gf_stress") >= 0;
  if (averaged_virial && lmp->update->ntimestep % sample_every != 0)
    usage_error(rank,
                "deck: fix gf_stress (ave/time) needs the shear to start on a multiple of "
                "gf_sample_every");

  std::FILE* series = nullptr;
  std::FILE* profile = nullptr;
  if (rank == 0) {
    series = std::fopen(opt.series.c_str(), "w");
    profile = std::fopen(opt.profile.c_str(), "w");
    if (!series || !profile) usage_error(rank, "cannot write " + opt.series + " / " + opt.profile);
    write_series_header(series, wet);
    std::fprintf(profile,
                 "# mean v_x (m/s) in %d y bins of equal height; columns: step strain "
                 "bin_0 ... bin_%d\n",
                 bins, bins - 1);
  }

  if (const double overlap = granflow::dem::mean_overlap(handle, *lmp); rank == 0)
    std::printf(
        "granflow-dem: shear starts at mean overlap <delta> = %.6g m of the touching pairs\n",
        overlap);

  granflow::dem::SampleSums local(bins), global(bins);
  const double dt = lmp->update->dt;
  const long shear_begin = lmp->update->ntimestep;
  // Segments: one per servo interval, check interval, sample (drained: fix gf_shear follows the
  // box height), or the parts before and after a rate step.
  const long segment_steps = servo                 ? servo_every
                             : rule                ? check_every
                             : drained             ? sample_every
                             : schedule.has_step() ? schedule.step_steps
                                                   : total_steps;
  double liggghts_seconds = 0.0, harness_seconds = 0.0, liggghts_cpu_seconds = 0.0;
  long samples = 0;
  double segment_normal_stress = 0.0;
  int segment_samples = 0;
  char command[512];

  // One sample of the harness after a run: the sums over ranks, the row of the series. `rate`:
  // the streaming profile's γ̇ (0 once the shear is stopped); the strain of a sample of the stop
  // stage is the strain at the stop, `strain_end` its step.
  auto sample = [&](double rate, long strain_end) -> ShearSample {
    local.clear();
    const granflow::dem::ParticleView view = granflow::dem::owned_particles(handle);
    const LAMMPS_NS::Domain& domain = *lmp->domain;
    const granflow::dem::ShearFrame frame{rate, domain.boxlo[1], domain.yprd};
    granflow::dem::accumulate_particles(view, frame, local);
    if (const LAMMPS_NS::NeighList* list = lmp->force->pair->list) {
      granflow::dem::HalfNeighborList half{list->inum, list->ilist, list->numneigh,
                                           list->firstneigh, NEIGHMASK};
      granflow::dem::accumulate_contacts(half, view.position, view.radius, view.count, local);
    }
    MPI_Allreduce(local.data(), global.data(), local.size(), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    std::array<double, 6> virial_stress{};
    if (averaged_virial) {
      for (int k = 0; k < 6; ++k) virial_stress[k] = stress_average_entry(handle, k);
    } else {
      const auto* virial = static_cast<double*>(lammps_extract_compute(handle, "gf_virial", 0, 1));
      if (virial == nullptr) usage_error(rank, "deck defines no compute gf_virial (pressure)");
      for (int k = 0; k < 6; ++k) virial_stress[k] = virial[k];
    }
    const granflow::dem::BoxState box{domain.xprd, domain.yprd, domain.zprd, domain.xy};
    ShearSample s =
        granflow::dem::finalize_sample(global, virial_stress, box, frame, particle_density);
    s.step = lmp->update->ntimestep;
    s.time = double(s.step - shear_begin) * dt;
    s.strain = schedule.strain_after((rate > 0.0 ? s.step : strain_end) - shear_begin, dt);
    check_sample(s, rank);
    const double overlap = granflow::dem::mean_overlap(handle, *lmp);
    // Z without rattlers, the non-rattler fraction and the fabric (contact_probe.hpp)
    const granflow::dem::NetworkState network =
        granflow::dem::probe_contacts(handle, *lmp, {}).network;
    granflow::dem::FluidStress fluid;
    if (wet) fluid = granflow::dem::fluid_stress(handle, s);
    if (rank == 0) {
      write_series_row(series, s, overlap, network, wet ? &fluid : nullptr);
      write_profile_row(profile, s);
    }
    ++samples;
    return s;
  };

  // A LIGGGHTS run command, its wall and CPU time added to the run's; returns when it ended.
  auto run_timed = [&](char* run_command) {
    const auto t0 = Clock::now();
    const double cpu0 = process_cpu_seconds();
    lammps_command(handle, run_command);
    liggghts_cpu_seconds += process_cpu_seconds() - cpu0;
    const auto t1 = Clock::now();
    liggghts_seconds += std::chrono::duration<double>(t1 - t0).count();
    return t1;
  };

  bool height_commanded = false;  // fix gf_shear moves the height (from the last servo update)
  long done = 0;                  // shear steps run
  if (drained) {
    const double sigma_n = deck_variable(handle, "gf_normal_stress", rank);
    if (shear_drainage_length > 0.0)
      std::snprintf(command, sizeof command,
                    "fix gf_drain all drainage %.17g gf_virial darcy %.17g gf_fluid", sigma_n,
                    shear_drainage_length);
    else
      std::snprintf(command, sizeof command,
                    "fix gf_drain all drainage %.17g gf_virial resistance %.17g", sigma_n,
                    height_resistance);
    lammps_command(handle, command);
    if (rank == 0)
      std::printf("granflow-dem: sigma_yy = %.6g Pa held every step: %s %.4g %s\n", sigma_n,
                  shear_drainage_length > 0.0 ? "drained over" : "damped height, resistance",
                  shear_drainage_length > 0.0 ? shear_drainage_length : height_resistance,
                  shear_drainage_length > 0.0 ? "m" : "Pa s");
  }
  while (done < total_steps) {
    if (schedule.has_step() && done == schedule.step_steps) {
      granflow::dem::step_shear_rate(handle, *lmp, schedule.rate, schedule.step_rate);
      if (rank == 0)
        std::printf("granflow-dem: shear rate %.6g -> %.6g 1/s at step %ld (strain %.6g)\n",
                    schedule.rate, schedule.step_rate, shear_begin + done,
                    schedule.strain_after(done, dt));
    } else if (drained && done > 0) {
      granflow::dem::define_shear(handle, schedule.rate_after(done));  // at the current height
    }
    const long segment_begin = shear_begin + done;
    const long segment_end = segment_begin + std::min(segment_steps, total_steps - done);
    // Move-then-hold: [segment_begin, move_end) with the height moving, the rest held.
    const long move_end = height_commanded && servo_move_every > 0
                              ? std::min(segment_begin + servo_move_every, segment_end)
                              : segment_begin;
    for (int phase = 0; phase < 2; ++phase) {
      const long phase_begin = phase == 0 ? segment_begin : move_end;
      const long phase_end = phase == 0 ? move_end : segment_end;
      if (phase_begin == phase_end) continue;
      if (phase == 1 && move_end > segment_begin) {  // hold the height reached
        const auto t0 = Clock::now();
        std::snprintf(command, sizeof command, "fix gf_shear all deform 1 xy erate %.17g remap v",
                      shear_rate);
        lammps_command(handle, command);
        harness_seconds += std::chrono::duration<double>(Clock::now() - t0).count();
      }
      const bool measured = servo_move_every == 0 || phase == 1;  // the servo's samples
      for (long step = phase_begin; step < phase_end; step += sample_every) {
        const long n = std::min(sample_every, phase_end - step);
        std::snprintf(command, sizeof command, "run %ld start %ld stop %ld pre %s post no", n,
                      phase_begin, phase_end, step == phase_begin ? "yes" : "no");
        const auto t1 = run_timed(command);
        const ShearSample s = sample(schedule.rate_after(step - shear_begin), shear_begin);
        if (rank == 0 && rule) rule->add(s);
        if (measured) {
          segment_normal_stress += s.normal_stress;
          ++segment_samples;
        }
        harness_seconds += std::chrono::duration<double>(Clock::now() - t1).count();
      }
    }
    done = segment_end - shear_begin;
    if (rule && done % check_every == 0 && done < total_steps) {
      int stop = 0;  // rank 0 decides on the series it wrote
      if (rank == 0) {
        const granflow::dem::TargetStatus status = rule->check();
        stop = rule->confirmed() ? 1 : 0;
        std::printf("granflow-dem: strain.target_error check at %s%s\n",
                    rule->describe(status, shear_rate * double(done) * dt).c_str(),
                    stop ? ": targets met, stopping" : "");
        std::fflush(stdout);
      }
      MPI_Bcast(&stop, 1, MPI_INT, 0, MPI_COMM_WORLD);
      if (stop) break;
    }
    if (servo && done < total_steps) {
      const auto t0 = Clock::now();
      const double height =
          servo->next_height(lmp->domain->yprd, segment_normal_stress / segment_samples);
      // The new height is reached smoothly over the next segment by fix deform (remap v: atoms
      // are not moved, periodic images and ghost velocities carry the dilation). An affine
      // change_box ... remap between runs instead shifted the peculiar momentum (v_x kept while y
      // is rescaled) and, with tangential history on 2 ranks, did not conserve momentum.
      std::snprintf(command, sizeof command,
                    "fix gf_shear all deform 1 xy erate %.17g y final %.17g %.17g remap v",
                    shear_rate, lmp->domain->boxlo[1], lmp->domain->boxlo[1] + height);
      lammps_command(handle, command);
      height_commanded = true;
      harness_seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    }
    segment_normal_stress = 0.0;
    segment_samples = 0;
  }

  if (rule && done == total_steps && rank == 0)  // strain.max: which targets were missed
    std::printf("granflow-dem: strain.target_error: strain.max reached at %s\n",
                rule->describe(rule->check(), shear_rate * double(done) * dt).c_str());
  // 6. The stop stage (gf_stop_steps, optional): the shear stopped at constant volume
  // (driver/shear_stop.hpp), sampled every gf_sample_every steps; its rows follow the shear's in
  // the series, at the strain of the stop.
  const long stop_steps = std::lround(optional_deck_variable(handle, "gf_stop_steps", 0.0));
  long stop_done = 0;
  // Drained (gf_stop_drainage_length > 0): fix drainage compacts the box under
  // gf_stop_normal_stress as its liquid drains (fixes/fix_drainage.hpp).
  const double drainage_length = optional_deck_variable(handle, "gf_stop_drainage_length", 0.0);
  const double drained_normal_stress =
      drainage_length > 0.0 ? deck_variable(handle, "gf_stop_normal_stress", rank) : 0.0;
  if (stop_steps > 0) {
    const long stop_begin = shear_begin + done;
    const granflow::dem::StoppedFlow stopped =
        granflow::dem::stop_shear(handle, *lmp, schedule.rate_after(std::max(done - 1, 0L)));
    if (drained && !(drainage_length > 0.0))
      lammps_command(handle, const_cast<char*>("unfix gf_drain"));  // the stop holds the volume
    if (drainage_length > 0.0) {
      std::snprintf(command, sizeof command,
                    "fix gf_drain all drainage %.17g gf_virial darcy %.17g gf_fluid",
                    drained_normal_stress, drainage_length);
      lammps_command(handle, command);
    }
    char how[128] = "at constant volume";
    if (drainage_length > 0.0)
      std::snprintf(how, sizeof how, "drained over %.4g m under sigma_yy = %.6g Pa",
                    drainage_length, drained_normal_stress);
    if (rank == 0)
      std::printf(
          "granflow-dem: shear stopped at step %ld (strain %.6g): streaming profile, mean spin "
          "%.6g 1/s and drift (%.3g, %.3g, %.3g) m/s taken out; %ld steps %s\n",
          stop_begin, schedule.strain_after(done, dt), stopped.mean_spin, stopped.drift[0],
          stopped.drift[1], stopped.drift[2], stop_steps, how);
    for (; stop_done < stop_steps; stop_done += sample_every) {
      const long n = std::min(sample_every, stop_steps - stop_done);
      std::snprintf(command, sizeof command, "run %ld pre %s post no", n,
                    stop_done == 0 ? "yes" : "no");
      const auto t1 = run_timed(command);
      sample(0.0, stop_begin);
      harness_seconds += std::chrono::duration<double>(Clock::now() - t1).count();
    }
  }
  const double natoms = double(lammps_get_natoms(handle));
  double cpu_all_ranks = liggghts_cpu_seconds;  // summed over ranks (MPI waits included)
  MPI_Reduce(&liggghts_cpu_seconds, &cpu_all_ranks, 1, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
  if (rank == 0) {
    std::fclose(series);
    std::fclose(profile);
    // The particle snapshots the deck asked for (output.snapshot_strain), indexed by strain.
    try {
      granflow::dem::index_snapshots(".", shear_begin, dt, shear_rate);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "granflow-dem: %s\n", e.what());
    }
    int ranks = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    const double particle_steps_per_s = natoms * double(done + stop_done) / liggghts_seconds;
    // steps: the shear steps run (fewer than gf_total_steps when strain.target_error stopped the
    // run); checks, check_s: the stopping rule's checks and their wall time on rank 0.
    const long checks = rule ? rule->checks() : 0;
    const double check_seconds = rule ? rule->seconds() : 0.0;
    if (std::FILE* f = std::fopen(opt.stats.c_str(), "w")) {
      std::fprintf(
          f,
          "ranks\tparticles\tsteps\tsamples\tdt\tliggghts_s\tharness_s\t"
          "particle_steps_per_s\tharness_fraction\tliggghts_cpu_s\tchecks\tcheck_s\n%d\t%.0f\t%ld\t"
          "%ld\t%.10g\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%ld\t%.6g\n",
          ranks, natoms, done, samples, dt, liggghts_seconds, harness_seconds, particle_steps_per_s,
          harness_seconds / liggghts_seconds, cpu_all_ranks, checks, check_seconds);
      std::fclose(f);
    }
    std::printf(
        "granflow-dem: %d ranks, %.0f particles, %ld shear steps, %ld samples, "
        "LIGGGHTS %.3f s, harness %.4f s (%.2f %%), %.4g particle-steps/s\n",
        ranks, natoms, done, samples, liggghts_seconds, harness_seconds,
        100.0 * harness_seconds / liggghts_seconds, particle_steps_per_s);
    if (rule)
      std::printf("granflow-dem: strain.target_error: %ld checks, %.4f s (%.2f %% of LIGGGHTS)\n",
                  checks, check_seconds, 100.0 * check_seconds / liggghts_seconds);
  }
  lammps_close(handle);
  MPI_Finalize();
  return 0;
}
