// Contact time scales of Hertzian spheres, for the DEM time step.
//   Rayleigh time (Li, Xu & Thornton 2005; LIGGGHTS check/timestep/gran):
//     t_R = pi r sqrt(rho_p / G) / (0.1631 nu + 0.8766),  G = E / (2 (1 + nu))
//   Hertz collision duration of two equal spheres at normal impact speed v (Johnson 1985, 11.24):
//     t_H = 2.87 (m*^2 / (R* E*^2 v))^(1/5),  m* = m/2, R* = r/2, E* = E / (2 (1 - nu^2))
//   Linear spring-dashpot (hooke): m* x'' + γ_n x' + k_n x = 0 with γ_n chosen for restitution e,
//     γ_n / m* = 2 sqrt(k_n/m*) (-ln e) / sqrt(π² + ln² e)       (damping rate, 1/s)
//     t_c = π / sqrt(k_n/m* - (γ_n/(2 m*))²) = π sqrt(m*/k_n) sqrt(1 + ln² e/π²)
//   (e = exp(-γ_n t_c / (2 m*)); Schäfer, Dippel & Wolf 1996, J. Phys. I France 6, 5).
// All are evaluated for the smallest particle (shortest times).
#pragma once

namespace granflow::dem {

struct ContactTimes {
  double rayleigh = 0.0;         // s
  double hertz = 0.0;            // s, at reference_speed
  double reference_speed = 0.0;  // m/s
  double linear_spring = 0.0;    // s, hooke t_c; 0 for hertz
  // The contact time that bounds dt: t_c of the linear spring, else min(t_R, t_H).
  double shortest() const {
    if (linear_spring > 0.0) return linear_spring;
    return rayleigh < hertz ? rayleigh : hertz;
  }
};

double rayleigh_time(double radius, double particle_density, double youngs_modulus,
                     double poisson_ratio);
double hertz_contact_time(double radius, double particle_density, double youngs_modulus,
                          double poisson_ratio, double impact_speed);
// Linear spring-dashpot of effective mass m* = m_i m_j/(m_i + m_j) and stiffness k_n.
double linear_spring_damping_rate(double effective_mass, double normal_stiffness,
                                  double restitution);
double linear_spring_contact_time(double effective_mass, double normal_stiffness,
                                  double restitution);
ContactTimes contact_times(double smallest_radius, double particle_density, double youngs_modulus,
                           double poisson_ratio, double reference_speed);

}  // namespace granflow::dem
