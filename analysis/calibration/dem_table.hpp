// Steady simple-shear tables from any DEM code (docs/calibration.md, "Bring your own DEM data"):
// CSV or whitespace-separated text, '#' comment lines, one header row, one row per steady
// condition. Quantities carry the names of granflow's own DEM results (/steady in result.h5,
// docs/dem_dataset.md); `columns` maps a quantity to a header name where the table names it
// otherwise. What a table lacks is derived where its other columns imply it:
//     γ̇ = I sqrt(σ_yy/ρ_p)/d,   σ_yy = ρ_p (γ̇ d/I)²,   μ = τ/σ_yy,   T* = T/(d γ̇)²,
// and `pressure` (tr σ/3) stands for σ_yy when the table has no normal_stress (the steady model's
// normal stresses are equal, docs/model/steady_state.md). Dimensionless tables are in units of
// d = ρ_p = γ̇ = 1 (stresses in ρ_p d² γ̇², T in (d γ̇)², η0 in ρ_p d² γ̇).
// Comment lines `# protocol: NAME`, `# units: NAME`, `# particle_friction: VALUE` state the
// table's own metadata (a case key that disagrees is an error).
#pragma once

#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/calibration/calibration.hpp"

namespace granflow::calibration {

// The quantities a table may hold (granflow's /steady names), in the order of the docs.
const std::vector<std::string>& table_quantities();

struct TableSpec {
  std::filesystem::path file;
  std::string protocol;                        // the case's data.protocol ("" when not given)
  std::string units;                           // the case's data.units ("" when not given)
  std::map<std::string, std::string> columns;  // quantity -> header name (data.columns)
  std::map<std::string, std::string> errors;   // quantity -> header name of its standard error
  double particle_friction = NAN;              // data.particle_friction (NaN when not given)
  double diameter = 0, particle_density = 0;   // the case's material (SI tables)
  int source_index = 0;
};

// A bad table: `line` is the table's line (1-based; 0 when the problem is not on one line),
// `key` the case key it concerns ("data.table", "data.columns.friction", "data.protocol", ...),
// `problem` what was found and expected.
class TableError : public std::runtime_error {
 public:
  TableError(int line, std::string key, const std::string& problem);
  int line;
  std::string key;
};

struct DemTable {
  DemDataset set;  // diameter and particle_density: 1 for a dimensionless table
  std::string units;
  std::vector<std::string> derived;  // e.g. "friction = shear_stress / normal_stress"
  std::vector<std::string> errors;   // per observable: the columns its standard error comes from
  std::vector<std::string> unused;   // header columns not read
};

// Reads and checks the whole table; throws TableError (missing or unknown column, a field that is
// not a finite number, φ outside (0, 0.74], σ_yy ≤ 0, T < 0, γ̇ ≤ 0, a negative error, protocol
// neither given nor stated, a dimensionless table with a shear rate other than 1) or
// std::runtime_error when the file cannot be read.
DemTable read_dem_table(const TableSpec& spec);

}  // namespace granflow::calibration
