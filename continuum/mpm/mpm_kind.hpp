// The `mpm` case kind: the double-point MPM problems run from case files (cases/mpm/*.yaml),
// tests `terzaghi`, `couette`, `elastic_column` (verification) and `rheometer`.
#pragma once

#include "core/kind_registry.hpp"

namespace granflow::mpm {

void register_mpm_kinds(core::KindRegistry& registry);

}  // namespace granflow::mpm
