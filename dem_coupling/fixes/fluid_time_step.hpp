// Time step of an immersed DEM run (fix fluid/le): the contact time and the viscous relaxation
// times of the fluid forces, which LIGGGHTS integrates explicitly.
//
// Velocity Verlet evaluates a velocity-dependent force F = -c w with the half-step velocity, so
// w relaxes by the factor (1 - Δt/τ) per step, τ = m/c: stable for Δt < 2τ and free of overshoot
// (w keeps its sign) for Δt <= τ. Δt <= τ is the limit enforced for every fluid force; a
// particle squeezed by several lubricated neighbours at once relaxes up to about twice as fast
// as one pair (a chain's fastest mode), which the factor 2 between the two bounds covers.
// Time scales, for the particle sizes that make them shortest:
//   drag               τ_d = m / c_p,   c_p = particle_drag_coefficient(liquid, d, ν) (∝ d, so
//                      the smallest sphere: τ_d ∝ d²)
//   rotational drag    τ_r = I / (π η d³) = ρ_p d² / (60 η),  I = m d²/10
//   normal lubrication τ_n = m_eff h_min / (6π η a²),  m_eff = m_i m_j/(m_i + m_j)
//   tangential lub.    τ_t = m_t / c_t(h_min),  1/m_t = 1/m_i + 1/m_j + r_i²/I_i + r_j²/I_j
//                      (inertia of the relative surface velocity v_ij - (r_i ω_i + r_j ω_j) × n)
// τ_n and τ_t are homogeneous of degree one in the radii and unimodal in r_j/r_i, so their
// minimum over a size range [r_min, r_max] is at one of the pairs (r_min, r_min), (r_min, r_max),
// (r_max, r_max); all three are evaluated.
// Contact: the refusal limit is 0.2 t_contact (LIGGGHTS' check/timestep/gran warns above 20 % of
// the Rayleigh time); the stable step uses the deck's safety factor (0.1 by default).
#pragma once

#include <limits>
#include <string>

#include "continuum/model/closures.hpp"

namespace granflow::dem {

struct FluidForceSettings {
  model::LiquidParameters liquid;  // viscosity, permeability (drag correlation), sphericity
  bool drag = true;
  bool rotational_drag = true;
  bool lubrication = true;
  bool tangential_lubrication = true;
  double maximum_gap = 5e-5;  // h_max, m
  double minimum_gap = 1e-6;  // h_min, m
};

struct FluidTimeStepInput {
  FluidForceSettings fluid;
  double contact_time = std::numeric_limits<double>::infinity();  // s; inf = not checked
  double particle_density = 2500.0;                               // ρ_p, kg/m³ (smallest)
  double smallest_radius = 5e-4;                                  // m
  double largest_radius = 5e-4;                                   // m
  double solid_fraction = 0.0;                                    // ν used by the drag
};

// Each time scale in s; +infinity for a force that is switched off.
struct FluidTimeScales {
  double contact = std::numeric_limits<double>::infinity();
  double drag = std::numeric_limits<double>::infinity();
  double rotational_drag = std::numeric_limits<double>::infinity();
  double normal_lubrication = std::numeric_limits<double>::infinity();
  double tangential_lubrication = std::numeric_limits<double>::infinity();
};

FluidTimeScales fluid_time_scales(const FluidTimeStepInput& in);

// Largest Δt each limit allows (refusal bounds): 0.2 t_contact and τ for the fluid forces.
constexpr double contact_time_limit_fraction = 0.2;

struct FluidTimeStep {
  double dt = 0.0;          // s, the recommended step
  std::string limited_by;   // name of the limit that sets it
  double limit_time = 0.0;  // the time scale of that limit, s
};

// dt = min(contact_safety t_contact, viscous_safety min(τ_d, τ_r, τ_n, τ_t)).
FluidTimeStep stable_fluid_time_step(const FluidTimeScales& scales, double contact_safety = 0.1,
                                     double viscous_safety = 0.2);

// "" if dt is within every limit; otherwise a message naming the limit that dt exceeds (the most
// restrictive one), its formula and value, and the largest acceptable dt.
std::string check_fluid_time_step(double dt, const FluidTimeScales& scales);

}  // namespace granflow::dem
