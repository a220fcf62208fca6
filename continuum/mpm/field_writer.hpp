// Particle and grid fields per output step: fields/step_NNNNNN.h5 (HDF5) with a matching
// step_NNNNNN.xmf (XDMF 2) that ParaView opens (solid points, liquid points and the background
// grid as three grids), plus fields/fields.xmf, the temporal collection of all steps written so
// far.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "continuum/mpm/solver.hpp"

namespace granflow::mpm {

class FieldWriter {
 public:
  explicit FieldWriter(std::filesystem::path directory);
  // Write the current state; returns the .h5 path.
  std::filesystem::path write(const Solver& solver);
  int written() const { return static_cast<int>(times_.size()); }
  // Extra per-solid-point fields written with every frame (e.g. a material's r_c, the strain);
  // each vector must have one value per solid point when write() is called.
  void add_solid_field(std::string name, const std::vector<double>* values) {
    extra_solid_.emplace_back(std::move(name), values);
  }

 private:
  std::filesystem::path dir_;
  std::vector<double> times_;
  std::vector<std::string> names_;
  std::vector<std::pair<std::string, const std::vector<double>*>> extra_solid_;
};

}  // namespace granflow::mpm
