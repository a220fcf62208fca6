// Checkpoint/restart: every point array of both phases and the clock (time, step, dt) in one HDF5
// file. Restoring into a solver built from the same case (same grid, conditions, materials) and
// continuing reproduces the uninterrupted run bit for bit: the nodal fields are rebuilt from the
// points at the start of every step, so the point arrays and the clock are the whole state.
// (Materials with internal state will add their arrays here through the same interface.)
#pragma once

#include <filesystem>

#include "continuum/mpm/solver.hpp"

namespace granflow::mpm {

void write_checkpoint(const std::filesystem::path& file, const Solver& solver);
// Throws std::runtime_error when the point counts differ from the solver's.
void read_checkpoint(const std::filesystem::path& file, Solver& solver);

}  // namespace granflow::mpm
