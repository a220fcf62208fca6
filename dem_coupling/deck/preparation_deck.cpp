#include "dem_coupling/deck/preparation_deck.hpp"

#include <fmt/format.h>

#include <cmath>

#include "dem_coupling/deck/driver_parameters.hpp"
#include "dem_coupling/deck/initial_state.hpp"

namespace granflow::dem {

double preparation_max_rate(const PreparationParams& p) {
  const DemMaterial& m = p.sample.material;
  return p.compression_inertial_number * std::sqrt(p.pressure / m.particle_density) / m.diameter;
}

PreparationDeck make_preparation_deck(const PreparationParams& p,
                                      const std::string& data_file_name) {
  PreparationDeck out;
  out.max_rate = preparation_max_rate(p);
  // The gas of the shear deck: inserted at φ = insertion_solid_fraction, not compressed; the
  // compression rate stands in for the shear rate in the Hertz time's impact speed.
  ShearDeckParams gas = p.sample;
  gas.solid_fraction = insertion_solid_fraction;
  gas.constant_pressure = false;
  gas.shear_rate = out.max_rate;
  gas.wet.enabled = false;
  out.sample = make_shear_deck(gas, data_file_name);
  out.data = out.sample.data;
  const DemMaterial& m = p.sample.material;
  const bool hooke = m.contact_law == ContactLaw::hooke;
  DriverParameters driver;
  driver.particle_density = m.particle_density;
  const double skin = 0.2 * out.sample.mean_diameter;
  out.deck = fmt::format(
      R"(# granflow DEM preparation deck, LIGGGHTS 3.8.0 (Debian): run it with granflow-dem
# (the triclinic workaround, then the preparation stage after this file):
#   granflow-dem in.granflow
# Isotropic compression of a granular gas to the mean stress p0 = {p0:.6g} Pa by a servo on the
# box lengths, with the preparation friction mu_prep = {mu:.6g}, then relaxation to rest
# (driver/prepare_stage.hpp); writes prepared.restart, prepared.tsv, prepare.tsv.
# dt = {safety:g} * min(t_Rayleigh = {rayleigh:.6g} s, t_Hertz = {hertz:.6g} s{linear})

{driver_parameters}variable gf_prepare_pressure equal {p0:.17g}
variable gf_prepare_tolerance equal {tolerance:.17g}
variable gf_prepare_energy_ratio equal {ratio:.17g}
# largest compression rate = {inertial:g} sqrt(p0/rho_p)/d
variable gf_prepare_max_rate equal {rate:.17g}
variable gf_prepare_loop_gain equal {loop:.17g}
variable gf_prepare_every equal {every}
variable gf_prepare_settle equal {settle}
variable gf_prepare_max_steps equal {max_steps}
# the contacts' elastic energy: 0 hertz (E* = E / (2 (1 - nu^2))), 1 hooke (k_n)
variable gf_elastic_law equal {law}
variable gf_effective_modulus equal {modulus:.17g}
variable gf_normal_stiffness equal {stiffness:.17g}

{atom_setup}box             tilt large
read_data       {data}
neighbor        {skin:.17g} bin
neigh_modify    delay 0

{contact}timestep        {dt:.17g}
fix             integr all nve/sphere

compute         gf_virial all pressure thermo_temp virial
thermo_style    custom step atoms ke c_gf_virial[1] c_gf_virial[2] c_gf_virial[3]
thermo_modify   norm no lost error
thermo          0
# contact virial averaged over each servo interval (read by granflow-dem)
fix             gf_stress all ave/time 1 {every} {every} c_gf_virial[1] c_gf_virial[2] c_gf_virial[3] c_gf_virial[4] c_gf_virial[5] c_gf_virial[6]
)",
      fmt::arg("p0", p.pressure), fmt::arg("mu", m.particle_friction),
      fmt::arg("safety", p.sample.dt_safety), fmt::arg("rayleigh", out.sample.times.rayleigh),
      fmt::arg("hertz", out.sample.times.hertz),
      fmt::arg("linear",
               hooke ? fmt::format(", linear spring t_c = {:.6g} s", out.sample.times.linear_spring)
                     : std::string()),
      fmt::arg("driver_parameters", driver_parameter_lines(driver)),
      fmt::arg("tolerance", p.tolerance), fmt::arg("ratio", p.energy_ratio),
      fmt::arg("inertial", p.compression_inertial_number), fmt::arg("rate", out.max_rate),
      fmt::arg("loop", p.loop_gain), fmt::arg("every", p.update_every),
      fmt::arg("settle", p.settle), fmt::arg("max_steps", p.max_steps),
      fmt::arg("law", hooke ? 1 : 0),
      fmt::arg("modulus", m.youngs_modulus / (2.0 * (1.0 - m.poisson_ratio * m.poisson_ratio))),
      fmt::arg("stiffness", m.normal_stiffness), fmt::arg("atom_setup", granular_atom_setup()),
      fmt::arg("data", data_file_name), fmt::arg("skin", skin),
      fmt::arg("contact", contact_law_commands(m, out.sample.mean_diameter)),
      fmt::arg("dt", out.sample.dt));
  return out;
}

}  // namespace granflow::dem
