// Checkpoint/restart: every point array of both phases, the material state and the clock (time,
// step, dt) in one HDF5 file, plus a record of the run that wrote it: its resolved case and its
// history accumulators (series, peaks, sums, averaging windows). Restoring into a solver built from
// the same case (same grid, conditions, materials) and continuing reproduces the uninterrupted run
// bit for bit: the nodal fields are rebuilt from the points at the start of every step, so the
// point arrays and the clock are the whole state of the solver; the record lets the run's
// summaries cover the whole history (continuum/mpm/restart.hpp).
#pragma once

#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "continuum/mpm/solver.hpp"

namespace granflow::mpm {

// Named history accumulators of a run (a scalar is a vector of one value).
using History = std::map<std::string, std::vector<double>>;

// What a checkpoint holds beside the solver state.
struct CheckpointRecord {
  std::string case_yaml;  // the resolved case of the run that wrote it ("" in an old checkpoint)
  History history;
};

struct CheckpointClock {
  double time = 0.0, dt = 0.0;
  long step = 0;
};

// A checkpoint that cannot be used: missing, unreadable, truncated, not a granflow MPM checkpoint,
// or holding other point counts than the solver. what() is the reason alone (no file name).
class CheckpointError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Written to `file`.tmp and renamed, so an interrupted write never leaves a truncated checkpoint
// under the name. Throws core::IoError (the file and the reason) when it cannot be written.
void write_checkpoint(const std::filesystem::path& file, const Solver& solver,
                      const CheckpointRecord& record = {});
// Restores the point arrays, the material state and the clock; returns the record. Throws
// CheckpointError.
CheckpointRecord read_checkpoint(const std::filesystem::path& file, Solver& solver);
// The clock and the record alone, without a solver (to check a restart before anything is built).
// Throws CheckpointError.
CheckpointRecord read_checkpoint_record(const std::filesystem::path& file, CheckpointClock& clock);

}  // namespace granflow::mpm
