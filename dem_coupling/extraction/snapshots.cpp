#include "dem_coupling/extraction/snapshots.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <utility>
#include <vector>

namespace granflow::dem {

namespace {
constexpr const char* prefix = "snapshot_";
constexpr const char* suffix = ".vtu";
constexpr const char* text_suffix = ".dump";  // the LAMMPS text dump of the same step
}  // namespace

std::string snapshot_commands(long every, long shear_start_step, double shear_rate) {
  if (every <= 0) return {};
  // dump custom/vtk writes one VTK XML file per dump step (the .vtu suffix selects the format;
  // LIGGGHTS 3.8.0 DumpCustomVTK) plus a bounding-box file of the same step. Its own steps are
  // multiples of N counted from timestep 0; `dump_modify every v_` with stride(start, stop, N)
  // counts them from the shear start instead (stride takes 32-bit steps: stop at 2e9), and
  // `first yes` adds the shear start itself. The second dump writes the same columns at the same
  // steps as LAMMPS text (dump custom: ITEM: TIMESTEP / NUMBER OF ATOMS / BOX BOUNDS xy xz yz /
  // ATOMS, reals as %g), the format OVITO reads natively (it has no reader for .vtu grids).
  return fmt::format(
      "# particle snapshots every {0} steps from the shear start (output.snapshot_strain;\n"
      "# indexed by strain in snapshots.pvd and snapshots.csv when granflow-dem ends):\n"
      "# {2}<step>{3} for ParaView, {2}<step>{5} (LAMMPS text dump) for OVITO\n"
      "variable        vx_fluctuation atom vx-{1:.17g}*(y-ylo)\n"
      "variable        gf_snapshot_next equal stride({4},2000000000,{0})\n"
      "dump            gf_snapshots all custom/vtk {0} {2}*{3} {6}\n"
      "dump_modify     gf_snapshots every v_gf_snapshot_next first yes\n"
      "dump            gf_snapshots_text all custom {0} {2}*{5} {6}\n"
      "dump_modify     gf_snapshots_text every v_gf_snapshot_next first yes\n",
      every, shear_rate, prefix, suffix, shear_start_step, text_suffix,
      "id type radius x y z v_vx_fluctuation vy vz omegax omegay omegaz fx fy fz");
}

int index_snapshots(const std::filesystem::path& dir, long shear_start_step, double dt,
                    double shear_rate) {
  std::vector<std::pair<long, std::string>> files;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) != 0 || name.size() <= std::strlen(prefix) + std::strlen(suffix) ||
        name.compare(name.size() - std::strlen(suffix), std::strlen(suffix), suffix) != 0)
      continue;
    const std::string step =
        name.substr(std::strlen(prefix), name.size() - std::strlen(prefix) - std::strlen(suffix));
    if (step.empty() || step.find_first_not_of("0123456789") != std::string::npos) continue;
    files.emplace_back(std::stol(step), name);
  }
  if (files.empty()) return 0;
  std::sort(files.begin(), files.end());
  std::string pvd =
      "<?xml version=\"1.0\"?>\n"
      "<!-- granflow: DEM particle snapshots of the shear stage; timestep = shear strain -->\n"
      "<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n";
  std::string csv = "step,time_s,strain,file,dump_file\n";
  for (const auto& [step, name] : files) {
    const double time = double(step - shear_start_step) * dt;
    pvd += fmt::format("<DataSet timestep=\"{:.10g}\" group=\"\" part=\"0\" file=\"{}\"/>\n",
                       shear_rate * time, name);
    // The text dump of the same step (empty when the deck did not write one).
    std::string text = fmt::format("{}{}{}", prefix, step, text_suffix);
    if (!std::filesystem::is_regular_file(dir / text, ec)) text.clear();
    csv += fmt::format("{},{:.10g},{:.10g},{},{}\n", step, time, shear_rate * time, name, text);
  }
  pvd += "</Collection>\n</VTKFile>\n";
  for (const auto& [file, text] :
       {std::pair{dir / "snapshots.pvd", pvd}, std::pair{dir / "snapshots.csv", csv}}) {
    std::ofstream out(file);
    out << text;
    out.close();
    if (!out)
      throw std::runtime_error(
          fmt::format("{}: cannot write: {}", file.string(), std::strerror(errno)));
  }
  return int(files.size());
}

}  // namespace granflow::dem
