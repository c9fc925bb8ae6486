// Solver-agnostic orchestration of `grainlift run`: runs the requested solvers on one case,
// stamps the metadata, writes <out>/<solver>.h5 (+ an XDMF sidecar for ParaView) and
// <out>/summary.json. The solvers themselves are plugged in by apps/ as SolverEntry values.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "grainlift/shared/case/case_model.h"
#include "grainlift/shared/run/progress.h"
#include "grainlift/shared/results/run_result.h"

namespace grainlift {

struct RunOptions {
  std::string out_dir = "out";
  int threads = 1;
  /// independent DEM runs side by side (seeds dem.seed + k), pooled (replica_pool.h); the
  /// continuum, deterministic, runs once
  int replicas = 1;
  bool progress = true;
  /// false on the MPI ranks other than 0 of a distributed run: they solve but write nothing
  bool writer = true;
  /// go on from the checkpoint in out_dir (DEM: <out_dir>/dem.checkpoint)
  bool resume = false;
  /// run the solvers at once, each on a thread of its own, instead of one after the other
  /// (`grainlift run` sets it for both solvers with --threads >= 2, one replica, one process:
  /// the continuum takes one core while the DEM runs beside it, and the DEM's own choice of
  /// one thread or its team, timed as it runs, takes the cores the continuum leaves)
  bool side_by_side = false;
  /// Set by run_solvers for each solver (empty when nothing is written): writes an
  /// intermediate result as <out_dir>/<solver>.h5, marked partial, metadata filled in, so a
  /// run killed later keeps it (the continuum: each converged mesh before it is refined).
  std::function<void(RunResult)> save_partial;
};

/// A solver that can be asked for by name on the command line.
struct SolverEntry {
  std::string name;         ///< "dem" or "fem": also the output file name
  std::string description;  ///< one line for --help
  /// Runs the case. Throws InputError (exit 2) for a case it cannot run, RunError (exit 1)
  /// for a run that failed. Metadata is filled in by the driver.
  std::function<RunResult(const Case&, const RunOptions&, ProgressReporter&)> run;
};

/// @brief Run @p solvers on @p c (in order, or side by side: RunOptions::side_by_side) and
/// write their files; returns the results in the solvers' order.
std::vector<RunResult> run_solvers(const Case& c, const std::vector<SolverEntry>& solvers,
                                   const RunOptions& options);

/// @brief Rebuild <out>/summary.json from the result files in @p out_dir whose case hash
/// matches @p case_hash (so separate dem and fem runs of one case share one summary), with a
/// "compare" object when both dem and fem are present.
void write_summary(const std::string& out_dir, const std::string& case_hash);

/// Scalar results of one file as the JSON object summary.json holds per solver.
std::string summary_object_json(const RunResult& r);

/// Version and build strings.
std::string grainlift_version();
std::string grainlift_git_revision();

}  // namespace grainlift
