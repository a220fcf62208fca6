// `kind: dem_prepare`: a packing at rest at the mean stress p0, prepared with the friction
// μ_prep (deck/preparation_deck.hpp, driver/prepare_stage.hpp), written for the `kind: dem`
// runs that start from it (start.preparation; kind/transient.hpp). docs/transient_dem.md.
#pragma once

#include <filesystem>

#include "core/kind_registry.hpp"

namespace granflow::dem {

void register_prepare_kind(core::KindRegistry& registry);

// The directory of one seed's prepared state in a preparation run directory.
std::filesystem::path prepared_seed_directory(const std::filesystem::path& run_dir, long seed);

}  // namespace granflow::dem
