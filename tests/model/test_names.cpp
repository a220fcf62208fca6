// Closure option names (case-file values) parse back to their enums; unknown names are refused
// with the list of valid ones.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "continuum/model/closures.hpp"

namespace gm = granflow::model;

namespace {
template <typename Kind, typename Parse>
void check_round_trip_and_refusal(const std::vector<std::string>& names, Parse parse) {
  ASSERT_FALSE(names.empty());
  for (std::size_t i = 0; i < names.size(); ++i) {
    EXPECT_EQ(parse(names[i]), static_cast<Kind>(i)) << names[i];
  }
  try {
    parse("no_such_closure");
    ADD_FAILURE() << "unknown name accepted";
  } catch (const std::invalid_argument& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("no_such_closure"), std::string::npos) << message;
    for (const auto& name : names) EXPECT_NE(message.find(name), std::string::npos) << message;
  }
  EXPECT_THROW(parse(""), std::invalid_argument);
  EXPECT_THROW(parse(names.front() + " "), std::invalid_argument);  // no silent trimming
}
}  // namespace

TEST(ClosuresNames, RoundTripAndRefusal) {
  check_round_trip_and_refusal<gm::RadialDistributionKind>(gm::radial_distribution_names(),
                                                           gm::parse_radial_distribution);
  check_round_trip_and_refusal<gm::EffectiveRestitutionKind>(gm::effective_restitution_names(),
                                                             gm::parse_effective_restitution);
  check_round_trip_and_refusal<gm::CorrelationLengthKind>(gm::correlation_length_names(),
                                                          gm::parse_correlation_length);
  check_round_trip_and_refusal<gm::MixtureViscosityKind>(gm::mixture_viscosity_names(),
                                                         gm::parse_mixture_viscosity);
  check_round_trip_and_refusal<gm::PermeabilityKind>(gm::permeability_names(),
                                                     gm::parse_permeability);
}

TEST(ClosuresNames, EnumCountsMatchNameLists) {
  // The enum and the names come from one list per family (closures.hpp), so they cannot differ
  // in length; the last enumerator is the last name, and each name is its enumerator's spelling.
  static_assert(std::size(gm::radial_distribution_table) == 3);
  static_assert(gm::radial_distribution_table[static_cast<int>(
                    gm::RadialDistributionKind::torquato)] == "torquato");
  static_assert(gm::permeability_table[static_cast<int>(gm::PermeabilityKind::ergun)] == "ergun");
  EXPECT_EQ(gm::parse_radial_distribution(gm::radial_distribution_names().back()),
            gm::RadialDistributionKind::chialvo_sundaresan);
  EXPECT_EQ(gm::parse_effective_restitution(gm::effective_restitution_names().back()),
            gm::EffectiveRestitutionKind::chialvo_sundaresan);
  EXPECT_EQ(gm::parse_correlation_length(gm::correlation_length_names().back()),
            gm::CorrelationLengthKind::toward_jamming);
  EXPECT_EQ(gm::parse_mixture_viscosity(gm::mixture_viscosity_names().back()),
            gm::MixtureViscosityKind::boyer);
  EXPECT_EQ(gm::parse_permeability(gm::permeability_names().back()), gm::PermeabilityKind::ergun);
}
