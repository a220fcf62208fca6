#include "continuum/multi_regime/model_sections.hpp"

#include <fmt/format.h>

namespace granflow::continuum {

core::Field material_section() {
  core::Field m("material", core::ValueType::section, "", "grain properties (shared with the DEM)");
  m.number("diameter", "m", "mean grain diameter d").required().greater_than(0);
  m.number("particle_density", "kg/m^3", "grain density ρ_p").required().greater_than(0);
  m.number("restitution", "", "normal coefficient of restitution e_r").required()
      .greater_than(0).at_most(1);
  m.number("particle_friction", "", "interparticle friction coefficient μ_p")
      .default_value("0.5").at_least(0);
  m.number("youngs_modulus", "Pa", "grain Young's modulus (DEM contact stiffness)")
      .default_value("1.0e7").greater_than(0);
  m.number("poisson_ratio", "", "grain Poisson ratio (DEM)").default_value("0.3")
      .greater_than(-1).less_than(0.5);
  return m;
}

core::Field collisional_section() {
  core::Field c("collisional", core::ValueType::section, "",
                "extended kinetic theory term σ_COL, Γ and the T balance (model.md §3)");
  c.boolean("enabled", "switch the collisional term on/off").default_value("true");
  c.choice("radial_distribution", model::radial_distribution_names(),
           "g0 at contact").default_value("chialvo_sundaresan");
  c.number("jamming_fraction", "", "ν_c where g0 diverges (≈0.639 frictionless, ≈0.587 at μ_p=0.5)")
      .default_value("0.587").greater_than(0.49).less_than(0.74);
  c.choice("effective_restitution", model::effective_restitution_names(),
           "ε in Γ: the plain restitution or the Chialvo-Sundaresan frictional correction")
      .default_value("chialvo_sundaresan");
  c.choice("correlation_length", model::correlation_length_names(),
           "L in Γ: the diameter (standard kinetic theory) or Jenkins' extended length")
      .default_value("diameter");
  c.number("correlation_length_constant", "", "c of Jenkins' correlation length")
      .default_value("0.5").greater_than(0);
  return c;
}

core::Field liquid_section() {
  core::Field l("liquid", core::ValueType::section, "",
                "interstitial liquid: σ_L, η(ν), drag, Λ (model.md §4)");
  l.boolean("enabled", "switch the liquid terms on/off (off: dry)").default_value("false");
  l.number("viscosity", "Pa s", "liquid viscosity η0").default_value("1.0e-3").greater_than(0);
  l.number("density", "kg/m^3", "liquid density ρ_L").default_value("1000").greater_than(0);
  l.number("bulk_modulus", "Pa", "liquid bulk modulus K_w").default_value("2.2e9").greater_than(0);
  l.choice("mixture_viscosity", model::mixture_viscosity_names(), "η(ν) closure")
      .default_value("boyer");
  l.number("maximum_packing", "", "ν_m of the Krieger-Dougherty / Boyer viscosity")
      .default_value("0.585").greater_than(0.3).less_than(0.74);
  l.choice("permeability", model::permeability_names(), "permeability κ(e) closure for the drag")
      .default_value("seed_eq26");
  l.number("sphericity", "", "A in seed Eq. 26 (1 for spheres)").default_value("1")
      .greater_than(0).at_most(1);
  l.boolean("fluctuation_dissipation", "Λ: fluctuation energy given to the liquid")
      .default_value("true");
  l.number("trulsson_alpha", "", "α of K = J + α I² (reporting only)").default_value("0.6")
      .greater_than(0);
  return l;
}

MultiRegimeSettings read_multi_regime_settings(const core::Case& c) {
  MultiRegimeSettings s;
  auto& col = s.collisional_parameters;
  col.diameter = c.number("material.diameter");
  col.particle_density = c.number("material.particle_density");
  col.restitution = c.number("material.restitution");
  col.particle_friction = c.number("material.particle_friction");
  s.collisional = c.boolean("collisional.enabled");
  col.jamming_fraction = c.number("collisional.jamming_fraction");
  col.radial_distribution = model::parse_radial_distribution(c.string("collisional.radial_distribution"));
  col.effective_restitution =
      model::parse_effective_restitution(c.string("collisional.effective_restitution"));
  col.correlation_length = model::parse_correlation_length(c.string("collisional.correlation_length"));
  col.correlation_length_constant = c.number("collisional.correlation_length_constant");

  auto& liq = s.liquid_parameters;
  s.liquid = c.boolean("liquid.enabled");
  s.fluctuation_dissipation = s.liquid && c.boolean("liquid.fluctuation_dissipation");
  liq.viscosity = c.number("liquid.viscosity");
  liq.density = c.number("liquid.density");
  liq.bulk_modulus = c.number("liquid.bulk_modulus");
  liq.mixture_viscosity = model::parse_mixture_viscosity(c.string("liquid.mixture_viscosity"));
  liq.maximum_packing = c.number("liquid.maximum_packing");
  liq.permeability = model::parse_permeability(c.string("liquid.permeability"));
  liq.sphericity = c.number("liquid.sphericity");
  if (!s.collisional && !s.liquid)
    c.fail("collisional.enabled", "at least one stress term must be switched on "
                                  "(collisional.enabled or liquid.enabled)");
  return s;
}

}  // namespace granflow::continuum
