// result.h5: time series and tables of one run, units as HDF5 attributes ("unit", "description").
// Thin RAII wrapper over the HDF5 C++ API (H5Cpp.h); writes are flushed so that a run stopped by
// a numerical failure keeps what it already wrote. Strings (attributes) are variable-length UTF-8;
// counts and flags are integers (the `long` overloads); every file made here carries the integer
// root attribute `schema_version` (docs/results.md says what each version changed).
#pragma once

#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace granflow::core {

// The vocabulary version of the datasets granflow writes (docs/results.md, "Schema versions").
inline constexpr long result_schema_version = 2;

// One column of a table: its dataset name, unit ("1" for a number without dimension) and meaning.
// Each kind defines its tables once as arrays of these (docs/results.md lists them all).
struct Column {
  const char* name;
  const char* unit;
  const char* description;
};

class ResultFile {
 public:
  enum class Mode { create, append };
  // create: a new file (truncated), with the root attribute schema_version; append: an existing
  // result.h5 opened for rewriting some of its groups (`granflow report`).
  explicit ResultFile(const std::filesystem::path& path, Mode mode = Mode::create);
  ~ResultFile();
  ResultFile(ResultFile&&) noexcept;
  ResultFile& operator=(ResultFile&&) noexcept;

  // 1D dataset `group/name` (groups created as needed, e.g. "series/T"), with unit and doc.
  void write(const std::string& path, std::span<const double> values, const std::string& unit,
             const std::string& description);
  void write(const std::string& path, std::span<const long> values, const std::string& unit,
             const std::string& description);
  // The same, named by a column of a kind's table: `group/column.name`.
  void write(const std::string& group, const Column& column, std::span<const double> values);
  void write(const std::string& group, const Column& column, std::span<const long> values);
  // 2D row-major dataset [rows x cols] (e.g. particle fields, profiles).
  void write_matrix(const std::string& path, std::span<const double> values, std::size_t rows,
                    std::size_t cols, const std::string& unit, const std::string& description);
  // Attributes on a group or dataset (created if the group does not exist).
  void attribute(const std::string& object_path, const std::string& name, double value);
  void attribute(const std::string& object_path, const std::string& name, long value);
  void attribute(const std::string& object_path, const std::string& name, int value) {
    attribute(object_path, name, static_cast<long>(value));
  }
  void attribute(const std::string& object_path, const std::string& name, const std::string& value);
  void attribute(const std::string& object_path, const std::string& name, const char* value) {
    attribute(object_path, name, std::string(value));
  }
  // A 1D array of strings (e.g. the column names of a table, in order).
  void attribute(const std::string& object_path, const std::string& name,
                 const std::vector<std::string>& values);
  // Removes a group or dataset if it exists (append mode: a group about to be rewritten).
  void remove(const std::string& object_path);
  // Failures of any of these are IoError naming result.h5, the object and the system's reason.
  void flush();
  // Flush and close (further writes are an error); the destructor closes quietly otherwise.
  void close();
  const std::filesystem::path& path() const { return path_; }

 private:
  struct Impl;
  Impl& open_file() const;
  template <class Operation>
  decltype(auto) guarded(const std::string& action, Operation&& operation);
  std::unique_ptr<Impl> impl_;
  std::string failure_;  // the reason of the first failed write; later writes are refused
  std::filesystem::path path_;
};

// Read a 1D double dataset (for tests, calibration and pair runs).
std::vector<double> read_dataset(const std::filesystem::path& file, const std::string& path);
// Whether `path` (absolute, "/a/b/c") names a dataset of the file (false for a group or nothing).
bool dataset_exists(const std::filesystem::path& file, const std::string& path);
std::string read_string_attribute(const std::filesystem::path& file, const std::string& object_path,
                                  const std::string& name);
double read_number_attribute(const std::filesystem::path& file, const std::string& object_path,
                             const std::string& name);
// A string-array attribute (empty when the object has no such attribute).
std::vector<std::string> read_string_list_attribute(const std::filesystem::path& file,
                                                    const std::string& object_path,
                                                    const std::string& name);

}  // namespace granflow::core
