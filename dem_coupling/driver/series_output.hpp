// granflow-dem's output tables: series.tsv (one row per sample: step, box, stress parts, the
// derived observables, the contact network, and the shear-stress split of immersed runs) and
// profile.tsv (mean v_x per y bin). Reals are written with 10 significant digits (momenta and
// the immersed split with 17); as_written gives a value as the kind reads it back, for the
// stopping rule (stopping_rule.hpp) that must see what the kind sees.
#pragma once

#include <cstdio>

#include "dem_coupling/extraction/contact_network.hpp"
#include "dem_coupling/extraction/shear_sample.hpp"

namespace granflow::dem {

// Immersed runs (deck defines gf_viscosity and fix gf_fluid, docs/dem_fluid.md): the shear
// stress split into contact, lubrication, drag and kinetic parts, appended to each series row.
struct FluidStress {
  double contact = 0, lubrication = 0, drag = 0, kinetic = 0, lubricated_pairs = 0;
  double pressure = 0;  // hydrodynamic part of tr(P)/3: lubrication (normal + tangential) + drag
};

void write_series_header(std::FILE* f, bool wet);

// One row of series.tsv, flushed (a run stopped by an error keeps what it wrote); `fluid` for
// immersed runs, else nullptr.
void write_series_row(std::FILE* f, const ShearSample& s, double overlap,
                      const NetworkState& network, const FluidStress* fluid);

void write_profile_row(std::FILE* f, const ShearSample& s);

// `value` as series.tsv holds it: printed "%.10g" (write_series_row) and read back as
// read_series_table (kind/series_table.cpp) does with std::stod, which gives NaN for a text it
// cannot read or that is out of range.
double as_written(double value);

}  // namespace granflow::dem
