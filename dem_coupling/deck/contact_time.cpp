#include "dem_coupling/deck/contact_time.hpp"

#include <cmath>
#include <numbers>

namespace granflow::dem {

double rayleigh_time(double radius, double particle_density, double youngs_modulus,
                     double poisson_ratio) {
  const double shear_modulus = youngs_modulus / (2.0 * (1.0 + poisson_ratio));
  return std::numbers::pi * radius * std::sqrt(particle_density / shear_modulus) /
         (0.1631 * poisson_ratio + 0.8766);
}

double hertz_contact_time(double radius, double particle_density, double youngs_modulus,
                          double poisson_ratio, double impact_speed) {
  const double mass = particle_density * 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
  const double effective_mass = 0.5 * mass;
  const double effective_radius = 0.5 * radius;
  const double effective_modulus = youngs_modulus / (2.0 * (1.0 - poisson_ratio * poisson_ratio));
  return 2.87 *
         std::pow(effective_mass * effective_mass /
                      (effective_radius * effective_modulus * effective_modulus * impact_speed),
                  0.2);
}

double linear_spring_damping_rate(double effective_mass, double normal_stiffness,
                                  double restitution) {
  const double log_e = std::log(restitution);
  return 2.0 * std::sqrt(normal_stiffness / effective_mass) * (-log_e) /
         std::sqrt(std::numbers::pi * std::numbers::pi + log_e * log_e);
}

double linear_spring_contact_time(double effective_mass, double normal_stiffness,
                                  double restitution) {
  const double log_e = std::log(restitution);
  return std::numbers::pi * std::sqrt(effective_mass / normal_stiffness) *
         std::sqrt(1.0 + log_e * log_e / (std::numbers::pi * std::numbers::pi));
}

ContactTimes contact_times(double smallest_radius, double particle_density, double youngs_modulus,
                           double poisson_ratio, double reference_speed) {
  ContactTimes t;
  t.reference_speed = reference_speed;
  t.rayleigh = rayleigh_time(smallest_radius, particle_density, youngs_modulus, poisson_ratio);
  t.hertz = hertz_contact_time(smallest_radius, particle_density, youngs_modulus, poisson_ratio,
                               reference_speed);
  return t;
}

}  // namespace granflow::dem
