#include "core/result_file.hpp"

#include <H5Cpp.h>
#include <fmt/format.h>

#include <stdexcept>
#include <vector>

#include "core/file_io.hpp"

namespace granflow::core {

struct ResultFile::Impl {
  H5::H5File file;
};

namespace {

// Open (creating intermediate groups) the parent group of `path` and return the leaf name.
std::pair<H5::Group, std::string> parent_group(H5::H5File& file, const std::string& path) {
  // H5::Group has no usable copy assignment, so the walk keeps the chain of opened groups.
  std::vector<H5::Group> chain;
  chain.emplace_back(file.openGroup("/"));
  std::size_t start = path.front() == '/' ? 1 : 0;
  while (true) {
    const auto slash = path.find('/', start);
    if (slash == std::string::npos) return {chain.back(), path.substr(start)};
    const std::string name = path.substr(start, slash - start);
    H5::Group& parent = chain.back();
    chain.emplace_back(parent.nameExists(name) ? parent.openGroup(name) : parent.createGroup(name));
    start = slash + 1;
  }
}

H5::Group ensure_group(H5::H5File& file, const std::string& path) {
  if (path.empty() || path == "/") return file.openGroup("/");
  auto [parent, leaf] = parent_group(file, path);
  return parent.nameExists(leaf) ? parent.openGroup(leaf) : parent.createGroup(leaf);
}

// Variable-length UTF-8: h5py returns str, and the length is that of each value.
H5::StrType utf8_string_type() {
  H5::StrType type(H5::PredType::C_S1, H5T_VARIABLE);
  type.setCset(H5T_CSET_UTF8);
  return type;
}

void string_attribute(H5::H5Object& object, const std::string& name, const std::string& value) {
  const H5::StrType type = utf8_string_type();
  H5::DataSpace scalar(H5S_SCALAR);
  if (object.attrExists(name)) object.removeAttr(name);
  object.createAttribute(name, type, scalar).write(type, value);
}

void string_list_attribute(H5::H5Object& object, const std::string& name,
                           const std::vector<std::string>& values) {
  const H5::StrType type = utf8_string_type();
  const hsize_t dims[1] = {values.size()};
  H5::DataSpace space(1, dims);
  if (object.attrExists(name)) object.removeAttr(name);
  std::vector<const char*> pointers;
  for (const auto& v : values) pointers.push_back(v.c_str());
  H5::Attribute a = object.createAttribute(name, type, space);
  if (!values.empty()) a.write(type, pointers.data());
}

void number_attribute(H5::H5Object& object, const std::string& name, double value) {
  H5::DataSpace scalar(H5S_SCALAR);
  if (object.attrExists(name)) object.removeAttr(name);
  object.createAttribute(name, H5::PredType::NATIVE_DOUBLE, scalar)
      .write(H5::PredType::NATIVE_DOUBLE, &value);
}

void integer_attribute(H5::H5Object& object, const std::string& name, long value) {
  H5::DataSpace scalar(H5S_SCALAR);
  if (object.attrExists(name)) object.removeAttr(name);
  object.createAttribute(name, H5::PredType::NATIVE_LONG, scalar)
      .write(H5::PredType::NATIVE_LONG, &value);
}

template <class T>
void write_dataset(H5::H5File& file, const std::string& path, const T* data, hsize_t rows,
                   hsize_t cols, const H5::PredType& type, const std::string& unit,
                   const std::string& description) {
  auto [group, leaf] = parent_group(file, path);
  if (group.nameExists(leaf)) group.unlink(leaf);
  const hsize_t dims[2] = {rows, cols};
  H5::DataSpace space(cols == 0 ? 1 : 2, dims);
  H5::DataSet set = group.createDataSet(leaf, type, space);
  if (rows > 0) set.write(data, type);
  string_attribute(set, "unit", unit);
  string_attribute(set, "description", description);
  set.close();  // a failure to write its data shows here, as an exception
}

}  // namespace

// Runs one HDF5 operation; an HDF5 failure becomes an IoError naming result.h5, the operation
// and the reason HDF5 recorded (the system's message for a failed write or open). After one
// failure every later write is refused at once with the same reason, without touching HDF5 (a
// full disk otherwise answers each of them with messages of its own).
template <class Operation>
decltype(auto) ResultFile::guarded(const std::string& action, Operation&& operation) {
  if (!failure_.empty()) throw IoError(path_, action, failure_ + " (an earlier write failed)");
  hdf5_failure_reason();  // forget an earlier, handled failure
  try {
    return operation();
  } catch (const H5::Exception&) {
    failure_ = hdf5_failure_reason();
    throw IoError(path_, action, failure_);
  }
}

ResultFile::ResultFile(const std::filesystem::path& path, Mode mode) : path_(path) {
  install_hdf5_error_recorder();
  if (mode == Mode::append) {
    impl_ = guarded("cannot open for writing the HDF5 file", [&] {
      return std::make_unique<Impl>(Impl{H5::H5File(path.string(), H5F_ACC_RDWR)});
    });
    return;
  }
  impl_ = guarded("cannot create the HDF5 file", [&] {
    return std::make_unique<Impl>(Impl{H5::H5File(path.string(), H5F_ACC_TRUNC)});
  });
  attribute("/", "schema_version", result_schema_version);
}
ResultFile::Impl& ResultFile::open_file() const {
  if (!impl_) throw IoError(path_, "cannot write", "the file was already closed");
  return *impl_;
}
ResultFile::~ResultFile() {
  try {
    close();
  } catch (...) {  // the error was reported by whoever saw it first; a destructor stays quiet
  }
}
ResultFile::ResultFile(ResultFile&&) noexcept = default;
ResultFile& ResultFile::operator=(ResultFile&&) noexcept = default;

void ResultFile::write(const std::string& path, std::span<const double> values,
                       const std::string& unit, const std::string& description) {
  guarded("cannot write " + path, [&] {
    write_dataset(open_file().file, path, values.data(), values.size(), 0,
                  H5::PredType::NATIVE_DOUBLE, unit, description);
  });
}
void ResultFile::write(const std::string& path, std::span<const long> values,
                       const std::string& unit, const std::string& description) {
  guarded("cannot write " + path, [&] {
    write_dataset(open_file().file, path, values.data(), values.size(), 0,
                  H5::PredType::NATIVE_LONG, unit, description);
  });
}
void ResultFile::write(const std::string& group, const Column& column,
                       std::span<const double> values) {
  write(group + "/" + column.name, values, column.unit, column.description);
}
void ResultFile::write(const std::string& group, const Column& column,
                       std::span<const long> values) {
  write(group + "/" + column.name, values, column.unit, column.description);
}
void ResultFile::write_matrix(const std::string& path, std::span<const double> values,
                              std::size_t rows, std::size_t cols, const std::string& unit,
                              const std::string& description) {
  if (values.size() != rows * cols)
    throw std::invalid_argument(
        fmt::format("write_matrix {}: {} values for {}x{}", path, values.size(), rows, cols));
  guarded("cannot write " + path, [&] {
    write_dataset(open_file().file, path, values.data(), rows, cols, H5::PredType::NATIVE_DOUBLE,
                  unit, description);
  });
}

namespace {

// An attribute on the dataset at `object_path` if there is one, else on that group (created).
template <class Value, class Write>
void set_attribute(H5::H5File& file, const std::string& object_path, const std::string& name,
                   const Value& value, Write&& write) {
  if (!object_path.empty() && object_path != "/" &&
      H5Lexists(file.getId(), object_path.c_str(), H5P_DEFAULT) > 0 &&
      file.childObjType(object_path) == H5O_TYPE_DATASET) {
    H5::DataSet set = file.openDataSet(object_path);
    write(set, name, value);
    return;
  }
  H5::Group group = ensure_group(file, object_path);
  write(group, name, value);
}

}  // namespace

void ResultFile::attribute(const std::string& object_path, const std::string& name, double value) {
  guarded("cannot write attribute " + name + " of " + object_path,
          [&] { set_attribute(open_file().file, object_path, name, value, number_attribute); });
}
void ResultFile::attribute(const std::string& object_path, const std::string& name, long value) {
  guarded("cannot write attribute " + name + " of " + object_path,
          [&] { set_attribute(open_file().file, object_path, name, value, integer_attribute); });
}
void ResultFile::attribute(const std::string& object_path, const std::string& name,
                           const std::string& value) {
  guarded("cannot write attribute " + name + " of " + object_path,
          [&] { set_attribute(open_file().file, object_path, name, value, string_attribute); });
}
void ResultFile::attribute(const std::string& object_path, const std::string& name,
                           const std::vector<std::string>& values) {
  guarded("cannot write attribute " + name + " of " + object_path, [&] {
    set_attribute(open_file().file, object_path, name, values, string_list_attribute);
  });
}
void ResultFile::remove(const std::string& object_path) {
  guarded("cannot remove " + object_path, [&] {
    H5::H5File& file = open_file().file;
    // Every component must exist for H5Lexists on the next one.
    for (std::size_t pos = 1;;) {
      const auto slash = object_path.find('/', pos);
      if (H5Lexists(file.getId(), object_path.substr(0, slash).c_str(), H5P_DEFAULT) <= 0) return;
      if (slash == std::string::npos) break;
      pos = slash + 1;
    }
    H5Ldelete(file.getId(), object_path.c_str(), H5P_DEFAULT);
  });
}
void ResultFile::flush() {
  guarded("cannot write (flush)", [&] { open_file().file.flush(H5F_SCOPE_GLOBAL); });
}
void ResultFile::close() {
  if (!impl_) return;
  // After a failed write (a full disk) HDF5's file object may be half closed: it is closed once
  // and then let go whatever happened, since a second close can crash inside HDF5.
  hdf5_failure_reason();
  std::string reason;
  try {
    impl_->file.flush(H5F_SCOPE_GLOBAL);
  } catch (const H5::Exception&) {
    reason = hdf5_failure_reason();
  }
  try {
    impl_->file.close();
  } catch (const H5::Exception&) {
    if (reason.empty()) reason = hdf5_failure_reason();
  }
  if (reason.empty())
    impl_.reset();
  else {
    [[maybe_unused]] Impl* abandoned = impl_.release();  // no second H5Fclose from its destructor
    abandon_hdf5_file();
  }
  if (reason.empty() && !failure_.empty()) reason = failure_ + " (an earlier write failed)";
  if (!reason.empty()) throw IoError(path_, "cannot write", reason);
}

// H5::Exception is not a std::exception: the readers translate it so that every caller (and the
// CLI's top-level handler) sees a std::runtime_error naming the file and the object.
[[noreturn]] static void rethrow_h5(const std::filesystem::path& file, const std::string& object,
                                    const H5::Exception& e) {
  throw std::runtime_error(file.string() + ": cannot read " + object + " (" + e.getDetailMsg() +
                           ": " + hdf5_failure_reason() + ")");
}

std::vector<double> read_dataset(const std::filesystem::path& file, const std::string& path) {
  install_hdf5_error_recorder();
  try {
    H5::H5File f(file.string(), H5F_ACC_RDONLY);
    H5::DataSet set = f.openDataSet(path);
    const auto n = set.getSpace().getSimpleExtentNpoints();
    std::vector<double> values(n);
    if (n > 0) set.read(values.data(), H5::PredType::NATIVE_DOUBLE);
    return values;
  } catch (const H5::Exception& e) {
    rethrow_h5(file, path, e);
  }
}

bool dataset_exists(const std::filesystem::path& file, const std::string& path) {
  install_hdf5_error_recorder();
  try {
    H5::H5File f(file.string(), H5F_ACC_RDONLY);
    // H5Lexists link by link: each parent must exist before its child is asked for.
    for (std::size_t end = path.find('/', 1);; end = path.find('/', end + 1)) {
      const std::string prefix = path.substr(0, end);
      if (H5Lexists(f.getId(), prefix.c_str(), H5P_DEFAULT) <= 0) return false;
      if (end == std::string::npos) break;
    }
    return f.childObjType(path) == H5O_TYPE_DATASET;
  } catch (const H5::Exception& e) {
    rethrow_h5(file, path, e);
  }
}

static H5::Attribute open_attribute(H5::H5File& f, const std::string& object_path,
                                    const std::string& name) {
  if (object_path.empty() || object_path == "/") return f.openGroup("/").openAttribute(name);
  if (f.childObjType(object_path) == H5O_TYPE_DATASET)
    return f.openDataSet(object_path).openAttribute(name);
  return f.openGroup(object_path).openAttribute(name);
}

std::string read_string_attribute(const std::filesystem::path& file, const std::string& object_path,
                                  const std::string& name) {
  install_hdf5_error_recorder();
  try {
    H5::H5File f(file.string(), H5F_ACC_RDONLY);
    H5::Attribute a = open_attribute(f, object_path, name);
    std::string value;
    a.read(a.getStrType(), value);
    return value;
  } catch (const H5::Exception& e) {
    rethrow_h5(file, object_path + " attribute " + name, e);
  }
}

double read_number_attribute(const std::filesystem::path& file, const std::string& object_path,
                             const std::string& name) {
  install_hdf5_error_recorder();
  try {
    H5::H5File f(file.string(), H5F_ACC_RDONLY);
    double value = 0;
    open_attribute(f, object_path, name).read(H5::PredType::NATIVE_DOUBLE, &value);
    return value;
  } catch (const H5::Exception& e) {
    rethrow_h5(file, object_path + " attribute " + name, e);
  }
}

std::vector<std::string> read_string_list_attribute(const std::filesystem::path& file,
                                                    const std::string& object_path,
                                                    const std::string& name) {
  install_hdf5_error_recorder();
  try {
    H5::H5File f(file.string(), H5F_ACC_RDONLY);
    const bool dataset = !(object_path.empty() || object_path == "/") &&
                         f.childObjType(object_path) == H5O_TYPE_DATASET;
    const bool exists = dataset
                            ? f.openDataSet(object_path).attrExists(name)
                            : f.openGroup(object_path.empty() ? "/" : object_path).attrExists(name);
    if (!exists) return {};
    H5::Attribute a = open_attribute(f, object_path, name);
    const auto n = a.getSpace().getSimpleExtentNpoints();
    std::vector<char*> pointers(n, nullptr);
    const H5::StrType type = utf8_string_type();
    if (n > 0) a.read(type, pointers.data());
    std::vector<std::string> values(pointers.begin(), pointers.end());
    H5Dvlen_reclaim(type.getId(), a.getSpace().getId(), H5P_DEFAULT, pointers.data());
    return values;
  } catch (const H5::Exception& e) {
    rethrow_h5(file, object_path + " attribute " + name, e);
  }
}

}  // namespace granflow::core
