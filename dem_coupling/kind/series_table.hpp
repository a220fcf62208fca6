// Reads the tab-separated tables written by granflow-dem (header line of column names, then
// rows of numbers; lines starting with '#' are comments). A truncated last line (a run killed
// while writing) is dropped.
#pragma once

#include <filesystem>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace granflow::dem {

struct SeriesTable {
  std::vector<std::string> names;  // column names in file order
  std::map<std::string, std::vector<double>> columns;
  std::size_t rows() const { return columns.empty() ? 0 : columns.begin()->second.size(); }
  const std::vector<double>& at(const std::string& name) const;  // throws std::out_of_range
};

// `header` false: columns are named "0", "1", ... (the profile table).
SeriesTable read_series_table(const std::filesystem::path& file, bool header = true);

// Rows of a series that belong to the shear when a stop stage followed it (stop.duration): the
// stop's rows repeat the strain of the stop (the last shear row's), so the shear ends at the
// first row with the last strain.
std::size_t shear_rows(std::span<const double> strain);

}  // namespace granflow::dem
