#include "app/export_command.hpp"

#include <H5Cpp.h>
#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/file_io.hpp"

namespace granflow::app {

namespace {

namespace fs = std::filesystem;

// A CSV field: quoted when it holds a comma, a quote or a line break.
std::string field(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

// One dataset's values as text, one entry per element (row-major).
struct Values {
  std::vector<std::string> cells;
  std::size_t rows = 0, cols = 1;
  int rank = 1;  // 1: a column of a table; 2: a matrix of its own
};

std::string number(double v) { return fmt::format("{:.17g}", v); }

Values read_values(const H5::DataSet& set) {
  Values out;
  const H5::DataSpace space = set.getSpace();
  const int rank = space.getSimpleExtentNdims();
  std::vector<hsize_t> dims(std::max(rank, 1), 1);
  if (rank > 0) space.getSimpleExtentDims(dims.data());
  out.rows = rank > 0 ? dims[0] : 1;
  out.cols = rank > 1 ? dims[1] : 1;
  out.rank = rank;
  const auto n = static_cast<std::size_t>(space.getSimpleExtentNpoints());
  switch (set.getTypeClass()) {
    case H5T_INTEGER: {
      std::vector<long> v(n);
      if (n > 0) set.read(v.data(), H5::PredType::NATIVE_LONG);
      for (long x : v) out.cells.push_back(std::to_string(x));
      break;
    }
    case H5T_FLOAT: {
      std::vector<double> v(n);
      if (n > 0) set.read(v.data(), H5::PredType::NATIVE_DOUBLE);
      for (double x : v) out.cells.push_back(number(x));
      break;
    }
    case H5T_STRING: {
      const H5::StrType type = set.getStrType();
      if (type.isVariableStr()) {
        std::vector<char*> v(n, nullptr);
        if (n > 0) set.read(v.data(), type);
        for (char* x : v) out.cells.push_back(x ? x : "");
        H5Dvlen_reclaim(type.getId(), space.getId(), H5P_DEFAULT, v.data());
      } else {
        const std::size_t size = type.getSize();
        std::string buffer(n * size, '\0');
        if (n > 0) set.read(buffer.data(), type);
        for (std::size_t i = 0; i < n; ++i) {
          std::string s = buffer.substr(i * size, size);
          out.cells.push_back(s.substr(0, s.find('\0')));
        }
      }
      break;
    }
    default:
      out.rows = 0;  // compound or opaque data: not a table
  }
  return out;
}

std::string string_attribute(const H5::H5Object& object, const std::string& name) {
  if (!object.attrExists(name)) return "";
  H5::Attribute a = object.openAttribute(name);
  if (a.getTypeClass() != H5T_STRING || a.getSpace().getSimpleExtentNpoints() != 1) return "";
  std::string value;
  a.read(a.getStrType(), value);
  return value.substr(0, value.find('\0'));
}

// The value of an attribute as text (arrays joined by "; ").
std::string attribute_text(const H5::Attribute& a) {
  const H5::DataSpace space = a.getSpace();
  const auto n = static_cast<std::size_t>(space.getSimpleExtentNpoints());
  std::vector<std::string> parts;
  switch (a.getTypeClass()) {
    case H5T_INTEGER: {
      std::vector<long> v(n);
      if (n > 0) a.read(H5::PredType::NATIVE_LONG, v.data());
      for (long x : v) parts.push_back(std::to_string(x));
      break;
    }
    case H5T_FLOAT: {
      std::vector<double> v(n);
      if (n > 0) a.read(H5::PredType::NATIVE_DOUBLE, v.data());
      for (double x : v) parts.push_back(number(x));
      break;
    }
    case H5T_STRING: {
      const H5::StrType type = a.getStrType();
      if (type.isVariableStr() && n > 1) {
        std::vector<char*> v(n, nullptr);
        a.read(type, v.data());
        for (char* x : v) parts.push_back(x ? x : "");
        H5Dvlen_reclaim(type.getId(), space.getId(), H5P_DEFAULT, v.data());
      } else if (n == 1) {
        std::string value;
        a.read(type, value);
        parts.push_back(value.substr(0, value.find('\0')));
      }
      break;
    }
    default:
      break;
  }
  std::string text;
  for (std::size_t i = 0; i < parts.size(); ++i) text += std::string(i ? "; " : "") + parts[i];
  return text;
}

struct Exporter {
  fs::path out;
  std::string attributes = "object,name,value\n";
  int files = 0;

  void attributes_of(const H5::H5Object& object, const std::string& path) {
    for (int i = 0; i < object.getNumAttrs(); ++i) {
      const H5::Attribute a = object.openAttribute(static_cast<unsigned>(i));
      attributes +=
          field(path) + "," + field(a.getName()) + "," + field(attribute_text(a)) + "\n";
    }
  }

  static std::string file_name(const std::string& path) {
    std::string name = path == "/" ? "root" : path.substr(1);
    std::replace(name.begin(), name.end(), '/', '_');
    return name + ".csv";
  }

  void write(const std::string& path, const std::string& text) {
    core::write_text_file(out / file_name(path), text);
    ++files;
  }

  static std::string heading(const std::string& name, const std::string& unit) {
    return field(unit.empty() ? name : name + " [" + unit + "]");
  }

  void group(const H5::Group& g, const std::string& path) {
    attributes_of(g, path);
    struct Column {
      std::string name, unit;
      Values values;
    };
    std::vector<Column> columns;
    std::vector<std::string> subgroups;
    for (hsize_t i = 0; i < g.getNumObjs(); ++i) {
      const std::string name = g.getObjnameByIdx(i);
      const std::string child = (path == "/" ? "" : path) + "/" + name;
      if (g.childObjType(name) == H5O_TYPE_GROUP) {
        subgroups.push_back(name);
        continue;
      }
      if (g.childObjType(name) != H5O_TYPE_DATASET) continue;
      const H5::DataSet set = g.openDataSet(name);
      attributes_of(set, child);
      Values values = read_values(set);
      if (values.rows == 0 && values.cells.empty() && set.getSpace().getSimpleExtentNpoints() > 0)
        continue;  // a type no CSV can hold
      columns.push_back({name, string_attribute(set, "unit"), std::move(values)});
    }
    // The table: the 1-D datasets of the most common length (ties: the longest).
    std::map<std::size_t, int> count;
    for (const auto& c : columns)
      if (c.values.rank == 1) ++count[c.values.rows];
    std::size_t length = 0;
    int best = 0;
    for (const auto& [rows, n] : count)
      if (n >= best) best = n, length = rows;
    std::string table;
    std::vector<const Column*> in_table;
    for (const auto& c : columns) {
      if (c.values.rank == 1 && c.values.rows == length && best > 0) {
        in_table.push_back(&c);
        continue;
      }
      // Outside the table: a file of its own (a matrix: one CSV row per row, columns NAME_j).
      std::string text;
      for (std::size_t j = 0; j < c.values.cols; ++j)
        text += std::string(j ? "," : "") +
                heading(c.values.rank == 1 ? c.name : fmt::format("{}_{}", c.name, j), c.unit);
      text += "\n";
      for (std::size_t r = 0; r < c.values.rows; ++r) {
        for (std::size_t j = 0; j < c.values.cols; ++j)
          text += std::string(j ? "," : "") + field(c.values.cells[r * c.values.cols + j]);
        text += "\n";
      }
      write((path == "/" ? "" : path) + "/" + c.name, text);
    }
    // In the order of the group's `columns` attribute when it has one (docs/results.md).
    std::vector<std::string> order;
    if (g.attrExists("columns")) {
      const std::string listed = attribute_text(g.openAttribute("columns"));
      for (std::size_t start = 0; start <= listed.size();) {
        const auto end = std::min(listed.find("; ", start), listed.size());
        order.push_back(listed.substr(start, end - start));
        start = end + 2;
      }
    }
    auto rank = [&](const Column* c) {
      return std::find(order.begin(), order.end(), c->name) - order.begin();
    };
    std::stable_sort(in_table.begin(), in_table.end(),
                     [&](const Column* a, const Column* b) { return rank(a) < rank(b); });
    if (!in_table.empty()) {
      for (std::size_t j = 0; j < in_table.size(); ++j)
        table += std::string(j ? "," : "") + heading(in_table[j]->name, in_table[j]->unit);
      table += "\n";
      for (std::size_t r = 0; r < length; ++r) {
        for (std::size_t j = 0; j < in_table.size(); ++j)
          table += std::string(j ? "," : "") + field(in_table[j]->values.cells[r]);
        table += "\n";
      }
      write(path, table);
    }
    for (const auto& name : subgroups)
      group(g.openGroup(name), (path == "/" ? "" : path) + "/" + name);
  }
};

}  // namespace

int export_csv(const fs::path& run_dir, const fs::path& out_dir) {
  const fs::path file = run_dir / "result.h5";
  if (!fs::exists(file))
    throw std::runtime_error(
        fmt::format("{}: no such file; expected a granflow run directory", file.string()));
  std::error_code error;
  fs::create_directories(out_dir, error);
  if (error)
    throw std::runtime_error(
        fmt::format("{}: cannot create the directory ({})", out_dir.string(), error.message()));
  core::install_hdf5_error_recorder();
  core::hdf5_failure_reason();  // forget an earlier, handled failure
  Exporter exporter{out_dir};
  try {
    H5::H5File h5(file.string(), H5F_ACC_RDONLY);
    exporter.group(h5.openGroup("/"), "/");
  } catch (const H5::Exception& e) {
    throw std::runtime_error(fmt::format("{}: cannot read ({}: {})", file.string(),
                                         e.getDetailMsg(), core::hdf5_failure_reason()));
  }
  core::write_text_file(out_dir / "attributes.csv", exporter.attributes);
  return exporter.files + 1;
}

}  // namespace granflow::app
