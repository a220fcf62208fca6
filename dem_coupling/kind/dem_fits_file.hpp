// Re-deriving the fits of an existing DEM run (`granflow report RUN_DIR`, analysis/report.cpp):
// read the steady table of result.h5 (docs/results.md) and rewrite its /fits group
// (core::ResultFile opened in append mode).
// Runs written before τ_contact/σ_yy was tabulated get it from /conditions/N/series (tau_contact,
// tau_lub, sigma_yy) over the steady part recorded in /conditions/N/steady (start_strain).
// Header-only (see statistics/least_squares.hpp).
#pragma once

#include <H5Cpp.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/file_io.hpp"
#include "dem_coupling/kind/dem_columns.hpp"
#include "dem_coupling/kind/dem_fits.hpp"

namespace granflow::dem {

namespace fits_file_detail {

// Opens `file`; a missing, truncated or foreign file is a std::runtime_error naming it and the
// reason HDF5 recorded (core/file_io.hpp).
inline H5::H5File open_h5(const std::filesystem::path& file, unsigned flags) {
  core::install_hdf5_error_recorder();
  core::hdf5_failure_reason();  // forget an earlier, handled failure
  try {
    return H5::H5File(file.string(), flags);
  } catch (const H5::Exception&) {
    throw std::runtime_error(fmt::format("{}: cannot open as HDF5 ({}); expected a DEM result.h5",
                                         file.string(), core::hdf5_failure_reason()));
  }
}

inline std::vector<double> read(H5::H5File& f, const std::string& path) {
  H5::DataSet set = f.openDataSet(path);
  std::vector<double> v(set.getSpace().getSimpleExtentNpoints());
  if (!v.empty()) set.read(v.data(), H5::PredType::NATIVE_DOUBLE);
  return v;
}

inline bool path_exists(H5::H5File& f, const std::string& path) {
  // Every component must exist for H5Lexists on the next one.
  std::size_t pos = 1;
  while (true) {
    const auto slash = path.find('/', pos);
    const std::string prefix = path.substr(0, slash);
    if (H5Lexists(f.getId(), prefix.c_str(), H5P_DEFAULT) <= 0) return false;
    if (slash == std::string::npos) return true;
    pos = slash + 1;
  }
}

inline double number_attribute(H5::H5Object& object, const std::string& name) {
  double v = std::numeric_limits<double>::quiet_NaN();
  if (object.attrExists(name)) object.openAttribute(name).read(H5::PredType::NATIVE_DOUBLE, &v);
  return v;
}

}  // namespace fits_file_detail

// τ_part/σ_yy of condition group g from its series over its recorded steady part; `part` is a
// series.tsv column (kind/dem_columns.hpp).
inline StressRatio series_stress_ratio(H5::H5File& f, const std::string& g, const char* part) {
  using namespace fits_file_detail;
  const std::string series = g + "/series/";
  if (!path_exists(f, series + dem_series_name(part)) || !path_exists(f, g + "/steady")) return {};
  H5::Group steady = f.openGroup(g + "/steady");
  const double start_strain = number_attribute(steady, dem_steady_name("start_strain"));
  const auto strain = read(f, series + dem_series_name("strain"));
  const std::size_t start = static_cast<std::size_t>(
      std::lower_bound(strain.begin(), strain.end(), start_strain - 1e-12) - strain.begin());
  return stress_ratio_of_series(read(f, series + dem_series_name(part)),
                                read(f, series + dem_series_name("sigma_yy")), start);
}

// A sweep that has not written /steady yet (still running, or interrupted): one row per
// /conditions/N from its steady attributes. A condition whose steady part ends before
// `total_strain` (× 0.98) did not finish (killed or failed): its row is NaN.
inline DemSteadyTable steady_table_from_conditions(H5::H5File& f, double total_strain) {
  using namespace fits_file_detail;
  DemSteadyTable t;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t n = 0; path_exists(f, fmt::format("/conditions/{}", n)); ++n) {
    const std::string g = fmt::format("/conditions/{}", n);
    H5::Group group = f.openGroup(g);
    const bool wet = group.attrExists("liquid_viscosity");
    t.wet = t.wet || wet;
    t.particle_friction.push_back(number_attribute(group, "particle_friction"));
    double v[6] = {nan, nan, nan, nan, nan, nan};
    double w[5] = {nan, nan, nan, nan, nan};
    if (path_exists(f, g + "/steady")) {
      H5::Group steady = f.openGroup(g + "/steady");
      const double end = number_attribute(steady, dem_steady_name("end_strain"));
      if (std::isfinite(end) && !(end < 0.98 * total_strain)) {
        const char* keys[] = {"I", "I_err", "mu", "mu_err", "phi", "phi_err"};
        for (int k = 0; k < 6; ++k) v[k] = number_attribute(steady, dem_steady_name(keys[k]));
        const char* wet_keys[] = {"St", "J", "J_err"};
        for (int k = 0; k < 3; ++k) w[k] = number_attribute(steady, dem_steady_name(wet_keys[k]));
      }
    }
    t.inertial.push_back(v[0]), t.inertial_err.push_back(v[1]);
    t.friction.push_back(v[2]), t.friction_err.push_back(v[3]);
    t.solid_fraction.push_back(v[4]), t.solid_fraction_err.push_back(v[5]);
    t.stokes.push_back(w[0]), t.viscous.push_back(w[1]), t.viscous_err.push_back(w[2]);
    StressRatio contact, lub;
    if (wet && std::isfinite(v[2])) {
      contact = series_stress_ratio(f, g, "tau_contact");
      lub = series_stress_ratio(f, g, "tau_lub");
    }
    t.friction_contact.push_back(contact.value);
    t.friction_contact_err.push_back(contact.error);
    t.friction_lubrication.push_back(lub.value);
    t.friction_lubrication_err.push_back(lub.error);
  }
  if (!t.wet) {
    for (auto* column :
         {&t.stokes, &t.viscous, &t.viscous_err, &t.friction_contact, &t.friction_contact_err,
          &t.friction_lubrication, &t.friction_lubrication_err})
      column->clear();
  }
  return t;
}

// Throws std::runtime_error naming the file and the missing dataset when it is not a DEM dataset.
// `total_strain` (strain.total of the case) is used only for a sweep without /steady (above).
inline DemSteadyTable read_dem_steady_table(
    const std::filesystem::path& file,
    double total_strain = std::numeric_limits<double>::quiet_NaN()) {
  using namespace fits_file_detail;
  H5::H5File f = open_h5(file, H5F_ACC_RDONLY);
  namespace c = core::columns;
  if (!path_exists(f, std::string("/steady/") + c::particle_friction.name) &&
      path_exists(f, "/conditions/0"))
    return steady_table_from_conditions(f, total_strain);
  auto column = [&](const std::string& name) {
    const std::string path = "/steady/" + name;
    if (!path_exists(f, path))
      throw std::runtime_error(
          fmt::format("{}: no dataset {} (expected a DEM result.h5, docs/results.md)",
                      file.string(), path));
    return read(f, path);
  };
  // The /steady names of kind/dem_columns.hpp, by the keys of the steady values.
  auto steady = [&](const char* key) { return column(dem_steady_name(key)); };
  DemSteadyTable t;
  t.particle_friction = column(c::particle_friction.name);
  t.inertial = steady("I");
  t.inertial_err = steady("I_err");
  t.friction = steady("mu");
  t.friction_err = steady("mu_err");
  t.solid_fraction = steady("phi");
  t.solid_fraction_err = steady("phi_err");
  t.wet = path_exists(f, "/steady/" + dem_steady_name("J"));
  if (!t.wet) return t;
  t.stokes = steady("St");
  t.viscous = steady("J");
  t.viscous_err = steady("J_err");
  if (path_exists(f, "/steady/" + dem_steady_name("mu_contact"))) {
    t.friction_contact = steady("mu_contact");
    t.friction_contact_err = steady("mu_contact_err");
    t.friction_lubrication = steady("mu_lub");
    t.friction_lubrication_err = steady("mu_lub_err");
    return t;
  }
  // Older runs: from the series, over the recorded steady part.
  for (std::size_t n = 0; n < t.rows(); ++n) {
    StressRatio contact, lub;
    const std::string g = fmt::format("/conditions/{}", n);
    if (std::isfinite(t.friction[n])) {
      contact = series_stress_ratio(f, g, "tau_contact");
      lub = series_stress_ratio(f, g, "tau_lub");
    }
    t.friction_contact.push_back(contact.value);
    t.friction_contact_err.push_back(contact.error);
    t.friction_lubrication.push_back(lub.value);
    t.friction_lubrication_err.push_back(lub.error);
  }
  return t;
}

}  // namespace granflow::dem
