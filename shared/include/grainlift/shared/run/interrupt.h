// Ctrl-C and SIGTERM for long runs: the first signal asks the run in progress to stop at its
// next event (the DEM writes a checkpoint and its outputs so far, marked partial); a second
// one ends the process at once. The solvers only poll interrupt_signal(); the command line
// installs the handlers.
#pragma once

namespace grainlift {

/// @brief Install the SIGINT and SIGTERM handlers (idempotent).
void install_interrupt_handlers();
/// The signal that asked the run to stop (SIGINT or SIGTERM), 0 if none.
int interrupt_signal();
/// @brief Ask as a signal would (tests), or clear the request with 0.
void set_interrupt_signal(int sig);

}  // namespace grainlift
