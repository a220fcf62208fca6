#include "continuum/mpm/field_writer.hpp"

#include <H5Cpp.h>
#include <fmt/format.h>

#include <numeric>
#include <stdexcept>

#include "core/file_io.hpp"

namespace granflow::mpm {

namespace {
void set_unit(H5::DataSet& d, const std::string& unit) {
  const H5::StrType type(H5::PredType::C_S1, H5T_VARIABLE);
  type.setCset(H5T_CSET_UTF8);
  d.createAttribute("unit", type, H5::DataSpace(H5S_SCALAR)).write(type, unit);
}
void write_array(H5::Group& g, const std::string& name, const std::vector<double>& v, hsize_t cols,
                 const std::string& unit) {
  hsize_t dims[2] = {cols ? v.size() / cols : 0, cols};
  H5::DataSpace space(cols == 1 ? 1 : 2, dims);
  H5::DataSet d = g.createDataSet(name, H5::PredType::NATIVE_DOUBLE, space);
  if (!v.empty()) d.write(v.data(), H5::PredType::NATIVE_DOUBLE);
  set_unit(d, unit);
}
void write_ints(H5::Group& g, const std::string& name, const std::vector<int>& v, hsize_t cols) {
  hsize_t dims[2] = {v.size() / cols, cols};
  H5::DataSpace space(cols == 1 ? 1 : 2, dims);
  H5::DataSet d = g.createDataSet(name, H5::PredType::NATIVE_INT, space);
  if (!v.empty()) d.write(v.data(), H5::PredType::NATIVE_INT);
  set_unit(d, "1");
}
// Interleaved components: (a0 b0 ..., a1 b1 ..., ...) from one vector per component (nullptr: 0).
std::vector<double> interleave(const std::vector<const std::vector<double>*>& parts,
                               std::size_t n) {
  std::vector<double> out(parts.size() * n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < parts.size(); ++k)
      if (parts[k]) out[parts.size() * i + k] = (*parts[k])[i];
  return out;
}

// One dataset of a frame and how XDMF shows it.
struct Field {
  std::string name;
  int components;  // 1 scalar, 2 vector (XY), 6 symmetric tensor (xx xy xz yy yz zz)
};

std::string attribute(const std::string& h5, const std::string& group, const Field& f,
                      std::size_t n) {
  const char* type = f.components == 1 ? "Scalar" : f.components == 2 ? "Vector" : "Tensor6";
  const std::string dims =
      f.components == 1 ? fmt::format("{}", n) : fmt::format("{} {}", n, f.components);
  return fmt::format(
      "        <Attribute Name=\"{0}\" AttributeType=\"{1}\" Center=\"Node\">\n"
      "          <DataItem Dimensions=\"{2}\" NumberType=\"Float\" Precision=\"8\" "
      "Format=\"HDF\">{3}:/{4}/{0}</DataItem>\n        </Attribute>\n",
      f.name, type, dims, h5, group);
}

std::string geometry(const std::string& h5, const std::string& group, std::size_t n) {
  return fmt::format(
      "        <Geometry GeometryType=\"XY\">\n"
      "          <DataItem Dimensions=\"{0} 2\" NumberType=\"Float\" Precision=\"8\" "
      "Format=\"HDF\">{1}:/{2}/xy</DataItem>\n        </Geometry>\n",
      n, h5, group);
}

// A frame of one series: a uniform grid with its time, topology, geometry and attributes.
std::string frame(const std::string& name, double time, const std::string& topology,
                  const std::string& geometry, const std::string& attributes) {
  return fmt::format(
      "      <Grid Name=\"{}\" GridType=\"Uniform\">\n        <Time Value=\"{:.17g}\"/>\n{}{}{}"
      "      </Grid>\n",
      name, time, topology, geometry, attributes);
}
}  // namespace

FieldWriter::FieldWriter(std::filesystem::path directory) : dir_(std::move(directory)) {
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) throw core::IoError(dir_, "cannot create the field directory", ec.message());
}

std::filesystem::path FieldWriter::write(const Solver& s) {
  const std::string stem = fmt::format("step_{:08d}", s.steps());
  const std::filesystem::path h5 = dir_ / (stem + ".h5");
  const SolidPoints& sp = s.solid();
  const LiquidPoints& lp = s.liquid();
  const NodeFields& nf = s.nodes();
  // Grid geometry and connectivity.
  std::vector<double> nx, ny;
  std::vector<int> quads;
  std::visit(
      [&](const auto& g) {
        for (int n = 0; n < g.nodes(); ++n) {
          nx.push_back(g.node_x(n));
          ny.push_back(g.node_y(n));
        }
        using G = std::decay_t<decltype(g)>;
        if constexpr (std::is_same_v<G, CartesianGrid>) {
          for (int j = 0; j < g.cells_y(); ++j)
            for (int i = 0; i < g.cells_x(); ++i)
              quads.insert(quads.end(), {g.node(i, j), g.node(i + 1, j), g.node(i + 1, j + 1),
                                         g.node(i, j + 1)});
        } else {
          for (int j = 0; j < g.cells_theta(); ++j)
            for (int i = 0; i < g.cells_r(); ++i)
              quads.insert(quads.end(), {g.node(i, j), g.node(i + 1, j), g.node(i + 1, j + 1),
                                         g.node(i, j + 1)});
        }
      },
      s.grid());
  const std::size_t ns = sp.size(), nl = lp.size(), nn = nx.size();
  // The scalar arrays (kept for scripts that read them by name), then the vector and tensor.
  std::vector<Field> solid = {{"vx", 1},       {"vy", 1},          {"sxx", 1},
                              {"syy", 1},      {"szz", 1},         {"sxy", 1},
                              {"porosity", 1}, {"temperature", 1}, {"mass", 1}};
  const std::vector<Field> liquid = {{"vx", 1},       {"vy", 1},   {"pressure", 1},
                                     {"porosity", 1}, {"mass", 1}, {"velocity", 2}};
  const std::vector<Field> grid = {{"mass_solid", 1},     {"mass_liquid", 1},     {"porosity", 1},
                                   {"velocity_solid", 2}, {"velocity_liquid", 2}, {"vx_solid", 1},
                                   {"vy_solid", 1},       {"vx_liquid", 1},       {"vy_liquid", 1}};
  core::install_hdf5_error_recorder();
  core::hdf5_failure_reason();  // forget an earlier, handled failure
  try {
    H5::H5File file(h5.string(), H5F_ACC_TRUNC);
    H5::Group root = file.openGroup("/");
    {
      const double t = s.time();
      H5::Attribute a =
          root.createAttribute("time", H5::PredType::NATIVE_DOUBLE, H5::DataSpace(H5S_SCALAR));
      a.write(H5::PredType::NATIVE_DOUBLE, &t);
    }
    std::vector<int> ids(std::max(ns, nl));
    std::iota(ids.begin(), ids.end(), 0);
    H5::Group g = file.createGroup("/solid");
    write_array(g, "xy", interleave({&sp.x, &sp.y}, ns), 2, "m");
    write_ints(g, "vertices", std::vector<int>(ids.begin(), ids.begin() + ns), 1);
    write_array(g, "vx", sp.vx, 1, "m/s");
    write_array(g, "vy", sp.vy, 1, "m/s");
    write_array(g, "sxx", sp.sxx, 1, "Pa");
    write_array(g, "syy", sp.syy, 1, "Pa");
    write_array(g, "szz", sp.szz, 1, "Pa");
    write_array(g, "sxy", sp.sxy, 1, "Pa");
    write_array(g, "porosity", sp.porosity, 1, "1");
    write_array(g, "temperature", sp.temperature, 1, "m^2/s^2");
    write_array(g, "mass", sp.mass, 1, "kg/m");  // per unit thickness (plane strain)
    write_array(g, "velocity", interleave({&sp.vx, &sp.vy}, ns), 2, "m/s");
    // Effective stress, plane strain: σ_xz = σ_yz = 0.
    write_array(g, "stress", interleave({&sp.sxx, &sp.sxy, nullptr, &sp.syy, nullptr, &sp.szz}, ns),
                6, "Pa");
    solid.push_back({"velocity", 2});
    solid.push_back({"stress", 6});
    for (const auto& e : extra_solid_) {
      if (e.values->size() != ns)
        throw std::invalid_argument("field " + e.name + ": not one value per solid point");
      write_array(g, e.name, *e.values, 1, e.unit);
      solid.push_back({e.name, 1});
    }
    H5::Group l = file.createGroup("/liquid");
    write_array(l, "xy", interleave({&lp.x, &lp.y}, nl), 2, "m");
    write_ints(l, "vertices", std::vector<int>(ids.begin(), ids.begin() + nl), 1);
    write_array(l, "vx", lp.vx, 1, "m/s");
    write_array(l, "vy", lp.vy, 1, "m/s");
    write_array(l, "pressure", lp.pressure, 1, "Pa");
    write_array(l, "porosity", lp.porosity, 1, "1");
    write_array(l, "mass", lp.mass, 1, "kg/m");
    write_array(l, "velocity", interleave({&lp.vx, &lp.vy}, nl), 2, "m/s");
    H5::Group gr = file.createGroup("/grid");
    write_array(gr, "xy", interleave({&nx, &ny}, nn), 2, "m");
    write_ints(gr, "quads", quads, 4);
    write_array(gr, "mass_solid", nf.mass_solid, 1, "kg/m");
    write_array(gr, "mass_liquid", nf.mass_liquid, 1, "kg/m");
    write_array(gr, "porosity", nf.porosity, 1, "1");
    write_array(gr, "velocity_solid", interleave({&nf.vx_solid, &nf.vy_solid}, nn), 2, "m/s");
    write_array(gr, "velocity_liquid", interleave({&nf.vx_liquid, &nf.vy_liquid}, nn), 2, "m/s");
    write_array(gr, "vx_solid", nf.vx_solid, 1, "m/s");
    write_array(gr, "vy_solid", nf.vy_solid, 1, "m/s");
    write_array(gr, "vx_liquid", nf.vx_liquid, 1, "m/s");
    write_array(gr, "vy_liquid", nf.vy_liquid, 1, "m/s");
  } catch (const H5::Exception&) {
    throw core::IoError(h5, "cannot write the field frame", core::hdf5_failure_reason());
  }
  // The three XDMF 3 series, each a temporal collection of uniform grids.
  const std::string file = stem + ".h5";
  auto points = [&](const std::string& group, std::size_t n, const std::vector<Field>& fields) {
    std::string attributes;
    for (const auto& f : fields) attributes += attribute(file, group, f, n);
    const std::string topology = fmt::format(
        "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{0}\" "
        "NodesPerElement=\"1\">\n"
        "          <DataItem Dimensions=\"{0} 1\" NumberType=\"Int\" Precision=\"4\" "
        "Format=\"HDF\">{1}:/{2}/vertices</DataItem>\n        </Topology>\n",
        n, file, group);
    return frame(stem, s.time(), topology, geometry(file, group, n), attributes);
  };
  std::string grid_attributes;
  for (const auto& f : grid) grid_attributes += attribute(file, "grid", f, nn);
  const std::string grid_topology = fmt::format(
      "        <Topology TopologyType=\"Quadrilateral\" NumberOfElements=\"{0}\">\n"
      "          <DataItem Dimensions=\"{0} 4\" NumberType=\"Int\" Precision=\"4\" "
      "Format=\"HDF\">{1}:/grid/quads</DataItem>\n        </Topology>\n",
      quads.size() / 4, file);
  frames_[0].push_back(points("solid", ns, solid));
  frames_[1].push_back(points("liquid", nl, liquid));
  frames_[2].push_back(
      frame(stem, s.time(), grid_topology, geometry(file, "grid", nn), grid_attributes));
  times_.push_back(s.time());
  const char* series[3] = {"solid", "liquid", "grid"};
  for (int k = 0; k < 3; ++k) {
    if (k == 1 && nl == 0) continue;  // a dry run has no liquid series
    std::string text = fmt::format(
        "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n"
        "    <Grid Name=\"{}\" GridType=\"Collection\" CollectionType=\"Temporal\">\n",
        series[k]);
    for (const auto& f : frames_[k]) text += f;
    text += "    </Grid>\n  </Domain>\n</Xdmf>\n";
    core::write_text_file(dir_ / (std::string(series[k]) + ".xmf"), text);
  }
  return h5;
}

}  // namespace granflow::mpm
