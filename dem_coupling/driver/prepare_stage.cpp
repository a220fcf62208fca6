#include "dem_coupling/driver/prepare_stage.hpp"

#include <mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "dem_coupling/driver/atom_view.hpp"
#include "dem_coupling/driver/contact_probe.hpp"
#include "dem_coupling/extraction/shear_sample.hpp"
#include "domain.h"
#include "lammps.h"
#include "library.h"
#include "update.h"

namespace granflow::dem {

namespace {

double variable(void* handle, const char* name, int rank) {
  void* p = lammps_extract_variable(handle, const_cast<char*>(name), nullptr);
  if (p == nullptr) {
    if (rank == 0) std::fprintf(stderr, "ERROR: granflow-dem: deck does not define %s\n", name);
    MPI_Finalize();
    std::exit(2);
  }
  const double v = *static_cast<double*>(p);
  std::free(p);
  return v;
}

// Interval mean of the contact virial (fix gf_stress ave/time), component k (xx yy zz xy xz yz).
double averaged_virial(void* handle, int k) {
  auto* p = static_cast<double*>(lammps_extract_fix(handle, "gf_stress", 0, 1, k, 0));
  const double v = *p;
  std::free(p);
  return v;
}

// Kinetic energy of rotation, Σ (1/5) m r² |ω|² (solid spheres, I = (2/5) m r²). Collective.
double rotational_energy(void* handle) {
  const int nlocal = *static_cast<int*>(lammps_extract_global(handle, "nlocal"));
  auto** omega = static_cast<double**>(lammps_extract_atom(handle, "omega"));
  const auto* mass = static_cast<double*>(lammps_extract_atom(handle, "rmass"));
  const auto* radius = static_cast<double*>(lammps_extract_atom(handle, "radius"));
  double local = 0.0, global = 0.0;
  for (int i = 0; i < nlocal; ++i)
    local += 0.2 * mass[i] * radius[i] * radius[i] *
             (omega[i][0] * omega[i][0] + omega[i][1] * omega[i][1] + omega[i][2] * omega[i][2]);
  MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  return global;
}

const char* const columns =
    "step\ttime\tlx\tly\tlz\tvolume\tphi\tp\tsigma_yy\tP_xx\tP_yy\tP_zz\tP_xy\tP_xz\tP_yz\t"
    "kinetic_energy\telastic_energy\tenergy_ratio\tZ\tZ_nr\tnonrattler_fraction\t"
    "fabric_xx\tfabric_yy\tfabric_zz\tfabric_xy\tfabric_xz\tfabric_yz\tanisotropy\toverlap\t"
    "d_mean\tparticles\tat_target\tat_rest\n";

void write_row(std::FILE* f, long step, double time, const ShearSample& s, double kinetic,
               const ContactProbe& c, bool at_target, bool at_rest) {
  const double ratio = c.elastic_energy > 0.0 ? kinetic / c.elastic_energy : HUGE_VAL;
  std::fprintf(f, "%ld\t%.10g\t%.17g\t%.17g\t%.17g\t%.10g\t%.10g\t%.10g\t%.10g", step, time,
               s.box.lx, s.box.ly, s.box.lz, s.box.volume(), s.solid_fraction, s.pressure,
               s.normal_stress);
  for (double v : s.stress) std::fprintf(f, "\t%.10g", v);
  std::fprintf(f, "\t%.10g\t%.10g\t%.10g\t%.10g\t%.10g\t%.10g", kinetic, c.elastic_energy,
               std::min(ratio, 1e300), c.network.coordination, c.network.coordination_nonrattler,
               c.network.nonrattler_fraction);
  for (double v : c.network.fabric) std::fprintf(f, "\t%.10g", v);
  std::fprintf(f, "\t%.10g\t%.10g\t%.10g\t%.0f\t%d\t%d\n", c.network.anisotropy, c.mean_overlap,
               s.mean_diameter, s.particles, at_target ? 1 : 0, at_rest ? 1 : 0);
  std::fflush(f);
}

}  // namespace

int run_preparation(void* handle, LAMMPS_NS::LAMMPS& lmp, int rank) {
  const double target = variable(handle, "gf_prepare_pressure", rank);
  const double tolerance = variable(handle, "gf_prepare_tolerance", rank);
  const double energy_ratio = variable(handle, "gf_prepare_energy_ratio", rank);
  const double max_rate = variable(handle, "gf_prepare_max_rate", rank);
  const double loop_gain = variable(handle, "gf_prepare_loop_gain", rank);
  const long every = std::lround(variable(handle, "gf_prepare_every", rank));
  const long max_steps = std::lround(variable(handle, "gf_prepare_max_steps", rank));
  const long settle = std::lround(variable(handle, "gf_prepare_settle", rank));
  const double density = variable(handle, "gf_particle_density", rank);
  ElasticLaw law;
  law.hooke = variable(handle, "gf_elastic_law", rank) != 0.0;
  law.effective_modulus = variable(handle, "gf_effective_modulus", rank);
  law.normal_stiffness = variable(handle, "gf_normal_stiffness", rank);
  if (!(target > 0.0) || every < 1 || max_steps < every || settle < 1) {
    if (rank == 0)
      std::fprintf(stderr,
                   "ERROR: granflow-dem: deck: need gf_prepare_pressure > 0, 1 <= "
                   "gf_prepare_every <= gf_prepare_max_steps, gf_prepare_settle >= 1\n");
    MPI_Finalize();
    std::exit(2);
  }
  std::FILE* series = nullptr;
  if (rank == 0) {
    series = std::fopen("prepare.tsv", "w");
    if (!series) {
      std::fprintf(stderr, "ERROR: granflow-dem: cannot write prepare.tsv\n");
      MPI_Abort(MPI_COMM_WORLD, 2);
    }
    std::fputs(columns, series);
  }
  const double dt = lmp.update->dt;
  const double largest_step = max_rate * double(every) * dt;
  SampleSums local(1), global(1);
  char command[512];
  long settled = 0, step = 0;
  ShearSample s;
  ContactProbe contacts;
  double kinetic = 0.0;
  bool at_target = false, at_rest = false, deforming = false;
  while (step < max_steps) {
    std::snprintf(command, sizeof command, "run %ld post no", every);
    lammps_command(handle, command);
    step += every;
    // ---- measure: stress, φ, T from the extraction harness with no streaming profile
    local.clear();
    const LAMMPS_NS::Domain& domain = *lmp.domain;
    const ShearFrame frame{0.0, domain.boxlo[1], domain.yprd};
    accumulate_particles(owned_particles(handle), frame, local);
    MPI_Allreduce(local.data(), global.data(), local.size(), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    std::array<double, 6> virial{};
    for (int k = 0; k < 6; ++k) virial[k] = averaged_virial(handle, k);
    s = finalize_sample(global, virial, {domain.xprd, domain.yprd, domain.zprd, domain.xy}, frame,
                        density);
    contacts = probe_contacts(handle, lmp, law);
    const double translational =
        0.5 * (s.kinetic_stress[0] + s.kinetic_stress[1] + s.kinetic_stress[2]) * s.box.volume();
    kinetic = translational + rotational_energy(handle);
    const double error = (target - s.pressure) / target;
    at_target = std::abs(error) <= tolerance;
    at_rest = kinetic <= energy_ratio * contacts.elastic_energy;
    settled = at_target && at_rest ? settled + 1 : 0;
    if (rank == 0)
      write_row(series, step, double(step) * dt, s, kinetic, contacts, at_target, at_rest);
    if (settled >= settle) break;
    // ---- servo: the next interval's box lengths
    double demand = -largest_step;  // the gas: no stress yet
    if (s.pressure > 0.0 && contacts.mean_overlap > 0.0) {
      const double overlap_at_target =
          contacts.mean_overlap * std::pow(target / s.pressure, 2.0 / 3.0);
      demand = -error * loop_gain * (2.0 / 3.0) * overlap_at_target / s.mean_diameter;
    }
    const double factor = std::exp(std::clamp(demand, -largest_step, largest_step));
    std::snprintf(command, sizeof command,
                  "fix gf_prepare all deform 1 x final %.17g %.17g y final %.17g %.17g z final "
                  "%.17g %.17g remap x",
                  domain.boxlo[0], domain.boxlo[0] + factor * domain.xprd, domain.boxlo[1],
                  domain.boxlo[1] + factor * domain.yprd, domain.boxlo[2],
                  domain.boxlo[2] + factor * domain.zprd);
    lammps_command(handle, command);
    deforming = true;
  }
  if (rank == 0) std::fclose(series);
  if (settled < settle) {
    if (rank == 0)
      std::fprintf(stderr,
                   "ERROR: granflow-dem: preparation not at rest within %ld steps: p = %.6g Pa "
                   "(target %.6g, tolerance %.3g), kinetic/elastic energy %.3g (at most %.3g)\n",
                   max_steps, s.pressure, target, tolerance,
                   contacts.elastic_energy > 0.0 ? kinetic / contacts.elastic_energy : HUGE_VAL,
                   energy_ratio);
    return 3;
  }
  if (deforming) lammps_command(handle, "unfix gf_prepare");
  lammps_command(handle, "write_restart prepared.restart");
  if (rank == 0) {
    std::FILE* f = std::fopen("prepared.tsv", "w");
    if (!f) {
      std::fprintf(stderr, "ERROR: granflow-dem: cannot write prepared.tsv\n");
      return 2;
    }
    std::fputs(columns, f);
    write_row(f, step, double(step) * dt, s, kinetic, contacts, at_target, at_rest);
    std::fclose(f);
    std::printf(
        "granflow-dem: prepared at step %ld: phi = %.6g, p = %.6g Pa, Z = %.4g, Z* = %.4g\n", step,
        s.solid_fraction, s.pressure, contacts.network.coordination,
        contacts.network.coordination_nonrattler);
  }
  return 0;
}

}  // namespace granflow::dem
