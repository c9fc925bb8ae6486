// FlowProblem::check_direct_memory(): the memory of the direct solve, estimated by MUMPS's own
// analysis before the first factorisation on a mesh, against what the process may still take
// (grainlift/shared/machine/memory.h). A level that cannot fit is refused with a sentence
// instead of MUMPS's abort (an allocation error in DMUMPS_F77 ends every MPI rank, with no
// word of grainlift's).
#include <Amesos_Mumps.h>
#include <Epetra_CrsMatrix.h>
#include <Epetra_LinearProblem.h>
#include <deal.II/base/mpi.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "flow_problem.h"
#include "grainlift/continuum/errors.h"
#include "grainlift/shared/machine/memory.h"

namespace grainlift::continuum::internal {

using namespace dealii;

namespace {
// Measured on the demo's meshes, refinements 0-4 (docs/reliability.md): MUMPS's analysis takes
// about 24 bytes per nonzero of the matrix (the triplet copy and its graph), and its estimate
// of the factorisation grows like 538 bytes x unknowns^1.14 (5, 23, 113, 519 MB at 3,028 to
// 177,440 unknowns). The analysis itself can abort where memory is short, so these rules
// screen a mesh before MUMPS sees it; its own estimate decides after the analysis, with
// kDirectMemoryMargin for what it leaves out (the solve's second analysis, the allocator).
constexpr double kAnalysisBytesPerNonzero = 40, kFactorRuleBytes = 538, kFactorRuleExponent = 1.14;
constexpr double kDirectMemoryMargin = 1.3, kTripletBytesPerNonzero = 24;

/// Whether any rank lacks memory for @p need bytes (per rank, or all ranks together where the
/// limit is the machine's or the control group's, which the ranks on it share).
struct Verdict {
  bool short_here = false, short_anywhere = false;
  double need = 0;
  MemoryRoom room;
};

Verdict judge(double per_rank, double total, MPI_Comm comm) {
  Verdict v;
  v.room = memory_room();
  const bool shared = v.room.limit.find("ulimit") == std::string::npos;
  v.need = shared ? total : per_rank;
  v.short_here = v.room.bytes >= 0 && v.need > v.room.bytes;
  v.short_anywhere = dealii::Utilities::MPI::logical_or(v.short_here, comm);
  return v;
}
}  // namespace

void FlowProblem::check_direct_memory() {
  direct_memory_checked_ = true;
  const double n = dof_handler_.n_dofs();
  const double nnz = direct_matrix_.n_nonzero_elements();
  const double ranks = dealii::Utilities::MPI::n_mpi_processes(comm_);
  auto refuse = [&](const Verdict& v, const char* source) {
    std::ostringstream m;
    m << "the direct solve (MUMPS) of " << dof_handler_.n_dofs() << " unknowns needs about "
      << format_bytes(v.need) << " (" << source << "), ";
    if (v.short_here)
      m << "where " << format_bytes(v.room.bytes) << " are left (the limit: " << v.room.limit
        << ")";
    else
      m << "more than another rank has left";
    throw OutOfMemory(m.str());
  };
  // before MUMPS: its analysis and, by the measured rule, its factors
  const double screen = std::max(kAnalysisBytesPerNonzero * nnz,
                                 kFactorRuleBytes * std::pow(n, kFactorRuleExponent));
  if (const Verdict v = judge(screen / ranks, screen, comm_); v.short_anywhere)
    refuse(v, "the measured rule for its analysis and factors");
  Epetra_LinearProblem problem;
  problem.SetOperator(const_cast<Epetra_CrsMatrix*>(&direct_matrix_.trilinos_matrix()));
  Amesos_Mumps mumps(problem);
  if (mumps.SymbolicFactorization() != 0) return;  // the solve itself will say what is wrong
  // INFOG(16): the most any rank needs, INFOG(17): all ranks together, both in millions of
  // bytes for the in-core factorisation (the same on every rank after the analysis)
  const int* infog = mumps.GetINFOG();
  const double triplets = kTripletBytesPerNonzero * nnz;
  const Verdict v = judge(kDirectMemoryMargin * 1e6 * infog[15] + triplets / ranks,
                          kDirectMemoryMargin * 1e6 * infog[16] + triplets, comm_);
  std::ostringstream m;
  m << "continuum: the direct solve of " << dof_handler_.n_dofs() << " unknowns needs about "
    << format_bytes(v.need) << " (MUMPS's estimate of " << infog[16] << " MB, with a margin); "
    << (v.room.bytes >= 0 ? format_bytes(v.room.bytes) + " left (" + v.room.limit + ")"
                          : std::string("no memory limit found"));
  log(m.str());
  if (v.short_anywhere) refuse(v, "MUMPS's estimate after its analysis, with a margin");
}

}  // namespace grainlift::continuum::internal
