// `kind: transient_pair` (docs/transient_pairs.md): the undrained (constant-volume) shear from
// rest of a prepared packing in the DEM (kind: dem with start.preparation, several seeds) and in
// the multi-regime REV (force chains + collisions, rev::run_simple_shear at constant volume),
// from one case file and so one material, started from the same state (the DEM's prepared φ0 and
// p0) and driven at the same γ̇; side by side p'(γ), σ_yy(γ), τ(γ) with the DEM's seed band and
// the transition metrics of both (dem::transient_metrics: peak τ and its strain, the strain at
// liquefaction, the residual τ). control.mode drained holds the total normal stress while the
// liquid drains over a length (both sides: the lumped Darcy law), and rate_step steps the shear
// rate (pair_stages.hpp compares the steps and the stops).
#pragma once

#include "core/kind_registry.hpp"

namespace granflow::transient_pair {

core::Schema transient_pair_schema();
void check_transient_pair_case(const core::Case& c);
// Before the run (KindEntry::check_inputs): the prepared states exist, the continuum can start at
// their φ0, and a `dem_run` is a finished kind: dem run of the same conditions.
void check_transient_pair_inputs(const core::Case& c);
int run_transient_pair_case(core::RunContext& ctx);

void register_transient_pair_kinds(core::KindRegistry& registry);

}  // namespace granflow::transient_pair
