// Contact time scales of Hertzian spheres, for the DEM time step.
//   Rayleigh time (Li, Xu & Thornton 2005; LIGGGHTS check/timestep/gran):
//     t_R = pi r sqrt(rho_p / G) / (0.1631 nu + 0.8766),  G = E / (2 (1 + nu))
//   Hertz collision duration of two equal spheres at normal impact speed v (Johnson 1985, 11.24):
//     t_H = 2.87 (m*^2 / (R* E*^2 v))^(1/5),  m* = m/2, R* = r/2, E* = E / (2 (1 - nu^2))
// Both are evaluated for the smallest particle (shortest times).
#pragma once

namespace granflow::dem {

struct ContactTimes {
  double rayleigh = 0.0;         // s
  double hertz = 0.0;            // s, at reference_speed
  double reference_speed = 0.0;  // m/s
  double shortest() const { return rayleigh < hertz ? rayleigh : hertz; }
};

double rayleigh_time(double radius, double particle_density, double youngs_modulus,
                     double poisson_ratio);
double hertz_contact_time(double radius, double particle_density, double youngs_modulus,
                          double poisson_ratio, double impact_speed);
ContactTimes contact_times(double smallest_radius, double particle_density, double youngs_modulus,
                           double poisson_ratio, double reference_speed);

}  // namespace granflow::dem
