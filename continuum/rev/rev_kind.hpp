// `kind: rev` cases: material-point (REV) tests of the continuum model.
#pragma once

#include "continuum/rev/element_test.hpp"
#include "core/case.hpp"
#include "core/kind_registry.hpp"

namespace granflow::rev {
void register_rev_kinds(core::KindRegistry& registry);
core::Schema simple_shear_schema();
core::Schema triaxial_schema();                                  // triaxial_kind.cpp
core::Schema isotropic_compression_schema();                     // triaxial_kind.cpp
void register_element_test_kinds(core::KindRegistry& registry);  // triaxial_kind.cpp
// The stages of a validated `test: triaxial` case (triaxial_kind.cpp).
TriaxialControl read_triaxial_control(const core::Case& c);
}  // namespace granflow::rev
