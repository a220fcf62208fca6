// result.h5: time series and tables of one run, units as HDF5 attributes ("unit", "description").
// Thin RAII wrapper over the HDF5 C++ API (H5Cpp.h); writes are flushed so that a run stopped by
// a numerical failure keeps what it already wrote.
#pragma once

#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace granflow::core {

class ResultFile {
 public:
  explicit ResultFile(const std::filesystem::path& path);  // creates (truncates) the file
  ~ResultFile();
  ResultFile(ResultFile&&) noexcept;
  ResultFile& operator=(ResultFile&&) noexcept;

  // 1D dataset `group/name` (groups created as needed, e.g. "series/T"), with unit and doc.
  void write(const std::string& path, std::span<const double> values, const std::string& unit,
             const std::string& description);
  void write(const std::string& path, std::span<const long> values, const std::string& unit,
             const std::string& description);
  // 2D row-major dataset [rows x cols] (e.g. particle fields, profiles).
  void write_matrix(const std::string& path, std::span<const double> values, std::size_t rows,
                    std::size_t cols, const std::string& unit, const std::string& description);
  // Attributes on a group or dataset (created if the group does not exist).
  void attribute(const std::string& object_path, const std::string& name, double value);
  void attribute(const std::string& object_path, const std::string& name, const std::string& value);
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
std::string read_string_attribute(const std::filesystem::path& file, const std::string& object_path,
                                  const std::string& name);
double read_number_attribute(const std::filesystem::path& file, const std::string& object_path,
                             const std::string& name);

}  // namespace granflow::core
