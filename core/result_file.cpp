#include "core/result_file.hpp"

#include <H5Cpp.h>
#include <fmt/format.h>

#include <stdexcept>
#include <vector>

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

void string_attribute(H5::H5Object& object, const std::string& name, const std::string& value) {
  H5::StrType type(H5::PredType::C_S1, std::max<std::size_t>(value.size(), 1));
  H5::DataSpace scalar(H5S_SCALAR);
  if (object.attrExists(name)) object.removeAttr(name);
  object.createAttribute(name, type, scalar).write(type, value.empty() ? std::string(" ") : value);
}

void number_attribute(H5::H5Object& object, const std::string& name, double value) {
  H5::DataSpace scalar(H5S_SCALAR);
  if (object.attrExists(name)) object.removeAttr(name);
  object.createAttribute(name, H5::PredType::NATIVE_DOUBLE, scalar)
      .write(H5::PredType::NATIVE_DOUBLE, &value);
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
}

}  // namespace

ResultFile::ResultFile(const std::filesystem::path& path)
    : impl_((H5::Exception::dontPrint(), new Impl{H5::H5File(path.string(), H5F_ACC_TRUNC)})),
      path_(path) {}
ResultFile::~ResultFile() {
  if (impl_) {
    try {
      impl_->file.flush(H5F_SCOPE_GLOBAL);
      impl_->file.close();
    } catch (...) {
    }
  }
}
ResultFile::ResultFile(ResultFile&&) noexcept = default;
ResultFile& ResultFile::operator=(ResultFile&&) noexcept = default;

void ResultFile::write(const std::string& path, std::span<const double> values,
                       const std::string& unit, const std::string& description) {
  write_dataset(impl_->file, path, values.data(), values.size(), 0, H5::PredType::NATIVE_DOUBLE,
                unit, description);
}
void ResultFile::write(const std::string& path, std::span<const long> values,
                       const std::string& unit, const std::string& description) {
  write_dataset(impl_->file, path, values.data(), values.size(), 0, H5::PredType::NATIVE_LONG, unit,
                description);
}
void ResultFile::write_matrix(const std::string& path, std::span<const double> values,
                              std::size_t rows, std::size_t cols, const std::string& unit,
                              const std::string& description) {
  if (values.size() != rows * cols)
    throw std::invalid_argument(
        fmt::format("write_matrix {}: {} values for {}x{}", path, values.size(), rows, cols));
  write_dataset(impl_->file, path, values.data(), rows, cols, H5::PredType::NATIVE_DOUBLE, unit,
                description);
}

void ResultFile::attribute(const std::string& object_path, const std::string& name, double value) {
  if (!object_path.empty() && object_path != "/" &&
      H5Lexists(impl_->file.getId(), object_path.c_str(), H5P_DEFAULT) > 0 &&
      impl_->file.childObjType(object_path) == H5O_TYPE_DATASET) {
    H5::DataSet set = impl_->file.openDataSet(object_path);
    number_attribute(set, name, value);
    return;
  }
  H5::Group group = ensure_group(impl_->file, object_path);
  number_attribute(group, name, value);
}
void ResultFile::attribute(const std::string& object_path, const std::string& name,
                           const std::string& value) {
  if (!object_path.empty() && object_path != "/" &&
      H5Lexists(impl_->file.getId(), object_path.c_str(), H5P_DEFAULT) > 0 &&
      impl_->file.childObjType(object_path) == H5O_TYPE_DATASET) {
    H5::DataSet set = impl_->file.openDataSet(object_path);
    string_attribute(set, name, value);
    return;
  }
  H5::Group group = ensure_group(impl_->file, object_path);
  string_attribute(group, name, value);
}
void ResultFile::flush() { impl_->file.flush(H5F_SCOPE_GLOBAL); }

// H5::Exception is not a std::exception: the readers translate it so that every caller (and the
// CLI's top-level handler) sees a std::runtime_error naming the file and the object.
[[noreturn]] static void rethrow_h5(const std::filesystem::path& file, const std::string& object,
                                    const H5::Exception& e) {
  throw std::runtime_error(file.string() + ": cannot read " + object + " (" + e.getDetailMsg() +
                           ")");
}

std::vector<double> read_dataset(const std::filesystem::path& file, const std::string& path) {
  H5::Exception::dontPrint();
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

static H5::Attribute open_attribute(H5::H5File& f, const std::string& object_path,
                                    const std::string& name) {
  if (object_path.empty() || object_path == "/") return f.openGroup("/").openAttribute(name);
  if (f.childObjType(object_path) == H5O_TYPE_DATASET)
    return f.openDataSet(object_path).openAttribute(name);
  return f.openGroup(object_path).openAttribute(name);
}

std::string read_string_attribute(const std::filesystem::path& file, const std::string& object_path,
                                  const std::string& name) {
  H5::Exception::dontPrint();
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
  H5::Exception::dontPrint();
  try {
    H5::H5File f(file.string(), H5F_ACC_RDONLY);
    double value = 0;
    open_attribute(f, object_path, name).read(H5::PredType::NATIVE_DOUBLE, &value);
    return value;
  } catch (const H5::Exception& e) {
    rethrow_h5(file, object_path + " attribute " + name, e);
  }
}

}  // namespace granflow::core
