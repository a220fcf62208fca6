#include "dem_coupling/deck/driver_parameters.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace granflow::dem {

namespace {
// Index in target_observables of a word "target_<observable>", else target_observables.size().
std::size_t target_index(const std::string& name) {
  for (std::size_t k = 0; k < target_observables.size(); ++k)
    if (name == std::string("target_") + target_observables[k]) return k;
  return target_observables.size();
}
}  // namespace

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
  if (p.targets.any()) {
    for (std::size_t k = 0; k < target_observables.size(); ++k)
      lines += fmt::format("variable gf_target_{} equal {:.17g}\n", target_observables[k],
                           p.targets.error[k]);
    lines += fmt::format(
        "variable gf_check_every equal {}\n"
        "variable gf_confirm_checks equal {}\n"
        "variable gf_temperature_scale equal {:.17g}\n",
        p.check_every, p.targets.confirm_checks, p.temperature_scale);
  }
  if (p.stop_steps > 0) lines += fmt::format("variable gf_stop_steps equal {}\n", p.stop_steps);
  if (p.stop_steps > 0 && p.stop_drainage_length > 0.0)
    lines += fmt::format(
        "variable gf_stop_drainage_length equal {:.17g}\n"
        "variable gf_stop_normal_stress equal {:.17g}\n",
        p.stop_drainage_length, p.stop_normal_stress);
  if (p.drainage_length > 0.0)
    lines += fmt::format("variable gf_drainage_length equal {:.17g}\n", p.drainage_length);
  if (p.height_resistance > 0.0)
    lines += fmt::format("variable gf_height_resistance equal {:.17g}\n", p.height_resistance);
  if (p.rate_step_steps > 0)
    lines += fmt::format(
        "variable gf_rate_step_steps equal {}\nvariable gf_rate_step_shear_rate equal {:.17g}\n",
        p.rate_step_steps, p.rate_step_shear_rate);
  return lines;
}

DriverParameters driver_parameters_from_words(const std::vector<std::string>& words) {
  DriverParameters p;
  bool servo_every_given = false;
  for (const auto& word : words) {
    const auto eq = word.find('=');
    const std::string name = word.substr(0, eq == std::string::npos ? 0 : eq);
    const std::string text = eq == std::string::npos ? std::string() : word.substr(eq + 1);
    double value = 0;
    try {
      std::size_t used = 0;
      value = std::stod(text, &used);
      if (used != text.size()) throw std::invalid_argument(text);
    } catch (const std::exception&) {
      throw std::invalid_argument("'" + word + "': expected NAME=NUMBER");
    }
    const long integer = std::lround(value);
    if (name == "shear_rate")
      p.shear_rate = value;
    else if (name == "total_steps")
      p.total_steps = integer;
    else if (name == "sample_every")
      p.sample_every = integer;
    else if (name == "constant_pressure")
      p.constant_pressure = integer != 0;
    else if (name == "normal_stress")
      p.normal_stress = value;
    else if (name == "servo_gain")
      p.servo_gain = value;
    else if (name == "servo_max_strain")
      p.servo_max_strain = value;
    else if (name == "servo_every")
      p.servo_every = integer, servo_every_given = true;
    else if (name == "servo_move_every")
      p.servo_move_every = integer;
    else if (name == "profile_bins")
      p.profile_bins = int(integer);
    else if (name == "particle_density")
      p.particle_density = value;
    else if (name == "check_every")
      p.check_every = integer;
    else if (name == "confirm_checks")
      p.targets.confirm_checks = int(integer);
    else if (name == "temperature_scale")
      p.temperature_scale = value;
    else if (name == "stop_steps")
      p.stop_steps = integer;
    else if (name == "stop_drainage_length")
      p.stop_drainage_length = value;
    else if (name == "stop_normal_stress")
      p.stop_normal_stress = value;
    else if (name == "drainage_length")
      p.drainage_length = value;
    else if (name == "height_resistance")
      p.height_resistance = value;
    else if (name == "rate_step_steps")
      p.rate_step_steps = integer;
    else if (name == "rate_step_shear_rate")
      p.rate_step_shear_rate = value;
    else if (const auto k = target_index(name); k < target_observables.size())
      p.targets.error[k] = value;
    else
      throw std::invalid_argument("'" + word + "': unknown parameter '" + name + "'");
  }
  if (!servo_every_given) p.servo_every = p.sample_every;
  return p;
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
