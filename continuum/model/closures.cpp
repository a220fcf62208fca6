// Name registries of the closure options (case-file names <-> enums) and the cold-path error
// reporting of the inline closures. Everything evaluated per point is inline in the headers.
#include "continuum/model/closures.hpp"

#include <array>
#include <stdexcept>
#include <string>

namespace granflow::model {
namespace {

// Names in enum order (closures.hpp's tables); the enum value is the index.
template <typename Kind>
Kind parse_kind(std::string_view option, std::string_view name,
                const std::vector<std::string>& names) {
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return static_cast<Kind>(i);
  }
  std::string message =
      "unknown " + std::string(option) + " '" + std::string(name) + "'; expected one of: ";
  for (std::size_t i = 0; i < names.size(); ++i) {
    message += (i ? ", " : "") + names[i];
  }
  throw std::invalid_argument(message);
}

template <std::size_t N>
std::vector<std::string> as_strings(const std::string_view (&table)[N]) {
  return {std::begin(table), std::end(table)};
}

}  // namespace

const std::vector<std::string>& radial_distribution_names() {
  static const std::vector<std::string> names = as_strings(radial_distribution_table);
  return names;
}
const std::vector<std::string>& effective_restitution_names() {
  static const std::vector<std::string> names = as_strings(effective_restitution_table);
  return names;
}
const std::vector<std::string>& correlation_length_names() {
  static const std::vector<std::string> names = as_strings(correlation_length_table);
  return names;
}
const std::vector<std::string>& mixture_viscosity_names() {
  static const std::vector<std::string> names = as_strings(mixture_viscosity_table);
  return names;
}
const std::vector<std::string>& permeability_names() {
  static const std::vector<std::string> names = as_strings(permeability_table);
  return names;
}

RadialDistributionKind parse_radial_distribution(std::string_view name) {
  return parse_kind<RadialDistributionKind>("radial distribution", name,
                                            radial_distribution_names());
}
EffectiveRestitutionKind parse_effective_restitution(std::string_view name) {
  return parse_kind<EffectiveRestitutionKind>("effective restitution", name,
                                              effective_restitution_names());
}
CorrelationLengthKind parse_correlation_length(std::string_view name) {
  return parse_kind<CorrelationLengthKind>("correlation length", name, correlation_length_names());
}
MixtureViscosityKind parse_mixture_viscosity(std::string_view name) {
  return parse_kind<MixtureViscosityKind>("mixture viscosity", name, mixture_viscosity_names());
}
PermeabilityKind parse_permeability(std::string_view name) {
  return parse_kind<PermeabilityKind>("permeability", name, permeability_names());
}

namespace detail {

void throw_solid_fraction_out_of_range(const char* closure, double nu, double lower, double upper) {
  throw std::domain_error(std::string(closure) + ": solid fraction nu = " + std::to_string(nu) +
                          " outside its domain (" + std::to_string(lower) + ", " +
                          std::to_string(upper) +
                          ") (singular closure or beyond jamming / maximum packing)");
}

void throw_bad_jamming_fraction(const char* closure, double jamming_fraction) {
  throw std::invalid_argument(std::string(closure) +
                              ": jamming fraction nu_c = " + std::to_string(jamming_fraction) +
                              " invalid (expected 0 < nu_c < 1, and nu_c > 0.49 for torquato)");
}

}  // namespace detail
}  // namespace granflow::model
