// `granflow export RUN_DIR --csv [--out DIR]`: every table of RUN_DIR/result.h5 as CSV, for
// users without Python (docs/results.md).
#pragma once

#include <filesystem>

namespace granflow::app {

// One CSV per table (the one-dimensional datasets of a group that share its most common length,
// the rule of analysis/python/granflow_results.py), named after the group ("/conditions/0/series"
// -> conditions_0_series.csv), header "name [unit]"; a dataset outside its group's table (2-D, or
// another length) gets a CSV of its own (GROUP_NAME.csv); the attributes of every group and
// dataset go to attributes.csv (object, name, value). Numbers with 17 significant digits
// (doubles round-trip), integers as integers. Returns the number of files written; throws
// std::runtime_error naming the file on an unreadable result.h5 or an unwritable DIR.
int export_csv(const std::filesystem::path& run_dir, const std::filesystem::path& out_dir);

}  // namespace granflow::app
