#include "continuum/mpm/field_writer.hpp"

#include <H5Cpp.h>
#include <fmt/format.h>

#include <stdexcept>

#include "core/file_io.hpp"

namespace granflow::mpm {

namespace {
void write_vector(H5::Group& g, const std::string& name, const std::vector<double>& v) {
  hsize_t dims[1] = {v.size()};
  H5::DataSpace space(1, dims);
  H5::DataSet d = g.createDataSet(name, H5::PredType::NATIVE_DOUBLE, space);
  if (!v.empty()) d.write(v.data(), H5::PredType::NATIVE_DOUBLE);
}
void write_matrix(H5::Group& g, const std::string& name, const std::vector<double>& v,
                  hsize_t cols) {
  hsize_t dims[2] = {v.size() / cols, cols};
  H5::DataSpace space(2, dims);
  H5::DataSet d = g.createDataSet(name, H5::PredType::NATIVE_DOUBLE, space);
  if (!v.empty()) d.write(v.data(), H5::PredType::NATIVE_DOUBLE);
}
void write_ints(H5::Group& g, const std::string& name, const std::vector<int>& v, hsize_t cols) {
  hsize_t dims[2] = {v.size() / cols, cols};
  H5::DataSpace space(2, dims);
  H5::DataSet d = g.createDataSet(name, H5::PredType::NATIVE_INT, space);
  if (!v.empty()) d.write(v.data(), H5::PredType::NATIVE_INT);
}
std::vector<double> interleave(const std::vector<double>& x, const std::vector<double>& y) {
  std::vector<double> xy(2 * x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    xy[2 * i] = x[i];
    xy[2 * i + 1] = y[i];
  }
  return xy;
}

std::string attribute(const std::string& h5, const std::string& path, const std::string& name,
                      std::size_t n, int cols = 1, const char* center = "Node") {
  const std::string type = cols == 1 ? "Scalar" : "Vector";
  const std::string dims = cols == 1 ? fmt::format("{}", n) : fmt::format("{} {}", n, cols);
  return fmt::format(
      "      <Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"{}\">\n"
      "        <DataItem Dimensions=\"{}\" NumberType=\"Float\" Precision=\"8\" "
      "Format=\"HDF\">{}:{}</DataItem>\n      </Attribute>\n",
      name, type, center, dims, h5, path);
}

std::string point_grid(const std::string& h5, const std::string& group, std::size_t n,
                       const std::vector<std::string>& fields) {
  std::string s = fmt::format(
      "    <Grid Name=\"{0}\" GridType=\"Uniform\">\n"
      "      <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{1}\" "
      "NodesPerElement=\"1\"/>\n"
      "      <Geometry GeometryType=\"XY\">\n"
      "        <DataItem Dimensions=\"{1} 2\" NumberType=\"Float\" Precision=\"8\" "
      "Format=\"HDF\">{2}:/{0}/xy</DataItem>\n      </Geometry>\n",
      group, n, h5);
  for (const auto& f : fields) s += attribute(h5, "/" + group + "/" + f, f, n);
  return s + "    </Grid>\n";
}
}  // namespace

FieldWriter::FieldWriter(std::filesystem::path directory) : dir_(std::move(directory)) {
  std::filesystem::create_directories(dir_);
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
  std::vector<std::string> solid_fields = {"vx",  "vy",       "sxx",         "syy", "szz",
                                                 "sxy", "porosity", "temperature", "mass"};
  const std::vector<std::string> liquid_fields = {"vx", "vy", "pressure", "porosity", "mass"};
  const std::vector<std::string> grid_fields = {"mass_solid", "mass_liquid", "vx_solid", "vy_solid",
                                                "vx_liquid",  "vy_liquid",   "porosity"};
  core::install_hdf5_error_recorder();
  core::hdf5_failure_reason();  // forget an earlier, handled failure
  try {
    H5::H5File file(h5.string(), H5F_ACC_TRUNC);
    H5::Group root = file.openGroup("/");
    {
      hsize_t one[1] = {1};
      H5::DataSpace scalar(1, one);
      const double t = s.time();
      root.createAttribute("time", H5::PredType::NATIVE_DOUBLE, scalar)
          .write(H5::PredType::NATIVE_DOUBLE, &t);
    }
    H5::Group g = file.createGroup("/solid");
    write_matrix(g, "xy", interleave(sp.x, sp.y), 2);
    const std::vector<const std::vector<double>*> sv = {&sp.vx,       &sp.vy,          &sp.sxx,
                                                        &sp.syy,      &sp.szz,         &sp.sxy,
                                                        &sp.porosity, &sp.temperature, &sp.mass};
    for (std::size_t k = 0; k < sv.size(); ++k) write_vector(g, solid_fields[k], *sv[k]);
    for (const auto& [name, values] : extra_solid_) {
      if (values->size() != sp.size())
        throw std::invalid_argument("field " + name + ": not one value per solid point");
      write_vector(g, name, *values);
      solid_fields.push_back(name);
    }
    H5::Group l = file.createGroup("/liquid");
    write_matrix(l, "xy", interleave(lp.x, lp.y), 2);
    const std::vector<const std::vector<double>*> lv = {&lp.vx, &lp.vy, &lp.pressure, &lp.porosity,
                                                        &lp.mass};
    for (std::size_t k = 0; k < lv.size(); ++k) write_vector(l, liquid_fields[k], *lv[k]);
    H5::Group gr = file.createGroup("/grid");
    write_matrix(gr, "xy", interleave(nx, ny), 2);
    write_ints(gr, "quads", quads, 4);
    const std::vector<const std::vector<double>*> gv = {
        &nf.mass_solid, &nf.mass_liquid, &nf.vx_solid, &nf.vy_solid,
        &nf.vx_liquid,  &nf.vy_liquid,   &nf.porosity};
    for (std::size_t k = 0; k < gv.size(); ++k) write_vector(gr, grid_fields[k], *gv[k]);
  } catch (const H5::Exception&) {
    throw core::IoError(h5, "cannot write the field frame", core::hdf5_failure_reason());
  }
  // XDMF of this step.
  const std::string h5name = stem + ".h5";
  std::string grids;
  grids += point_grid(h5name, "solid", sp.size(), solid_fields);
  if (lp.size() > 0) grids += point_grid(h5name, "liquid", lp.size(), liquid_fields);
  grids += fmt::format(
      "    <Grid Name=\"grid\" GridType=\"Uniform\">\n"
      "      <Topology TopologyType=\"Quadrilateral\" NumberOfElements=\"{0}\">\n"
      "        <DataItem Dimensions=\"{0} 4\" NumberType=\"Int\" Format=\"HDF\">{1}:/grid/quads"
      "</DataItem>\n      </Topology>\n"
      "      <Geometry GeometryType=\"XY\">\n"
      "        <DataItem Dimensions=\"{2} 2\" NumberType=\"Float\" Precision=\"8\" "
      "Format=\"HDF\">{1}:/grid/xy</DataItem>\n      </Geometry>\n",
      quads.size() / 4, h5name, nx.size());
  for (const auto& f : grid_fields) grids += attribute(h5name, "/grid/" + f, f, nx.size());
  grids += "    </Grid>\n";
  const std::string step_grid = fmt::format(
      "  <Grid Name=\"{}\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
      "    <Time Value=\"{:.17g}\"/>\n{}  </Grid>\n",
      stem, s.time(), grids);
  const std::string header = "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"2.0\">\n <Domain>\n";
  core::write_text_file(dir_ / (stem + ".xmf"), header + step_grid + " </Domain>\n</Xdmf>\n");
  times_.push_back(s.time());
  names_.push_back(step_grid);
  std::string series =
      header + "  <Grid Name=\"time series\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const auto& g : names_) series += g;
  core::write_text_file(dir_ / "fields.xmf", series + "  </Grid>\n </Domain>\n</Xdmf>\n");
  return h5;
}

}  // namespace granflow::mpm
