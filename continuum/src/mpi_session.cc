#include "grainlift/continuum/mpi_session.h"

#include <deal.II/base/mpi.h>

#include <mpi.h>

#include <chrono>
#include <cstdlib>
#include <iostream>
#include <thread>

#include "fault_injection.h"

namespace grainlift::continuum {

namespace {
/// The communicator on which failing ranks meet (all_ranks_failed()); a copy of MPI_COMM_WORLD
/// for the lifetime of the MpiSession that initialised MPI, MPI_COMM_NULL otherwise.
MPI_Comm failure_comm = MPI_COMM_NULL;
}  // namespace

struct MpiSession::Impl {
  Impl(int& argc, char**& argv) : init(argc, argv, 1) {}
  dealii::Utilities::MPI::MPI_InitFinalize init;
};

MpiSession::MpiSession(int& argc, char**& argv) {
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (!initialised) {
    impl_ = std::make_unique<Impl>(argc, argv);
    MPI_Comm_dup(MPI_COMM_WORLD, &failure_comm);
  }
}

MpiSession::~MpiSession() {
  if (impl_ && failure_comm != MPI_COMM_NULL) MPI_Comm_free(&failure_comm);
}

int MpiSession::rank() {
  int initialised = 0, finalised = 0;
  MPI_Initialized(&initialised);
  MPI_Finalized(&finalised);
  if (!initialised || finalised) return 0;
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

int MpiSession::size() {
  int initialised = 0, finalised = 0;
  MPI_Initialized(&initialised);
  MPI_Finalized(&finalised);
  if (!initialised || finalised) return 1;
  int s = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &s);
  return s;
}

bool MpiSession::all_ranks_failed(FailureSite site, const std::string& message, int exit_code) {
  const int n = size();
  if (n == 1) return true;
  // Every failing rank contributes (site, code); the maximum of the pair and of its negation
  // tell whether all ranks contributed the same. The reduction is non-blocking and polled, so
  // a rank whose partners never arrive gives up after the wait.
  bool together = false;
  if (failure_comm != MPI_COMM_NULL) {
    const int mine = static_cast<int>(site) * 1000 + exit_code;
    int in[2] = {mine, -mine}, out[2] = {0, 0};
    MPI_Request request;
    MPI_Iallreduce(in, out, 2, MPI_INT, MPI_MAX, failure_comm, &request);
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::duration<double>(
                              internal::failure_wait_seconds(kFailureWaitSeconds));
    int done = 0;
    while (true) {
      MPI_Test(&request, &done, MPI_STATUS_IGNORE);
      if (done || std::chrono::steady_clock::now() > deadline) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    together = done && out[0] == mine && -out[1] == mine;
  }
  if (together) return true;
  std::cerr << "grainlift: error on MPI rank " << rank() << " of " << n << ": " << message
            << (message.empty() || message.back() != '\n' ? "\n" : "")
            << "grainlift: not every rank failed here; ending all " << n << " ranks (MPI_Abort)\n"
            << std::flush;
  MPI_Abort(MPI_COMM_WORLD, exit_code);
  std::abort();  // MPI_Abort does not return
}

}  // namespace grainlift::continuum
