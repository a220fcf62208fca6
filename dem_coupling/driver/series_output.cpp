#include "dem_coupling/driver/series_output.hpp"

#include <cerrno>
#include <cstdlib>
#include <limits>

namespace granflow::dem {

void write_series_header(std::FILE* f, bool wet) {
  std::fprintf(f,
               "step\ttime\tstrain\tlx\tly\tlz\txy\tvolume\t"
               "Pvir_xx\tPvir_yy\tPvir_zz\tPvir_xy\tPvir_xz\tPvir_yz\t"
               "Pkin_xx\tPkin_yy\tPkin_zz\tPkin_xy\tPkin_xz\tPkin_yz\t"
               "P_xx\tP_yy\tP_zz\tP_xy\tP_xz\tP_yz\t"
               "sigma_yy\ttau\tp\tmu\tT\tphi\te\tI\tZ\td_mean\t"
               "momentum_x\tmomentum_y\tmomentum_z\tparticles\tprofile_deviation\toverlap\t"
               "Z_nr\tnonrattler_fraction\tfabric_xy\tanisotropy");
  if (wet) std::fprintf(f, "\ttau_contact\ttau_lub\ttau_drag\ttau_kin\tlubricated_pairs\tp_fluid");
  std::fputc('\n', f);
}

void write_series_row(std::FILE* f, const ShearSample& s, double overlap,
                      const NetworkState& network, const FluidStress* fluid) {
  std::fprintf(f, "%ld\t%.10g\t%.10g\t%.10g\t%.10g\t%.10g\t%.10g\t%.10g", s.step, s.time, s.strain,
               s.box.lx, s.box.ly, s.box.lz, s.box.xy, s.box.volume());
  for (double v : s.virial_stress) std::fprintf(f, "\t%.10g", v);
  for (double v : s.kinetic_stress) std::fprintf(f, "\t%.10g", v);
  for (double v : s.stress) std::fprintf(f, "\t%.10g", v);
  std::fprintf(f, "\t%.10g\t%.10g\t%.10g\t%.10g\t%.10g\t%.10g\t%.10g\t%.10g\t%.10g\t%.10g",
               s.normal_stress, s.shear_stress, s.pressure, s.friction, s.temperature,
               s.solid_fraction, s.void_ratio, s.inertial_number, s.coordination, s.mean_diameter);
  std::fprintf(f, "\t%.17g\t%.17g\t%.17g\t%.0f\t%.10g\t%.10g", s.peculiar_momentum[0],
               s.peculiar_momentum[1], s.peculiar_momentum[2], s.particles, s.profile_deviation,
               overlap);
  std::fprintf(f, "\t%.10g\t%.10g\t%.10g\t%.10g", network.coordination_nonrattler,
               network.nonrattler_fraction, network.fabric[3], network.anisotropy);
  if (fluid)
    std::fprintf(f, "\t%.17g\t%.17g\t%.17g\t%.17g\t%.0f\t%.17g", fluid->contact, fluid->lubrication,
                 fluid->drag, fluid->kinetic, fluid->lubricated_pairs, fluid->pressure);
  std::fputc('\n', f);
  std::fflush(f);
}

void write_profile_row(std::FILE* f, const ShearSample& s) {
  std::fprintf(f, "%ld\t%.10g", s.step, s.strain);
  for (double v : s.profile_velocity) std::fprintf(f, "\t%.10g", v);
  std::fputc('\n', f);
  std::fflush(f);
}

double as_written(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", value);  // the format of write_series_row
  errno = 0;
  char* end = nullptr;
  const double read = std::strtod(text, &end);  // std::stod is strtod that throws on these
  if (end == text || errno == ERANGE) return std::numeric_limits<double>::quiet_NaN();
  return read;
}

}  // namespace granflow::dem
