// MPI for the continuum engine (Trilinos needs MPI even on one process). deal.II-free, so a
// program's main() can hold one without seeing deal.II.
#pragma once

#include <memory>
#include <string>

namespace grainlift::continuum {

/// Initialises MPI (through deal.II, which also sets up its thread pool) for the lifetime of the
/// object and finalises it at the end. Hold one in main() before any solve. Without one, the
/// engine initialises MPI itself the first time the amg solver needs it and finalises it at exit.
class MpiSession {
 public:
  MpiSession(int& argc, char**& argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  /// Rank and size of MPI_COMM_WORLD (0 and 1 when MPI is not initialised).
  static int rank();
  static int size();

  /// Where an exception was caught: ranks that fail at different places did not fail together.
  enum class FailureSite { continuum_solve = 1, command = 2 };

  /// For a rank that caught an exception, when other ranks may still be running. Returns true
  /// when every rank of MPI_COMM_WORLD failed at the same @p site with the same @p exit_code
  /// within kFailureWaitSeconds of each other (a collective failure: input that every rank
  /// read, a solve that did not converge; the caller reports it on rank 0 only and carries on),
  /// and at once on one process. Otherwise the other ranks are still computing and may be
  /// waiting in a collective call that this rank will never make: prints
  /// "grainlift: error on MPI rank R of N: @p message" to stderr and ends every rank with
  /// MPI_Abort(MPI_COMM_WORLD, @p exit_code); does not return. The ranks meet on a communicator
  /// of their own (made by the MpiSession), so the wait cannot be mistaken for a collective
  /// call of the solver; without an MpiSession, any failure on several ranks aborts.
  static bool all_ranks_failed(FailureSite site, const std::string& message, int exit_code);
  static constexpr double kFailureWaitSeconds = 10;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace grainlift::continuum
