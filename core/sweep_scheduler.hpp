// The independent conditions of a sweep, run in order in one process, or distributed over the
// ranks of `mpirun -np N granflow run CASE.yaml` (docs/parallel-runs.md).
//
// A kind splits its per-condition work in two:
//   compute(n)        the expensive part (a REV integration, a LIGGGHTS run); runs on any rank and
//                     returns its result packed into bytes (Packer); logs to the logger it is
//                     given;
//   absorb(n, bytes)  writes result.h5, summary.json and the log; runs on rank 0 only, in the
//                     order n = 0, 1, ..., whichever rank computed n, so the files are those of a
//                     serial run.
// Without mpirun (or with one rank) compute and absorb simply alternate in this process: no MPI
// call, no thread, exceptions propagate as before. Under mpirun the conditions go out on a
// dynamic master/worker queue (DEM points have very unequal costs, ∝ 1/I): rank 0 computes
// conditions on a thread of its own while its main thread hands conditions to the other ranks as
// they become free, collects their results and absorbs them in order. A condition that throws on
// any rank is rethrown by rank 0 when its turn to be absorbed comes, exactly as in a serial run
// (its log lines first); the ranks busy with later conditions finish them and are released, so
// nothing hangs.
//
// The run directory must be on a file system every rank sees (it is: the ranks of one machine).
#pragma once

#include <spdlog/logger.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/run.hpp"

namespace granflow::core {

// Bytes of a condition's result: numbers (bit-exact), integers, texts and number arrays, read
// back in the order they were written. Ranks of one job share the machine's byte order.
class Packer {
 public:
  Packer& number(double value);
  Packer& integer(std::int64_t value);
  Packer& text(std::string_view value);
  Packer& numbers(const std::vector<double>& values);
  std::string take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

class Unpacker {
 public:
  explicit Unpacker(std::string_view bytes) : bytes_(bytes) {}
  double number();
  std::int64_t integer();
  std::string text();
  std::vector<double> numbers();
  bool done() const { return position_ == bytes_.size(); }

 private:
  void read(void* destination, std::size_t size);
  std::string_view bytes_;
  std::size_t position_ = 0;
};

// A NumericalFailure that compute(n) caught to return the data computed before it: packed with
// that data, rethrown by absorb(n) after writing it, with the serial run's message.
void pack_numerical_failure(Packer& packer, const NumericalFailure& failure);
[[noreturn]] void throw_numerical_failure(Unpacker& unpacker);

// What compute(n) gets.
struct ConditionContext {
  std::size_t index;                    // n, the condition's index in expand_sweep()
  std::shared_ptr<spdlog::logger> log;  // lines reach rank 0's log.txt in condition order
  std::filesystem::path run_directory;  // the run directory (rank 0's, also on other ranks)
  int rank;                             // the MPI rank computing it (0 without mpirun)
};

using ComputeCondition = std::function<std::string(const ConditionContext&)>;
using AbsorbCondition = std::function<void(std::size_t index, const std::string& packed)>;

// Runs conditions 0..count-1 of `ctx`'s case. Returns true on the rank that owns the outputs
// (rank 0, or the only process); false on the other ranks, whose run function must then return
// at once (rank 0 writes the tables, the summary and the plots).
bool run_conditions(RunContext& ctx, std::size_t count, const ComputeCondition& compute,
                    const AbsorbCondition& absorb);

// True when this process writes the run directory: no mpirun, or rank 0.
bool owns_outputs();

// MPI for one `granflow` process. MPI is initialised only when the process was started by
// mpirun (Open MPI sets OMPI_COMM_WORLD_SIZE, PMIx sets PMIX_RANK): a plain `granflow run`
// makes no MPI call at all. The destructor finalises MPI.
class MpiRanks {
 public:
  MpiRanks(int& argc, char**& argv);
  ~MpiRanks();
  MpiRanks(const MpiRanks&) = delete;
  MpiRanks& operator=(const MpiRanks&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool distributed() const { return size_ > 1; }

  // End of `granflow run`. A rank > 0 tells rank 0 it has left; rank 0 waits until every other
  // rank has left, releasing those still waiting for a condition (say when rank 0 stopped
  // before its sweep started). Call once on every rank after the kind's run function returned
  // or threw.
  void leave_run();

 private:
  bool initialised_ = false;
  int rank_ = 0, size_ = 1;
};

// True when this process was started by mpirun (the variables Open MPI / PMIx set for a rank).
bool launched_by_mpirun();

}  // namespace granflow::core
