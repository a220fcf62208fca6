// Stopping cleanly on SIGINT (Ctrl-C) and SIGTERM: the handler only records the signal; every
// time loop asks interrupted() at its step boundary and leaves as if it had reached its end, so
// the run writes its series, result.h5 and summary.json (with run.interrupted = 1) as usual, then
// exits 128 + the signal (130 for SIGINT, 143 for SIGTERM). Child processes (granflow-dem,
// mpirun, plot scripts) run in a process group of their own and are stopped by run_process when
// the run is interrupted. A second signal of the same kind ends granflow at once (the default
// action), for a user who does not want to wait for the step boundary.
#pragma once

#include <string>

namespace granflow::core {

// Installs the SIGINT and SIGTERM handlers (idempotent).
void install_interrupt_handlers();

// The signal that asked the run to stop (SIGINT or SIGTERM), 0 when none did. Async-signal-safe
// to read, cheap enough for every step of a hot loop.
int interrupt_signal();
inline bool interrupted() { return interrupt_signal() != 0; }

// "SIGINT", "SIGTERM".
std::string interrupt_name();

// The exit code of an interrupted run: 128 + the signal.
int interrupt_exit_code();

// For tests: record `signal` as if it had been received (0 clears).
void set_interrupt_for_testing(int signal);

}  // namespace granflow::core
