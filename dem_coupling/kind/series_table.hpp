// Reads the tab-separated tables written by granflow-dem (header line of column names, then
// rows of numbers; lines starting with '#' are comments). A truncated last line (a run killed
// while writing) is dropped.
#pragma once

#include <filesystem>
#include <map>
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

}  // namespace granflow::dem
