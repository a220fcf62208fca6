// Restart of an MPM run from a checkpoint (output.restart_from; docs/mpm.md, "Restart").
//
// A checkpoint records the resolved case of the run that wrote it and the history accumulators of
// that run (series, peaks, sums, averaging windows, reference values at t = 0), beside the solver
// state (checkpoint.hpp). A restart is allowed only for the same case: it may change run.end_time,
// output.*, name, description and numerics.threads (the thread count only changes the summation
// order: the continuation is then equal to round-off instead of bit for bit), plus keys a kind
// declares free because its history covers them. Its summaries then cover the whole history, equal
// to the uninterrupted run's.
//
// Every refusal is a core::CaseError located at output.restart_from that names the file and the
// reason (missing, unreadable, truncated, not a checkpoint, another case with the first differing
// key, at or past the end time), so the CLI stops with one line and exit code 2.
#pragma once

#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "continuum/mpm/checkpoint.hpp"
#include "core/case.hpp"
#include "core/run.hpp"

namespace granflow::mpm {

struct RestartPoint {
  std::string file;
  CheckpointClock clock;
  CheckpointRecord record;
};

// Check phase. Without output.restart_from (or with ""): nullopt. Else reads the checkpoint's clock
// and record and refuses a file that cannot be used or was written by another case: the first key
// that differs, other than the always free ones and `free_keys`.
std::optional<RestartPoint> check_restart(const core::Case& c,
                                          std::initializer_list<std::string_view> free_keys);
// Refuses a checkpoint at or past `end_time` (set by the key `end_key`): nothing would run.
void check_restart_end(const core::Case& c, const RestartPoint& r, double end_time,
                       std::string_view end_key);
// The refusal itself: "<where>: output.restart_from: <file>: <why>".
[[noreturn]] void refuse_restart(const core::Case& c, const std::string& file,
                                 const std::string& why);

// The history accumulators of a run: restored from the checkpoint it continues, recorded into the
// checkpoint it writes.
class RunHistory {
 public:
  bool restarted() const { return restarted_; }
  // The restored value (CaseError when the checkpoint lacks it), or `fresh` for a run from t = 0.
  double get(const std::string& name, double fresh) const;
  // Replaces `v` by the restored array; leaves it for a run from t = 0.
  void get(const std::string& name, std::vector<double>& v) const;
  void set(const std::string& name, double value) { values_[name] = {value}; }
  void set(const std::string& name, std::vector<double> value) { values_[name] = std::move(value); }
  const History& values() const { return values_; }
  // The critical time steps in force: the solver's own, except after a restart until the solver
  // next re-evaluates them (SolverOptions::dt_update_interval), when they are the checkpoint's
  // (the restored solver has those of its t = 0 state).
  const TimeStepLimits& limits(const Solver& solver) const;

 private:
  friend RunHistory restore_run(core::RunContext& ctx, Solver& solver);
  const std::vector<double>& restored(const std::string& name) const;
  const core::Case* case_ = nullptr;
  std::string file_;
  bool restarted_ = false;
  History values_;
  TimeStepLimits limits_;  // the checkpoint's
  long limits_until_ = 0;  // step of the solver's next re-evaluation after the restart
};

// Run phase: restores `solver` (point arrays, material state, clock) from output.restart_from when
// given, logs it, and returns the history of the run it continues (empty for a run from t = 0).
RunHistory restore_run(core::RunContext& ctx, Solver& solver);

// Writes checkpoint.h5 when output.checkpoint is on: the solver, the resolved case and `history`.
void write_run_checkpoint(core::RunContext& ctx, const Solver& solver, const RunHistory& history);

// Stops (core::NumericalFailure naming the key: exit code 3) when one of the summary's `keys` is
// not finite. summary.json leaves a NaN out as "not available" with exit code 0; an error measure
// of an analytic check or a conservation law never is.
void check_error_measures(const core::RunContext& ctx, long step,
                          std::initializer_list<std::string_view> keys);

// Kind rules that need the checkpoint's history (names as the kinds record them):
// Terzaghi: run.isochrones is free; the isochrones already checked ("terzaghi.isochrones") must
// come first in it, and the last one (× "terzaghi.time_per_Tv") must lie after the checkpoint.
void check_terzaghi_restart(const core::Case& c, const RestartPoint& r);
// Couette: run.average_from is free when the window starts after the checkpoint (the sums restart
// from zero) or is the checkpoint's ("couette.average_from": the stored sums are the window's).
void check_couette_restart(const core::Case& c, const RestartPoint& r);

}  // namespace granflow::mpm
