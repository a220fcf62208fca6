#include "dem_coupling/kind/series_table.hpp"

#include <algorithm>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace granflow::dem {

const std::vector<double>& SeriesTable::at(const std::string& name) const {
  const auto it = columns.find(name);
  if (it == columns.end()) throw std::out_of_range("series table has no column " + name);
  return it->second;
}

SeriesTable read_series_table(const std::filesystem::path& file, bool header) {
  SeriesTable t;
  std::ifstream in(file);
  if (!in) return t;
  std::string line;
  bool have_names = !header;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    if (!have_names) {
      for (std::string name; std::getline(fields, name, '\t');) t.names.push_back(name);
      for (const auto& n : t.names) t.columns[n];
      have_names = true;
      continue;
    }
    std::vector<double> row;
    for (std::string cell; std::getline(fields, cell, '\t');) {
      try {
        row.push_back(std::stod(cell));
      } catch (const std::exception&) {
        row.push_back(std::numeric_limits<double>::quiet_NaN());
      }
    }
    if (t.names.empty())
      for (std::size_t k = 0; k < row.size(); ++k) {
        t.names.push_back(std::to_string(k));
        t.columns[t.names.back()];
      }
    if (row.size() != t.names.size()) break;  // truncated last line of a killed run
    for (std::size_t k = 0; k < row.size(); ++k) t.columns[t.names[k]].push_back(row[k]);
  }
  return t;
}

std::size_t shear_rows(std::span<const double> strain) {
  if (strain.empty()) return 0;
  return std::size_t(std::find(strain.begin(), strain.end(), strain.back()) - strain.begin()) + 1;
}

}  // namespace granflow::dem
