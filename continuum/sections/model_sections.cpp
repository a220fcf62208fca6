#include "continuum/sections/model_sections.hpp"

#include <fmt/format.h>

namespace granflow::continuum {

core::Field material_section() {
  core::Field m("material", core::ValueType::section, "", "grain properties (shared with the DEM)");
  m.number("diameter", "m", "mean grain diameter d").required().greater_than(0);
  // From 1 kg/m^3, lighter than any granular solid: far below it stresses and time scales
  // underflow.
  m.number("particle_density", "kg/m^3", "grain density ρ_p").required().at_least(1);
  m.number("restitution", "", "normal coefficient of restitution e_r")
      .required()
      .greater_than(0)
      .at_most(1);
  m.number("particle_friction", "", "interparticle friction coefficient μ_p")
      .default_value("0.5")
      .at_least(0);
  m.number("youngs_modulus", "Pa", "grain Young's modulus (DEM contact stiffness)")
      .default_value("1.0e7")
      .greater_than(0);
  m.number("poisson_ratio", "", "grain Poisson ratio (DEM)")
      .default_value("0.3")
      .greater_than(-1)
      .less_than(0.5);
  return m;
}

core::Field collisional_section() {
  core::Field c("collisional", core::ValueType::section, "",
                "extended kinetic theory term σ_COL, Γ and the T balance (docs/model/closures.md)");
  c.boolean("enabled", "switch the collisional term on/off").default_value("true");
  c.choice("radial_distribution", model::radial_distribution_names(), "g0 at contact")
      .default_value("chialvo_sundaresan");
  c.number("jamming_fraction", "", "ν_c where g0 diverges (≈0.639 frictionless, ≈0.587 at μ_p=0.5)")
      .default_value("0.587")
      .greater_than(0.49)
      .less_than(0.74);
  c.choice("effective_restitution", model::effective_restitution_names(),
           "ε in Γ: the plain restitution or the Chialvo-Sundaresan frictional correction")
      .default_value("chialvo_sundaresan");
  c.choice("correlation_length", model::correlation_length_names(),
           "L in Γ: the diameter (standard kinetic theory), Jenkins' extended length, or a "
           "length growing toward jamming, L/d = 1 + c (ν-ν_L)/(ν_c-ν)^n (docs/model/closures.md)")
      .default_value("diameter");
  c.number("correlation_length_constant", "",
           "c of Jenkins' correlation length, or c_L of toward_jamming")
      .default_value("0.5")
      .greater_than(0);
  c.number("correlation_length_onset", "",
           "ν_L of toward_jamming: L = d at ν ≤ ν_L (0.49, the freezing fraction of hard spheres)")
      .default_value("0.49")
      .greater_than(0)
      .less_than(0.74);
  c.number("correlation_length_exponent", "", "n of toward_jamming: L/d grows as (ν_c - ν)^-n")
      .default_value("1.5")
      .greater_than(0)
      .at_most(4);
  c.number("inertial_contact", "",
           "a_c: the contacts' stress of dense inertial flow of rigid grains, p_IC = "
           "ρ_p (a_c d γ̇)² (ν_c - ν)^-m, sheared at the force chains' critical state friction "
           "(granflow's own term after φ = φ_c - a I of GDR MiDi 2004 and da Cruz et al. 2005; "
           "the steady model shears it at μ_FC with its friction rise; 0 = off, the seed's model)")
      .default_value("0")
      .at_least(0);
  c.number("inertial_contact_power", "",
           "m: the contacts' dense inertial stress grows as (ν_c - ν)^-m (2: φ = φ_c - a I)")
      .default_value("2")
      .greater_than(0);
  c.number("inertial_contact_friction", "",
           "μ_IC: the friction that shears the contacts' dense inertial stress, τ_IC = μ_IC p_IC; "
           "0 = the force chains' own (the steady model's μ_FC with its rise, M(θ=0)/√3 in the "
           "REV and the MPM)")
      .default_value("0")
      .at_least(0);
  return c;
}

core::Field liquid_section() {
  core::Field l("liquid", core::ValueType::section, "",
                "interstitial liquid: σ_L, η(ν), drag, Λ (docs/model/closures.md)");
  l.boolean("enabled", "switch the liquid terms on/off (off: dry)").default_value("false");
  l.number("viscosity", "Pa s", "liquid viscosity η0").default_value("1.0e-3").greater_than(0);
  l.number("density", "kg/m^3", "liquid density ρ_L").default_value("1000").greater_than(0);
  l.number("bulk_modulus", "Pa", "liquid bulk modulus K_w").default_value("2.2e9").greater_than(0);
  l.choice("mixture_viscosity", model::mixture_viscosity_names(), "η(ν) closure")
      .default_value("boyer");
  l.number("maximum_packing", "", "ν_m of the Krieger-Dougherty / Boyer viscosity")
      .default_value("0.585")
      .greater_than(0.3)
      .less_than(0.74);
  l.choice("permeability", model::permeability_names(), "permeability κ(e) closure for the drag")
      .default_value("seed_eq26");
  l.number("sphericity", "", "A in seed Eq. 26 (1 for spheres)")
      .default_value("1")
      .greater_than(0)
      .at_most(1);
  l.boolean("fluctuation_dissipation", "Λ: fluctuation energy given to the liquid")
      .default_value("true");
  std::vector<std::string> dissipation_g0 = {"collisional"};
  for (const auto& name : model::radial_distribution_names()) dissipation_g0.push_back(name);
  l.choice("dissipation_radial_distribution", dissipation_g0,
           "g0 in the resistance R_diss of Λ (its lubrication term ν g0 ln(1/ε_m)): collisional = "
           "collisional.radial_distribution; or a g0 option of its own at ν (with "
           "collisional.jamming_fraction for those with a pole), e.g. carnahan_starling, the "
           "hard-sphere structure's, when the collisional g0's pole is a fit to stresses")
      .default_value("collisional");
  l.number("viscous_contact", "",
           "b_v: the viscous scale of the contacts' dense-flow stress, p_IC = [ρ_p (a_c d γ̇)² + "
           "b_v η0 γ̇] (ν_c - ν)^-m (collisional.inertial_contact_*; the contact part of the "
           "suspension rheology of Boyer et al. 2011 that η(ν) leaves out; 0 = off)")
      .default_value("0")
      .at_least(0);
  l.number("trulsson_alpha", "",
           "α of K = J + α I² (reporting, and the mixed number sqrt(K/α) of the steady model's "
           "friction rise)")
      .default_value("0.6")
      .greater_than(0);
  return l;
}

namespace {
std::string yaml_number(double value) { return fmt::format("{}", value); }
}  // namespace

core::Field force_chains_section(bool enabled_by_default) {
  using model::force_chains::ForceChainParameters;
  const ForceChainParameters d{};
  core::Field f(
      "force_chains", core::ValueType::section, "",
      "force-chain term σ_FC = σ' (strain-hardening elasto-plasticity, docs/model/force_chains.md; "
      "equations and sources in docs/model/force_chains.md). Compression positive.");
  f.boolean("enabled",
            enabled_by_default
                ? "switch the force-chain term on/off (off: the kinetic-theory-only steady model)"
                : "switch the force-chain term on/off")
      .default_value(enabled_by_default ? "true" : "false");
  auto num = [&](const char* key, const char* unit, const char* doc, double value) -> core::Field& {
    return f.number(key, unit, doc).default_value(yaml_number(value));
  };
  num("bulk_modulus_ref", "Pa", "K_ref of K = K_ref (max(p', p_floor)/p_ref)^n", d.bulk_modulus_ref)
      .greater_than(0);
  num("reference_pressure", "Pa", "p_ref of the elastic law", d.reference_pressure).greater_than(0);
  num("elastic_exponent", "", "n of the elastic law", d.elastic_exponent).at_least(0).less_than(1);
  num("poisson_ratio", "", "Poisson ratio of the skeleton (constant)", d.poisson_ratio)
      .greater_than(-1)
      .less_than(0.5);
  num("pressure_floor", "Pa", "p_floor: K stays K(p_floor) > 0 below it", d.pressure_floor)
      .greater_than(0);
  num("beta_f", "", "β_f of the di Prisco et al. (1993) yield locus", d.beta_f).greater_than(0);
  num("gamma", "", "γ of the yield locus (> 3: closed locus)", d.gamma).greater_than(3);
  num("b_p", "", "plastic compressibility b_p: dr_c = (r_c/b_p)(dε^p_v + ξ dε^p_q)", d.b_p)
      .greater_than(0);
  num("xi_psi", "", "ξ_ψ: deviatoric softening of looser-than-critical states (ψ > 0)", d.xi_psi)
      .at_least(0);
  num("xi_psi_dense", "", "ξ_ψ,d: deviatoric hardening of denser-than-critical states (ψ < 0)",
      d.xi_psi_dense)
      .at_least(0);
  num("c_p", "", "rotational hardening rate of the axis χ", d.c_p).at_least(0);
  num("theta_hat_c", "rad", "target axis angle θ̂_c in triaxial compression", d.theta_hat_c)
      .at_least(0)
      .less_than(1.5);
  num("theta_hat_e", "rad", "target axis angle θ̂_e in triaxial extension", d.theta_hat_e)
      .at_least(0)
      .less_than(1.5);
  num("M_c", "", "critical stress ratio q/p' in triaxial compression (Lade-Duncan locus)", d.M_c)
      .greater_than(0)
      .less_than(3);
  num("e_Gamma", "", "e_Γ: critical void ratio at p' = 0, e_cs = e_Γ - λ_c (p'/p_atm)^ξ_c",
      d.e_Gamma)
      .greater_than(0);
  num("lambda_c", "", "λ_c of the critical state line", d.lambda_c).at_least(0);
  num("xi_c", "", "ξ_c of the critical state line", d.xi_c).greater_than(0);
  num("atmospheric_pressure", "Pa",
      "p_atm, the reference pressure of the critical state line (101.325 kPa for sand; the "
      "stress scale of the sample for DEM spheres, e.g. 100 Pa)",
      d.atmospheric_pressure)
      .greater_than(0);
  num("e_min", "", "minimum void ratio (state parameter bounds, regrowth)", d.e_min)
      .greater_than(0);
  num("e_max", "", "maximum void ratio (no regrowth above it)", d.e_max).greater_than(0);
  num("d_0", "", "d_0 of the dilatancy D = d_0 (M_c exp(n_d ψ) - η̃)/η̃", d.d_0).greater_than(0);
  num("n_d", "", "n_d of the dilatancy", d.n_d);
  num("fluidization_size", "Pa", "r_c below which the force chains vanish (σ_FC = 0)",
      d.fluidization_size)
      .greater_than(0);
  num("resolidification_size", "Pa", "r_c at which a regrowing skeleton is solid again",
      d.resolidification_size)
      .greater_than(0);
  num("regrowth_modulus", "Pa", "K_r: dr_c = w(T) K_r <dε_v> while fluidized", d.regrowth_modulus)
      .at_least(0);
  num("regrowth_temperature", "m^2/s^2", "T_r: w(T) = max(0, 1 - T/T_r)", d.regrowth_temperature)
      .greater_than(0);
  num("stress_tolerance", "", "STOL: relative local error per plastic sub-step", d.stress_tolerance)
      .greater_than(0);
  num("yield_tolerance", "", "FTOL: |f| accepted as on the locus", d.yield_tolerance)
      .greater_than(0);
  f.integer("fixed_substeps", "> 0: that many equal plastic sub-steps, no error control")
      .default_value(fmt::format("{}", d.fixed_substeps))
      .at_least(0);
  f.integer("max_substeps", "plastic sub-steps per update at most")
      .default_value(fmt::format("{}", d.max_substeps))
      .at_least(1);
  return f;
}

core::Field steady_section() {
  core::Field s("steady", core::ValueType::section, "",
                "steady simple-shear forward model of pair and calibrate (docs/model/"
                "steady_state.md)");
  s.number("contact_production", "",
           "α_FC: fraction of the force chains' shear work τ_FC γ̇ fed to the granular "
           "temperature (granflow's own term; 0 = the seed's model: only σ_COL : D produces T)")
      .default_value("0")
      .at_least(0)
      .at_most(1);
  s.number("friction_rise", "",
           "Δμ_FC: rise of the force chains' friction with I, μ_FC = μ_cs + Δμ_FC/(1 + I_0/X), "
           "X = I dry, sqrt(I² + J/α) immersed "
           "(granflow's own extension after the μ(I) law of GDR MiDi 2004; 0 = the seed's "
           "rate-independent skeleton)")
      .default_value("0")
      .at_least(0);
  s.number("viscous_dilatancy", "",
           "a_J: immersed, the skeleton's critical void ratio e_Γ + a_J √J (granflow's own "
           "extension after Boyer et al. 2011, φ(J) = φ_m/(1 + √J): a_J ≈ 1/φ_m; 0 = the seed's "
           "critical state)")
      .default_value("0")
      .at_least(0);
  s.number("friction_rise_I0", "", "I_0 of the force chains' friction rise")
      .default_value("0.3")
      .greater_than(0);
  s.choice("skeleton_stress", {"lode_zero", "force_chain_model"},
           "stress state of the skeleton on its critical state in simple shear: lode_zero "
           "(σ_xx = σ_yy = σ_zz, τ/σ_yy = M(θ=0)/√3, closed form) or force_chain_model (the state "
           "the force-chain model reaches, as the time-stepped REV; integrated once per parameter "
           "set)")
      .default_value("lode_zero");
  return s;
}

namespace {
model::force_chains::ForceChainParameters read_force_chain_parameters(const core::Case& c) {
  model::force_chains::ForceChainParameters p;
  const auto get = [&](const char* key) { return c.number(std::string("force_chains.") + key); };
  p.bulk_modulus_ref = get("bulk_modulus_ref");
  p.reference_pressure = get("reference_pressure");
  p.elastic_exponent = get("elastic_exponent");
  p.poisson_ratio = get("poisson_ratio");
  p.pressure_floor = get("pressure_floor");
  p.beta_f = get("beta_f");
  p.gamma = get("gamma");
  p.b_p = get("b_p");
  p.xi_psi = get("xi_psi");
  p.xi_psi_dense = get("xi_psi_dense");
  p.c_p = get("c_p");
  p.theta_hat_c = get("theta_hat_c");
  p.theta_hat_e = get("theta_hat_e");
  p.M_c = get("M_c");
  p.e_Gamma = get("e_Gamma");
  p.lambda_c = get("lambda_c");
  p.xi_c = get("xi_c");
  p.atmospheric_pressure = get("atmospheric_pressure");
  p.e_min = get("e_min");
  p.e_max = get("e_max");
  p.d_0 = get("d_0");
  p.n_d = get("n_d");
  p.fluidization_size = get("fluidization_size");
  p.resolidification_size = get("resolidification_size");
  p.regrowth_modulus = get("regrowth_modulus");
  p.regrowth_temperature = get("regrowth_temperature");
  p.stress_tolerance = get("stress_tolerance");
  p.yield_tolerance = get("yield_tolerance");
  p.fixed_substeps = static_cast<int>(c.integer("force_chains.fixed_substeps"));
  p.max_substeps = static_cast<int>(c.integer("force_chains.max_substeps"));
  try {
    model::force_chains::validate(p);
  } catch (const std::invalid_argument& error) {
    // "force_chains.<key>: expected ..." -> located at that key
    const std::string message = error.what();
    const auto colon = message.find(':');
    std::string key = message.substr(0, colon);
    if (key.find('/') != std::string::npos) key = "force_chains.e_max";
    c.fail(key, message.substr(colon + 2));
  }
  return p;
}
}  // namespace

MultiRegimeSettings read_multi_regime_settings(const core::Case& c) {
  MultiRegimeSettings s;
  auto& col = s.collisional_parameters;
  col.diameter = c.number("material.diameter");
  col.particle_density = c.number("material.particle_density");
  col.restitution = c.number("material.restitution");
  col.particle_friction = c.number("material.particle_friction");
  s.collisional = c.boolean("collisional.enabled");
  col.jamming_fraction = c.number("collisional.jamming_fraction");
  col.radial_distribution =
      model::parse_radial_distribution(c.string("collisional.radial_distribution"));
  col.effective_restitution =
      model::parse_effective_restitution(c.string("collisional.effective_restitution"));
  col.correlation_length =
      model::parse_correlation_length(c.string("collisional.correlation_length"));
  col.correlation_length_constant = c.number("collisional.correlation_length_constant");
  col.correlation_length_onset = c.number("collisional.correlation_length_onset");
  col.correlation_length_exponent = c.number("collisional.correlation_length_exponent");
  s.inertial_contact = c.number("collisional.inertial_contact");
  s.inertial_contact_power = c.number("collisional.inertial_contact_power");
  s.inertial_contact_friction = c.number("collisional.inertial_contact_friction");
  s.viscous_contact = c.number("liquid.viscous_contact");

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
  if (const std::string g0 = c.string("liquid.dissipation_radial_distribution");
      g0 != "collisional") {
    liq.dissipation_radial_distribution = model::parse_radial_distribution(g0);
    liq.dissipation_jamming_fraction = c.number("collisional.jamming_fraction");
  }
  if (c.schema().child("force_chains") != nullptr) {
    s.force_chains = c.boolean("force_chains.enabled");
    if (s.force_chains) s.force_chain_parameters = read_force_chain_parameters(c);
  }
  if (!s.collisional && !s.liquid && !s.force_chains)
    c.fail("collisional.enabled",
           "at least one stress term must be switched on "
           "(force_chains.enabled, collisional.enabled or liquid.enabled)");
  return s;
}

}  // namespace granflow::continuum
