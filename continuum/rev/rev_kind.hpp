// `kind: rev` cases: material-point (REV) tests of the continuum model.
#pragma once

#include "core/kind_registry.hpp"

namespace granflow::rev {
void register_rev_kinds(core::KindRegistry& registry);
core::Schema simple_shear_schema();
}  // namespace granflow::rev
