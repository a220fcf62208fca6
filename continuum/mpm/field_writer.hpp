// Particle and grid fields per output step: fields/step_NNNNNNNN.h5 (HDF5; every dataset carries
// its `unit`) and three XDMF 3 time series that ParaView's default reader and meshio's
// TimeSeriesReader open: fields/solid.xmf and fields/liquid.xmf (material points as Polyvertex
// cells with an explicit connectivity, velocity as a vector, the solid stress as a tensor) and
// fields/grid.xmf (the background grid). Each series is rewritten whole after every frame, so it
// always lists the frames written so far.
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
  void add_solid_field(std::string name, const std::vector<double>* values, std::string unit) {
    extra_solid_.push_back({std::move(name), values, std::move(unit)});
  }

 private:
  struct Extra {
    std::string name;
    const std::vector<double>* values;
    std::string unit;
  };
  std::filesystem::path dir_;
  std::vector<double> times_;
  // The <Grid> element of every frame written so far, per series (solid, liquid, grid).
  std::vector<std::string> frames_[3];
  std::vector<Extra> extra_solid_;
};

}  // namespace granflow::mpm
