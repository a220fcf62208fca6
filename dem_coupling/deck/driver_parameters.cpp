#include "dem_coupling/deck/driver_parameters.hpp"

#include <fmt/format.h>

namespace granflow::dem {

std::string driver_parameter_lines(const DriverParameters& p) {
  std::string lines = fmt::format(
      "variable gf_shear_rate equal {:.17g}\n"
      "variable gf_total_steps equal {}\n"
      "variable gf_sample_every equal {}\n"
      "variable gf_constant_pressure equal {}\n"
      "variable gf_normal_stress equal {:.17g}\n"
      "variable gf_servo_gain equal {:.17g}\n"
      "variable gf_servo_max_strain equal {:.17g}\n"
      "variable gf_servo_every equal {}\n",
      p.shear_rate, p.total_steps, p.sample_every, p.constant_pressure ? 1 : 0, p.normal_stress,
      p.servo_gain, p.servo_max_strain, p.servo_every);
  if (p.servo_move_every)
    lines += fmt::format("variable gf_servo_move_every equal {}\n", *p.servo_move_every);
  lines += fmt::format(
      "variable gf_profile_bins equal {}\n"
      "variable gf_particle_density equal {:.17g}\n",
      p.profile_bins, p.particle_density);
  return lines;
}

std::string granular_atom_setup() {
  return "atom_style      granular\n"
         "atom_modify     map array\n"
         "boundary        p p p\n"
         "newton          off\n"
         "communicate     single vel yes\n"
         "units           si\n";
}

}  // namespace granflow::dem
