#include "continuum/mpm/checkpoint.hpp"

#include <H5Cpp.h>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

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
void put(H5::Group& g, const std::string& name, const std::vector<double>& v) {
  hsize_t dims[1] = {v.size()};
  H5::DataSpace space(1, dims);
  H5::DataSet d = g.createDataSet(name, H5::PredType::NATIVE_DOUBLE, space);
  if (!v.empty()) d.write(v.data(), H5::PredType::NATIVE_DOUBLE);
}
void get(H5::Group& g, const std::string& name, std::vector<double>& v) {
  H5::DataSet d = g.openDataSet(name);
  hsize_t dims[1];
  d.getSpace().getSimpleExtentDims(dims);
  if (dims[0] != v.size()) {
    throw std::runtime_error("checkpoint: '" + name + "' has " + std::to_string(dims[0]) +
                             " values, the solver has " + std::to_string(v.size()) + " points");
  }
  if (!v.empty()) d.read(v.data(), H5::PredType::NATIVE_DOUBLE);
}
}  // namespace

void write_checkpoint(const std::filesystem::path& file, const Solver& solver) {
  Solver& s = const_cast<Solver&>(solver);  // the field tables take non-const pointers; no write
  H5::H5File f(file.string(), H5F_ACC_TRUNC);
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
}

void read_checkpoint(const std::filesystem::path& file, Solver& s) {
  H5::H5File f(file.string(), H5F_ACC_RDONLY);
  H5::Group clock = f.openGroup("/clock");
  std::vector<double> c(3);
  get(clock, "time_step_dt", c);
  H5::Group g = f.openGroup("/solid");
  for (auto& [name, v] : fields(s.solid())) get(g, name, *v);
  H5::Group l = f.openGroup("/liquid");
  for (auto& [name, v] : fields(s.liquid())) get(l, name, *v);
  for (int k = 0; k < s.materials(); ++k) {
    auto state = s.material_state(k);
    if (state.empty()) continue;
    H5::Group m = f.openGroup("/material_" + std::to_string(k));
    for (auto& [name, v] : state) get(m, name, *v);
  }
  s.set_clock(c[0], static_cast<long>(c[1]), c[2]);
}

}  // namespace granflow::mpm
