// The subcommands of `grainlift` (run, validate, compare, sweep, keys).
#pragma once

#include <string>
#include <vector>

#include "grainlift/shared/run_driver.h"

namespace grainlift::app {

/// Parses argv, runs the subcommand, maps errors to exit codes (0, 1 run failed, 2 bad input).
int main_with_args(int argc, char** argv);

/// The solvers compiled into this binary (solver_table.cc).
std::vector<SolverEntry> available_solvers();

/// Rank and number of processes of an MPI run (0 and 1 without MPI; solver_table.cc).
int process_rank();
int process_count();
/// Under mpirun, for an exception that reached a command: true when every rank got one there
/// with the same exit code; otherwise prints @p what with the rank and ends every rank with
/// MPI_Abort(@p code) (see continuum::MpiSession::all_ranks_failed). True without MPI.
bool failed_on_every_rank(const std::string& what, int code);

}  // namespace grainlift::app
