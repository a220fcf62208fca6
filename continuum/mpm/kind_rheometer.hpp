// The rheometer of a case of kind `mpm` / `rheometer` as a run reads it (kind_rheometer.cpp), for
// programs that build the problem without running the kind (bench/bench_rheometer.cpp).
#pragma once

#include "continuum/mpm/rheometer.hpp"
#include "core/case.hpp"

namespace granflow::mpm::kind {

// Geometry, initial state, loading, model settings, liquid and solver options of the case
// (the internal length is the material's: solid.internal_length, solid.overnonlocal).
RheometerSpec read_rheometer(const core::Case& c);

}  // namespace granflow::mpm::kind
