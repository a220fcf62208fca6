// What the problems of the `mpm` case kind share (mpm_kind.cpp registers them; one file each:
// kind_terzaghi.cpp, kind_couette.cpp, kind_column.cpp, kind_rheometer.cpp): the solver options
// of the numerics section, the field frames, the time loop, the set-up report, the common
// summary and the end of the output. Internal to the kind.
#pragma once

#include <chrono>
#include <initializer_list>
#include <memory>
#include <string_view>

#include "continuum/mpm/field_writer.hpp"
#include "continuum/mpm/restart.hpp"
#include "continuum/mpm/solver.hpp"
#include "core/case.hpp"
#include "core/interrupt.hpp"
#include "core/run.hpp"

namespace granflow::mpm::kind {

// The solver options of the `numerics` section.
SolverOptions read_options(const core::Case& c);

// The field frames of a whole run: t = 0 and `count` frames evenly spaced up to `end_time`, the
// end of the whole run, whichever segments advance() runs it in (Terzaghi's isochrones). After a
// restart the frames before the checkpoint are the earlier run's: only later ones are written.
// Several frames due within one step are written once.
class FrameSchedule {
 public:
  FrameSchedule(FieldWriter* writer, double end_time, int count, const Solver& s)
      : writer_(count > 0 ? writer : nullptr), end_(end_time), count_(count) {
    skip_due(s);
  }
  void write_initial(const Solver& s) {
    if (writer_ && s.steps() == 0 && !initial_written_) writer_->write(s);
    initial_written_ = true;
  }
  void write_due(core::RunContext& ctx, const Solver& s) {
    if (writer_ && skip_due(s)) {
      writer_->write(s);
      ctx.result.flush();  // result.h5 readable up to this frame even after SIGKILL
    }
  }

 private:
  bool skip_due(const Solver& s) {
    bool due = false;
    for (; next_ <= count_ && s.time() >= end_ * next_ / count_ - 0.5 * s.dt(); ++next_) due = true;
    return due;
  }
  FieldWriter* writer_;
  double end_;
  int count_, next_ = 1;
  bool initial_written_ = false;
};

// The time loop of every problem: runs the solver to `end_time` (one segment of the run), with its
// field frames and progress (a core::NumericalFailure of the solver stops the run, exit 3);
// `after_step` is called after every step, before the frames due are written. Returns the solver
// wall time.
template <class AfterStep>
double advance(core::RunContext& ctx, Solver& s, double end_time, FrameSchedule& frames,
               AfterStep&& after_step) {
  core::Progress progress(ctx.log, "simulated time", end_time);
  const auto start = std::chrono::steady_clock::now();
  frames.write_initial(s);
  while (s.time() < end_time - 0.5 * s.dt() && !core::interrupted()) {
    s.step();
    after_step();
    frames.write_due(ctx, s);
    progress.update(s.time());
  }
  if (core::interrupted())
    ctx.log->warn("interrupted by {} at step {}, t = {:.6g} s (end time {:g} s)",
                  core::interrupt_name(), s.steps(), s.time(), end_time);
  progress.finish();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The log lines of the set-up: points, nodes, threads, Δt and its limits, the modelling choices.
void report_setup(core::RunContext& ctx, const Solver& s, const RunHistory& history);

// The summary keys of every problem (cost, mpm.*, mass.*); ms0, ml0: the initial phase masses.
void common_summary(core::RunContext& ctx, const Solver& s, const RunHistory& history, double wall,
                    double ms0, double ml0);

// After the summary: its error measures must be numbers (exit 3 naming the one that is not);
// then the checkpoint with the run's history (continuum/mpm/restart.hpp).
void finish_output(core::RunContext& ctx, const Solver& s, const RunHistory& history,
                   std::initializer_list<std::string_view> error_measures);

// The field writer of output.frames (none for 0 frames).
std::unique_ptr<FieldWriter> field_writer(core::RunContext& ctx);

// The problems: the checkpoint checks of output.restart_from (KindEntry::check_inputs, also run
// by the run itself) and the runs.
void terzaghi_inputs(const core::Case& c);
void couette_inputs(const core::Case& c);
void column_inputs(const core::Case& c);
void rheometer_inputs(const core::Case& c);
int run_terzaghi(core::RunContext& ctx);
int run_couette(core::RunContext& ctx);
int run_column(core::RunContext& ctx);
int run_rheometer(core::RunContext& ctx);

}  // namespace granflow::mpm::kind
