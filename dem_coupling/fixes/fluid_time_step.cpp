#include "dem_coupling/fixes/fluid_time_step.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string_view>

#include "dem_coupling/fixes/lubrication.hpp"

namespace granflow::dem {

namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

double sphere_mass(double density, double radius) {
  return density * 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
}

// Moment of inertia of a solid sphere, (2/5) m r².
double sphere_inertia(double density, double radius) {
  return 0.4 * sphere_mass(density, radius) * radius * radius;
}

double normal_lubrication_time(const FluidTimeStepInput& in, double ri, double rj) {
  const double mi = sphere_mass(in.particle_density, ri), mj = sphere_mass(in.particle_density, rj);
  const double effective_mass = mi * mj / (mi + mj);
  return effective_mass / normal_lubrication_resistance(in.fluid.liquid.viscosity, ri, rj,
                                                        in.fluid.minimum_gap, in.fluid.minimum_gap);
}

double tangential_lubrication_time(const FluidTimeStepInput& in, double ri, double rj) {
  const double rho = in.particle_density;
  const double inverse_mass = 1.0 / sphere_mass(rho, ri) + 1.0 / sphere_mass(rho, rj) +
                              ri * ri / sphere_inertia(rho, ri) + rj * rj / sphere_inertia(rho, rj);
  return 1.0 / (inverse_mass * tangential_lubrication_resistance(in.fluid.liquid.viscosity, ri, rj,
                                                                 in.fluid.minimum_gap,
                                                                 in.fluid.minimum_gap));
}

template <class F>
double smallest_over_size_pairs(const FluidTimeStepInput& in, F time) {
  const double r0 = in.smallest_radius, r1 = in.largest_radius;
  return std::min({time(in, r0, r0), time(in, r0, r1), time(in, r1, r1)});
}

}  // namespace

FluidTimeScales fluid_time_scales(const FluidTimeStepInput& in) {
  FluidTimeScales t;
  t.contact = in.contact_time;
  const double eta = in.fluid.liquid.viscosity;
  const double d = 2.0 * in.smallest_radius;
  if (in.fluid.drag)
    t.drag = sphere_mass(in.particle_density, in.smallest_radius) /
             model::particle_drag_coefficient(in.fluid.liquid, d, in.solid_fraction);
  if (in.fluid.rotational_drag)
    t.rotational_drag = sphere_inertia(in.particle_density, in.smallest_radius) /
                        (std::numbers::pi * eta * d * d * d);
  if (in.fluid.lubrication) {
    t.normal_lubrication = smallest_over_size_pairs(in, normal_lubrication_time);
    if (in.fluid.tangential_lubrication)
      t.tangential_lubrication = smallest_over_size_pairs(in, tangential_lubrication_time);
  }
  return t;
}

namespace {

struct Limit {
  const char* name;
  const char* formula;
  double time_scale;
  double max_dt;
};

std::array<Limit, 5> limits(const FluidTimeScales& t) {
  return {{{"contact", "0.2 x shortest contact time (Rayleigh/Hertz)", t.contact,
            contact_time_limit_fraction * t.contact},
           {"drag", "m / c_p (smallest sphere, drag correlation at the current solid fraction)",
            t.drag, t.drag},
           {"rotational drag", "I / (pi eta d^3) = rho_p d^2 / (60 eta)", t.rotational_drag,
            t.rotational_drag},
           {"normal lubrication", "m_eff h_min / (6 pi eta a^2)", t.normal_lubrication,
            t.normal_lubrication},
           {"tangential lubrication", "m_t / c_t(h_min), c_t the log(1/h) shear resistance",
            t.tangential_lubrication, t.tangential_lubrication}}};
}

}  // namespace

FluidTimeStep stable_fluid_time_step(const FluidTimeScales& scales, double contact_safety,
                                     double viscous_safety) {
  FluidTimeStep best{infinity, "", infinity};
  for (const Limit& l : limits(scales)) {
    const double dt =
        (std::string_view(l.name) == "contact" ? contact_safety : viscous_safety) * l.time_scale;
    if (dt < best.dt) best = {dt, l.name, l.time_scale};
  }
  return best;
}

std::string check_fluid_time_step(double dt, const FluidTimeScales& scales) {
  const auto all = limits(scales);
  const Limit* worst = nullptr;
  for (const Limit& l : all)
    if (!(dt <= l.max_dt) && (worst == nullptr || l.max_dt < worst->max_dt)) worst = &l;
  if (worst == nullptr) return "";
  double largest = infinity;
  for (const Limit& l : all) largest = std::min(largest, l.max_dt);
  return fmt::format(
      "time step dt = {:.4g} s is unstable: it exceeds the {} limit {:.4g} s ({} = {:.4g} s); "
      "the largest stable dt is {:.4g} s (reduce dt, or raise h_min / lower the viscosity)",
      dt, worst->name, worst->max_dt, worst->formula, worst->time_scale, largest);
}

}  // namespace granflow::dem
