#include "continuum/mpm/checkpoint.hpp"

#include <H5Cpp.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "core/file_io.hpp"

namespace granflow::mpm {

namespace {
template <class P>
std::vector<std::pair<std::string, std::vector<double>*>> common_fields(P& p) {
  return {{"x", &p.x},       {"y", &p.y},           {"vx", &p.vx},         {"vy", &p.vy},
          {"mass", &p.mass}, {"volume", &p.volume}, {"fx_ext", &p.fx_ext}, {"fy_ext", &p.fy_ext},
          {"Lxx", &p.Lxx},   {"Lxy", &p.Lxy},       {"Lyx", &p.Lyx},       {"Lyy", &p.Lyy},
          {"x0", &p.x0},     {"y0", &p.y0}};
}
std::vector<std::pair<std::string, std::vector<double>*>> fields(SolidPoints& s) {
  auto f = common_fields(s);
  f.insert(f.end(), {{"sxx", &s.sxx},
                     {"syy", &s.syy},
                     {"szz", &s.szz},
                     {"sxy", &s.sxy},
                     {"solid_volume", &s.solid_volume},
                     {"porosity", &s.porosity},
                     {"temperature", &s.temperature}});
  return f;
}
std::vector<std::pair<std::string, std::vector<double>*>> fields(LiquidPoints& l) {
  auto f = common_fields(l);
  f.insert(f.end(), {{"pressure", &l.pressure},
                     {"txx", &l.txx},
                     {"tyy", &l.tyy},
                     {"tzz", &l.tzz},
                     {"txy", &l.txy},
                     {"porosity", &l.porosity},
                     {"drag", &l.drag}});
  return f;
}

// HDF5 prints its error stack to stderr by itself; while one of these lives it does not (the
// reason goes into the exception instead).
class QuietHdf5 {
 public:
  QuietHdf5() {
    H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~QuietHdf5() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }
  QuietHdf5(const QuietHdf5&) = delete;
  QuietHdf5& operator=(const QuietHdf5&) = delete;

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

// The innermost message of HDF5's error stack (e.g. "truncated file: eof = 96, ..."), else the
// exception's own.
std::string hdf5_reason(const H5::Exception& e) {
  std::string inner;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_UPWARD,
      [](unsigned, const H5E_error2_t* err, void* data) -> herr_t {
        auto* text = static_cast<std::string*>(data);
        if (text->empty() && err && err->desc && *err->desc) *text = err->desc;
        return 0;
      },
      &inner);
  return inner.empty() ? e.getDetailMsg() : inner;
}

bool exists(const H5::H5Location& where, const std::string& name) {
  return H5Lexists(where.getId(), name.c_str(), H5P_DEFAULT) > 0;
}

void put(H5::Group& g, const std::string& name, const std::vector<double>& v) {
  hsize_t dims[1] = {v.size()};
  H5::DataSpace space(1, dims);
  H5::DataSet d = g.createDataSet(name, H5::PredType::NATIVE_DOUBLE, space);
  if (!v.empty()) d.write(v.data(), H5::PredType::NATIVE_DOUBLE);
}
std::vector<double> get_any(const H5::Group& g, const std::string& name) {
  H5::DataSet d = g.openDataSet(name);
  H5::DataSpace space = d.getSpace();
  if (space.getSimpleExtentNdims() != 1)
    throw CheckpointError("'" + name + "' is not a one-dimensional array");
  hsize_t dims[1];
  space.getSimpleExtentDims(dims);
  std::vector<double> v(dims[0]);
  if (!v.empty()) d.read(v.data(), H5::PredType::NATIVE_DOUBLE);
  return v;
}
void get(const H5::Group& g, const std::string& group, const std::string& name,
         std::vector<double>& v) {
  if (!exists(g, name)) throw CheckpointError("no " + group + "/" + name + " in it");
  std::vector<double> read = get_any(g, name);
  if (read.size() != v.size()) {
    throw CheckpointError(group + "/" + name + " has " + std::to_string(read.size()) +
                          " values where the case has " + std::to_string(v.size()) + " points");
  }
  v = std::move(read);
}
H5::Group open_group(const H5::H5File& f, const std::string& name) {
  if (!exists(f, name)) throw CheckpointError("not a granflow MPM checkpoint (no " + name + ")");
  return f.openGroup(name);
}

// Opens for reading, with the reason of a refusal in words.
H5::H5File open_checkpoint(const std::filesystem::path& file) {
  std::error_code ec;
  const auto st = std::filesystem::status(file, ec);
  if (!std::filesystem::exists(st)) throw CheckpointError("no such file");
  if (std::filesystem::is_directory(st)) throw CheckpointError("a directory, not a file");
  if (!std::filesystem::is_regular_file(st)) throw CheckpointError("not a regular file");
  {
    std::ifstream probe(file, std::ios::binary);
    if (!probe) throw CheckpointError(std::string("cannot be read (") + std::strerror(errno) + ")");
  }
  if (!H5::H5File::isHdf5(file.string())) throw CheckpointError("not an HDF5 file");
  return H5::H5File(file.string(), H5F_ACC_RDONLY);
}

CheckpointClock read_clock(const H5::H5File& f) {
  const H5::Group clock = open_group(f, "/clock");
  std::vector<double> c(3);
  get(clock, "/clock", "time_step_dt", c);
  CheckpointClock out;
  out.time = c[0];
  out.step = static_cast<long>(c[1]);
  out.dt = c[2];
  if (!std::isfinite(out.time) || !(out.dt > 0) || out.step < 0)
    throw CheckpointError("its clock (t, step, dt) is not valid");
  return out;
}

CheckpointRecord read_record(const H5::H5File& f) {
  CheckpointRecord r;
  if (!exists(f, "/run")) return r;  // written before checkpoints recorded their case
  const H5::Group run = f.openGroup("/run");
  if (exists(run, "case")) {
    H5::DataSet d = run.openDataSet("case");
    H5::StrType type = d.getStrType();
    std::string text(type.getSize(), '\0');
    d.read(text.data(), type);
    r.case_yaml = text.substr(0, text.find('\0'));
  }
  if (exists(run, "history")) {
    const H5::Group h = run.openGroup("history");
    for (hsize_t i = 0; i < h.getNumObjs(); ++i) {
      const std::string name = h.getObjnameByIdx(i);
      r.history[name] = get_any(h, name);
    }
  }
  return r;
}

template <class Body>
auto translated(Body&& body) {
  const QuietHdf5 quiet;
  try {
    return body();
  } catch (const H5::Exception& e) {
    throw CheckpointError("unreadable HDF5 file (" + hdf5_reason(e) + ")");
  }
}
}  // namespace

void write_checkpoint(const std::filesystem::path& file, const Solver& solver,
                      const CheckpointRecord& record) {
  Solver& s = const_cast<Solver&>(solver);  // the field tables take non-const pointers; no write
  std::filesystem::path tmp = file;
  tmp += ".tmp";
  const QuietHdf5 quiet;
  try {
    {
      H5::H5File f(tmp.string(), H5F_ACC_TRUNC);
      H5::Group clock = f.createGroup("/clock");
      put(clock, "time_step_dt", {solver.time(), static_cast<double>(solver.steps()), solver.dt()});
      H5::Group g = f.createGroup("/solid");
      for (auto& [name, v] : fields(s.solid())) put(g, name, *v);
      std::vector<double> material(s.solid().material.begin(), s.solid().material.end());
      put(g, "material", material);
      H5::Group l = f.createGroup("/liquid");
      for (auto& [name, v] : fields(s.liquid())) put(l, name, *v);
      for (int k = 0; k < s.materials(); ++k) {
        H5::Group m = f.createGroup("/material_" + std::to_string(k));
        for (auto& [name, v] : s.material_state(k)) put(m, name, *v);
      }
      H5::Group run = f.createGroup("/run");
      if (!record.case_yaml.empty()) {
        H5::StrType type(H5::PredType::C_S1, record.case_yaml.size());
        H5::DataSet d = run.createDataSet("case", type, H5::DataSpace(H5S_SCALAR));
        d.write(record.case_yaml.data(), type);
      }
      H5::Group h = run.createGroup("history");
      for (const auto& [name, v] : record.history) put(h, name, v);
    }
    std::filesystem::rename(tmp, file);
  } catch (const H5::Exception& e) {
    const std::string reason = hdf5_reason(e);
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw core::IoError(file, "cannot write the checkpoint", reason);
  } catch (const std::filesystem::filesystem_error& e) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw core::IoError(file, "cannot write the checkpoint", e.code().message());
  }
}

CheckpointRecord read_checkpoint_record(const std::filesystem::path& file, CheckpointClock& clock) {
  return translated([&]() {
    const H5::H5File f = open_checkpoint(file);
    clock = read_clock(f);
    return read_record(f);
  });
}

CheckpointRecord read_checkpoint(const std::filesystem::path& file, Solver& s) {
  return translated([&]() {
    const H5::H5File f = open_checkpoint(file);
    const CheckpointClock c = read_clock(f);
    CheckpointRecord record = read_record(f);
    const H5::Group g = open_group(f, "/solid");
    for (auto& [name, v] : fields(s.solid())) get(g, "/solid", name, *v);
    const H5::Group l = open_group(f, "/liquid");
    for (auto& [name, v] : fields(s.liquid())) get(l, "/liquid", name, *v);
    for (int k = 0; k < s.materials(); ++k) {
      auto state = s.material_state(k);
      if (state.empty()) continue;
      const std::string group = "/material_" + std::to_string(k);
      const H5::Group m = open_group(f, group);
      for (auto& [name, v] : state) get(m, group, name, *v);
    }
    s.set_clock(c.time, c.step, c.dt);
    return record;
  });
}

}  // namespace granflow::mpm
