// The collisional (extended kinetic theory) and liquid closures of docs/model/closures.md,
// gathered behind one value-type interface. Each closure lives in its own file
// (g0_carnahan_starling.hpp, permeability_kozeny_carman.hpp, ...) and is selected by name in the
// case file; the selection is an enum resolved once, so hot loops do a switch, never a string
// look-up or a virtual call.
//
// Conventions: SI units; ν = solid volume fraction = 1/(1+e); T = granular temperature (m²/s²);
// pressures compression-positive (docs/model/conventions.md).
#pragma once

#include <iterator>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace granflow::model {

// ---- closure families: one table each ------------------------------------------------------
// Each family is one list of its options, in the order of the enum, written once: the enum, the
// names of the case files (schema choices, docs) and their count all come from it, so an option
// cannot lack a name. A new option is one line in its family's list, its own header with the
// formula (included by closures_inline.hpp) and its case in the family's dispatch switch there
// (-Wswitch, an error in CI, names a switch that misses it).
#define GRANFLOW_RADIAL_DISTRIBUTIONS(X) X(carnahan_starling) X(torquato) X(chialvo_sundaresan)
#define GRANFLOW_EFFECTIVE_RESTITUTIONS(X) X(restitution) X(chialvo_sundaresan)
#define GRANFLOW_CORRELATION_LENGTHS(X) X(diameter) X(jenkins) X(toward_jamming)
#define GRANFLOW_MIXTURE_VISCOSITIES(X) X(einstein) X(krieger_dougherty) X(boyer)
#define GRANFLOW_PERMEABILITIES(X) X(seed_eq26) X(kozeny_carman) X(ergun)

#define GRANFLOW_CLOSURE_ENUMERATOR(option) option,
#define GRANFLOW_CLOSURE_NAME(option) #option,
enum class RadialDistributionKind { GRANFLOW_RADIAL_DISTRIBUTIONS(GRANFLOW_CLOSURE_ENUMERATOR) };
enum class EffectiveRestitutionKind {
  GRANFLOW_EFFECTIVE_RESTITUTIONS(GRANFLOW_CLOSURE_ENUMERATOR)
};
enum class CorrelationLengthKind { GRANFLOW_CORRELATION_LENGTHS(GRANFLOW_CLOSURE_ENUMERATOR) };
enum class MixtureViscosityKind { GRANFLOW_MIXTURE_VISCOSITIES(GRANFLOW_CLOSURE_ENUMERATOR) };
enum class PermeabilityKind { GRANFLOW_PERMEABILITIES(GRANFLOW_CLOSURE_ENUMERATOR) };

// Names as written in case files, in enum order (the enumerator's own spelling).
inline constexpr std::string_view radial_distribution_table[] = {
    GRANFLOW_RADIAL_DISTRIBUTIONS(GRANFLOW_CLOSURE_NAME)};
inline constexpr std::string_view effective_restitution_table[] = {
    GRANFLOW_EFFECTIVE_RESTITUTIONS(GRANFLOW_CLOSURE_NAME)};
inline constexpr std::string_view correlation_length_table[] = {
    GRANFLOW_CORRELATION_LENGTHS(GRANFLOW_CLOSURE_NAME)};
inline constexpr std::string_view mixture_viscosity_table[] = {
    GRANFLOW_MIXTURE_VISCOSITIES(GRANFLOW_CLOSURE_NAME)};
inline constexpr std::string_view permeability_table[] = {
    GRANFLOW_PERMEABILITIES(GRANFLOW_CLOSURE_NAME)};
#undef GRANFLOW_CLOSURE_ENUMERATOR
#undef GRANFLOW_CLOSURE_NAME

// A family's table by its enum, and every option of a family in enum order (the tests and the
// closure study iterate over them instead of listing the enumerators).
template <typename Kind>
struct ClosureFamily;
template <>
struct ClosureFamily<RadialDistributionKind> {
  static constexpr const auto& names = radial_distribution_table;
};
template <>
struct ClosureFamily<EffectiveRestitutionKind> {
  static constexpr const auto& names = effective_restitution_table;
};
template <>
struct ClosureFamily<CorrelationLengthKind> {
  static constexpr const auto& names = correlation_length_table;
};
template <>
struct ClosureFamily<MixtureViscosityKind> {
  static constexpr const auto& names = mixture_viscosity_table;
};
template <>
struct ClosureFamily<PermeabilityKind> {
  static constexpr const auto& names = permeability_table;
};
template <typename Kind>
std::vector<Kind> all_options() {
  std::vector<Kind> options;
  for (std::size_t i = 0; i < std::size(ClosureFamily<Kind>::names); ++i)
    options.push_back(static_cast<Kind>(i));
  return options;
}

// The same names as strings (schema choices, docs).
const std::vector<std::string>& radial_distribution_names();
const std::vector<std::string>& effective_restitution_names();
const std::vector<std::string>& correlation_length_names();
const std::vector<std::string>& mixture_viscosity_names();
const std::vector<std::string>& permeability_names();
// Parse a name; throws std::invalid_argument listing the valid names.
RadialDistributionKind parse_radial_distribution(std::string_view name);
EffectiveRestitutionKind parse_effective_restitution(std::string_view name);
CorrelationLengthKind parse_correlation_length(std::string_view name);
MixtureViscosityKind parse_mixture_viscosity(std::string_view name);
PermeabilityKind parse_permeability(std::string_view name);

// ---- parameters ----------------------------------------------------------------------------
struct CollisionalParameters {
  double diameter = 1e-3;            // d, m
  double particle_density = 2500.0;  // ρ_p, kg/m³
  double restitution = 0.7;          // e_r, normal restitution coefficient in (0, 1]
  double particle_friction = 0.5;    // μ_p, interparticle friction (for ε and ν_c)
  double jamming_fraction = 0.587;   // ν_c, singularity of g0 (friction dependent)
  RadialDistributionKind radial_distribution = RadialDistributionKind::chialvo_sundaresan;
  EffectiveRestitutionKind effective_restitution = EffectiveRestitutionKind::chialvo_sundaresan;
  CorrelationLengthKind correlation_length = CorrelationLengthKind::diameter;
  double correlation_length_constant = 0.5;  // c of the Jenkins length, c_L of toward_jamming
  double correlation_length_onset = 0.49;    // ν_L of toward_jamming (L = d below it)
  double correlation_length_exponent = 1.5;  // n of toward_jamming: L/d ∝ (ν_c - ν)^-n
};

struct LiquidParameters {
  double viscosity = 1e-3;      // η0, Pa s
  double density = 1000.0;      // ρ_L, kg/m³
  double bulk_modulus = 2.2e9;  // K_w, Pa
  MixtureViscosityKind mixture_viscosity = MixtureViscosityKind::boyer;
  double maximum_packing = 0.585;  // ν_m of Krieger-Dougherty / Boyer
  PermeabilityKind permeability = PermeabilityKind::seed_eq26;
  double sphericity = 1.0;  // A of seed Eq. 26
  // g0 in R_diss of Λ (liquid_fluctuation_dissipation): unset = the g0 the caller passes (the
  // collisional closures'); set = this option at ν (with the collisional jamming fraction for
  // the options with a pole), e.g. Carnahan-Starling, the pair distribution of the hard-sphere
  // structure rather than a jamming pole fitted to stresses.
  std::optional<RadialDistributionKind> dissipation_radial_distribution;
  double dissipation_jamming_fraction = 0.64;
};

// ---- collisional coefficients (docs/model/closures.md)
// -------------------------------------------------
struct CollisionalCoefficients {
  double nu = 0;       // ν
  double g0 = 0;       // radial distribution at contact
  double G = 0;        // ν g0
  double epsilon = 0;  // effective restitution ε
  double f1 = 0;       // p_COL = ρ_p f1 T
  double f2 = 0;       // shear viscosity ρ_p d f2 T^½
  double f3 = 0;       // dissipation Γ = ρ_p f3 T^{3/2} / L
  double f4 = 0;       // conductivity ρ_p d f4 T^½
  double J = 0;        // J(e_r, G) in f2
};

// Largest admissible ν for the chosen g0: ν_c (`jamming_fraction`) for every option, including
// Carnahan-Starling (finite up to ν = 1, but the model is not meant beyond jamming). Throws
// std::invalid_argument for ν_c outside (0, 1), or ν_c ≤ 0.49 with Torquato (branch point).
double maximum_solid_fraction(const CollisionalParameters& p);
// All coefficients at ν. Precondition 0 < ν < maximum_solid_fraction(p); outside it throws
// std::domain_error (guarded singularity).
CollisionalCoefficients collisional_coefficients(const CollisionalParameters& p, double nu);
// The same with the effective restitution ε = effective_restitution(p) given (a constant of the
// material: a hot loop evaluates it once instead of once per call).
CollisionalCoefficients collisional_coefficients(const CollisionalParameters& p, double nu,
                                                 double epsilon);

double effective_restitution(const CollisionalParameters& p);  // ε
// g0(ν) of the chosen option, no range check (collisional_coefficients() checks).
double radial_distribution(const CollisionalParameters& p, double nu);
// L, m (≥ d). Jenkins' L is unbounded at T = 0 or ε = 1 with γ̇ ≠ 0: +infinity there (Γ = 0);
// toward_jamming's depends on ν only (c.nu).
double correlation_length(const CollisionalParameters& p, const CollisionalCoefficients& c,
                          double shear_rate, double T);  // L, m (≥ d)
double collisional_pressure(const CollisionalParameters& p, const CollisionalCoefficients& c,
                            double T);  // ρ_p f1 T, Pa
double collisional_viscosity(const CollisionalParameters& p, const CollisionalCoefficients& c,
                             double T);  // ρ_p d f2 T^½, Pa s
double collisional_dissipation(const CollisionalParameters& p, const CollisionalCoefficients& c,
                               double T, double L);  // Γ, W/m³
double collisional_conductivity(const CollisionalParameters& p, const CollisionalCoefficients& c,
                                double T);  // ρ_p d f4 T^½, kg/(m s)
// Γ with L = correlation_length(p, c, shear_rate, T) folded in, written so that it stays finite
// (and exact) at T = 0: Γ = ρ_p f3 T² / (d ℓ max(T^½, a)), a = c [2J/(15(1-ε²))]^½ d |γ̇| for
// jenkins (else 0), ℓ = L/d of toward_jamming (else 1).
double collisional_dissipation_at_shear_rate(const CollisionalParameters& p,
                                             const CollisionalCoefficients& c, double shear_rate,
                                             double T);  // Γ, W/m³
// The T arguments above must be ≥ 0 (a negative T yields NaN, caught by the caller's
// check_finite with step, point and variable).

// ---- liquid (docs/model/closures.md)
// --------------------------------------------------------------------- Largest admissible ν for
// η(ν): ν_m (`maximum_packing`) for Krieger-Dougherty and Boyer (both singular there), 1 for
// Einstein.
double maximum_mixture_solid_fraction(const LiquidParameters& l);
// η(ν) for 0 ≤ ν < maximum_mixture_solid_fraction(l); outside it throws std::domain_error.
double mixture_viscosity(const LiquidParameters& l, double nu);  // η(ν), Pa s
// κ for 0 < ν < 1 (throws std::domain_error outside). Ergun: viscous part only (see below).
double permeability(const LiquidParameters& l, double diameter, double nu);  // κ, m²
// 1/κ for 0 ≤ ν < 1 (finite at ν = 0, where it is 0); used by the drag coefficients.
double inverse_permeability(const LiquidParameters& l, double diameter, double nu);  // m⁻²
// Inertial (Forchheimer) coefficient c_F of -∇p = (η0/κ) q + c_F |q| q, q = n (u_L - u_G):
// 1.75 ρ_L ν / (A d n³) for Ergun, 0 for the Darcy-only correlations. kg/m⁴.
double forchheimer_coefficient(const LiquidParameters& l, double diameter, double nu);
// Drag coefficient β of F = -β (u_L - u_G) per unit mixture volume (seed Eq. 25): η0 n / κ.
// Defined for 0 ≤ ν < 1 (β = 0 at ν = 0); Darcy part only for Ergun.
double drag_coefficient(const LiquidParameters& l, double diameter, double nu);  // kg/(m³ s)
// β + c_F n² |u_L - u_G| (Ergun's inertial term; equals drag_coefficient() for other options).
double drag_coefficient_with_inertia(const LiquidParameters& l, double diameter, double nu,
                                     double relative_speed);  // kg/(m³ s)
// Per-particle drag coefficient of the same correlation (DEM): f_p = c_p (u_f - v_p),
// c_p = β π d³ / (6 ν); tends to 3π η0 d for seed_eq26 as ν -> 0.
double particle_drag_coefficient(const LiquidParameters& l, double diameter, double nu);
double dissipation_resistance(double nu, double g0);  // R_diss(ν), 1 at ν=0
// Λ = 54 ν η0 R_diss T / d² (Koch & Sangani 1999), W/m³.
double liquid_fluctuation_dissipation(const LiquidParameters& l, double diameter, double nu,
                                      double g0, double T);

// Cold-path error reporting (closures.cpp), kept out of the inlined hot code.
namespace detail {
[[noreturn]] void throw_solid_fraction_out_of_range(const char* closure, double nu, double lower,
                                                    double upper);
[[noreturn]] void throw_bad_jamming_fraction(const char* closure, double jamming_fraction);
}  // namespace detail

}  // namespace granflow::model

// Inline definitions of everything above (dispatch by switch, so one evaluation inlines fully).
#include "continuum/model/closures_inline.hpp"
