// Particle and grid fields per output step: fields/step_NNNNNN.h5 (HDF5) with a matching
// step_NNNNNN.xmf (XDMF 2) that ParaView opens (solid points, liquid points and the background
// grid as three grids), plus fields/fields.xmf, the temporal collection of all steps written so
// far.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "continuum/mpm/solver.hpp"

namespace granflow::mpm {

class FieldWriter {
 public:
  explicit FieldWriter(std::filesystem::path directory);
  // Write the current state; returns the .h5 path.
  std::filesystem::path write(const Solver& solver);
  int written() const { return static_cast<int>(times_.size()); }

 private:
  std::filesystem::path dir_;
  std::vector<double> times_;
  std::vector<std::string> names_;
};

}  // namespace granflow::mpm
