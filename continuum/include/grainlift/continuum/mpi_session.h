// MPI for the continuum engine (Trilinos needs MPI even on one process). deal.II-free, so a
// program's main() can hold one without seeing deal.II.
#pragma once

#include <memory>

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

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace grainlift::continuum
