#include "grainlift/continuum/mpi_session.h"

#include <deal.II/base/mpi.h>

#include <mpi.h>

namespace grainlift::continuum {

struct MpiSession::Impl {
  Impl(int& argc, char**& argv) : init(argc, argv, 1) {}
  dealii::Utilities::MPI::MPI_InitFinalize init;
};

MpiSession::MpiSession(int& argc, char**& argv) {
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (!initialised) impl_ = std::make_unique<Impl>(argc, argv);
}

MpiSession::~MpiSession() = default;

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

}  // namespace grainlift::continuum
