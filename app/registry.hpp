// The registry of every case kind this build knows, built explicitly (no static registration).
#pragma once

#include "core/kind_registry.hpp"

namespace granflow::app {
core::KindRegistry make_registry();
}
