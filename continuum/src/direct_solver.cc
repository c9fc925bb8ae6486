// FlowProblem's direct solve: MUMPS through Amesos on the whole matrix, with its memory checked
// before the first factorisation on a mesh (a measured rule before MUMPS's analysis, then its
// own estimate) against what the process may still take (grainlift/shared/machine/memory.h):
// a level that cannot fit is refused with a sentence instead of MUMPS's abort (an allocation
// error in DMUMPS_F77 ends every MPI rank with no word of grainlift's), and a factorisation
// that fails for memory says so (MUMPS's INFOG(1)).
#include <Amesos_Mumps.h>
#include <Epetra_CrsMatrix.h>
#include <Epetra_LinearProblem.h>
#include <deal.II/base/mpi.h>
#include <deal.II/lac/trilinos_vector.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "flow_problem.h"
#include "linear_algebra_utilities.h"
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
// kDirectMemoryMargin for what it leaves out (Amesos's copies, the allocator's slack).
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

/// Throws when an Amesos call on MUMPS failed (@p ierr != 0): OutOfMemory for MUMPS's codes of
/// a workspace too small or an allocation that failed, std::runtime_error otherwise.
void mumps_step(int ierr, Amesos_Mumps& mumps, const char* phase) {
  if (ierr == 0) return;
  const int* infog = mumps.GetINFOG();
  const int code = infog[0];
  std::ostringstream m;
  m << "MUMPS's " << phase << " failed (INFOG(1) = " << code << ", INFOG(2) = " << infog[1];
  // -8, -9, -11, -12, -14, -15: a workspace too small; -13: an allocation failed; -17, -20:
  // a communication buffer too small; -19: the memory allowed by ICNTL(23) (MUMPS 5.5 guide)
  for (const int c : {-8, -9, -11, -12, -13, -14, -15, -17, -19, -20})
    if (code == c) {
      m << (code == -13 ? ": an allocation failed)" : ": a workspace too small)");
      throw OutOfMemory(m.str());
    }
  m << "; Amesos error " << ierr << ": the MUMPS users' guide lists the codes)";
  throw std::runtime_error(m.str());
}
}  // namespace

void FlowProblem::screen_direct_memory() {
  const double n = dof_handler_.n_dofs();
  const double nnz = direct_matrix_.n_nonzero_elements();
  const double ranks = dealii::Utilities::MPI::n_mpi_processes(comm_);
  // before MUMPS: its analysis and, by the measured rule, its factors
  const double screen = std::max(kAnalysisBytesPerNonzero * nnz,
                                 kFactorRuleBytes * std::pow(n, kFactorRuleExponent));
  if (const Verdict v = judge(screen / ranks, screen, comm_); v.short_anywhere)
    refuse_direct_solve(v.need, v.room, v.short_here,
                        "the measured rule for its analysis and factors");
}

void FlowProblem::check_direct_memory(const int* infog) {
  const double nnz = direct_matrix_.n_nonzero_elements();
  const double ranks = dealii::Utilities::MPI::n_mpi_processes(comm_);
  // INFOG(16): the most any rank needs, INFOG(17): all ranks together, both in millions of
  // bytes for the in-core factorisation (the same on every rank after the analysis)
  const double triplets = kTripletBytesPerNonzero * nnz;
  const Verdict v = judge(kDirectMemoryMargin * 1e6 * infog[15] + triplets / ranks,
                          kDirectMemoryMargin * 1e6 * infog[16] + triplets, comm_);
  std::ostringstream m;
  m << "continuum: the direct solve of " << dof_handler_.n_dofs() << " unknowns needs about "
    << format_bytes(v.need) << " (MUMPS's estimate of " << infog[16] << " MB, with a margin); "
    << (v.room.bytes >= 0 ? format_bytes(v.room.bytes) + " left (" + v.room.limit + ")"
                          : std::string("no memory limit found"));
  log(m.str());
  if (v.short_anywhere)
    refuse_direct_solve(v.need, v.room, v.short_here,
                        "MUMPS's estimate after its analysis, with a margin");
}

void FlowProblem::refuse_direct_solve(double need, const MemoryRoom& room, bool short_here,
                                      const char* source) const {
  std::ostringstream m;
  m << "the direct solve (MUMPS) of " << dof_handler_.n_dofs() << " unknowns needs about "
    << format_bytes(need) << " (" << source << "), ";
  if (short_here)
    m << "where " << format_bytes(room.bytes) << " are left (the limit: " << room.limit << ")";
  else
    m << "more than another rank has left";
  throw OutOfMemory(m.str());
}

/// MUMPS on one mesh: the right-hand side and solution it reads and writes, and its analysis
/// (the fill-reducing ordering and the symbolic factorisation, PORD), kept between the solves
/// of the mesh: the pattern does not change, only the values. A fresh analysis at every solve
/// took a fifth of the demo's nonlocal fluidity run at refinement 2 (perf: 20% in MUMPS's
/// analysis, 7% more in its ordering's clock() calls).
struct FlowProblem::DirectFactorization {
  DirectFactorization(const TrilinosWrappers::SparseMatrix& a, const IndexSet& owned,
                      MPI_Comm comm)
      : b(owned, comm),
        x(owned, comm),
        problem(const_cast<Epetra_CrsMatrix*>(&a.trilinos_matrix()), &x.trilinos_vector(),
                const_cast<Epetra_FEVector*>(&b.trilinos_vector())),
        mumps(problem) {}
  TrilinosWrappers::MPI::Vector b, x;
  Epetra_LinearProblem problem;
  Amesos_Mumps mumps;
  bool analysed = false;
  /// where each stored entry of the blocks (0,0), (0,1), (1,0), (1,1) goes in the one matrix,
  /// in the order of their row views: the copy is then a loop of stores (Epetra's
  /// ReplaceGlobalValues, a binary search per entry, took 13% of the run above)
  std::vector<double*> destination;
  double sink = 0;  ///< where the entries go that the one matrix lacks
};

void FlowProblem::map_blocks_into_direct_matrix() {
  Epetra_CrsMatrix& a = const_cast<Epetra_CrsMatrix&>(direct_matrix_.trilinos_matrix());
  std::vector<double*>& dest = direct_->destination;
  dest.clear();
  using Index = TrilinosWrappers::types::int_type;
  const Index offset[2] = {0, static_cast<Index>(n_u_)};
  for (unsigned int bi = 0; bi < 2; ++bi)
    for (unsigned int bj = 0; bj < 2; ++bj) {
      const Epetra_CrsMatrix& e = system_matrix_.block(bi, bj).trilinos_matrix();
      for_each_row(e, [&](int r, int n, double*, int* columns) {
        const Index row = offset[bi] + TrilinosWrappers::global_row_index(e, r);
        const int ar = a.RowMap().LID(row);
        int an = 0;
        double* av = nullptr;
        int* ac = nullptr;
        a.ExtractMyRowView(ar, an, av, ac);
        for (int k = 0; k < n; ++k) {
          const Index col = offset[bj] + TrilinosWrappers::global_index(e.ColMap(), columns[k]);
          const int lc = a.ColMap().LID(col);
          const int* hit = std::find(ac, ac + an, lc);
          // an entry the one matrix lacks: on several ranks a block row with no coupling (a
          // constrained velocity row of the (0,1) block) holds a zero placeholder; it goes to
          // the sink, as Epetra's ReplaceGlobalValues dropped it before
          dest.push_back(hit != ac + an ? av + (hit - ac) : &direct_->sink);
        }
      });
    }
}

void FlowProblem::DirectFactorizationDeleter::operator()(DirectFactorization* d) const {
  delete d;
}

void FlowProblem::analyse(DirectFactorization& d) {
  mumps_step(d.mumps.SymbolicFactorization(), d.mumps, "analysis");
  if (!d.analysed) check_direct_memory(d.mumps.GetINFOG());  // the mesh's first analysis
  d.analysed = true;
}

double FlowProblem::factorise_and_solve(DirectFactorization& d, bool kept) {
  const int ierr = d.mumps.NumericFactorization();
  if (ierr != 0 && kept) return std::numeric_limits<double>::infinity();  // analyse again
  mumps_step(ierr, d.mumps, "factorisation");
  mumps_step(d.mumps.Solve(), d.mumps, "solve");
  TrilinosWrappers::MPI::Vector r(d.b);
  direct_matrix_.vmult(r, d.x);
  r -= d.b;
  const double nb = d.b.l2_norm();
  return nb > 0 ? r.l2_norm() / nb : r.l2_norm();
}

// MUMPS on the blocks copied into one matrix (global numbering: the blocks'
// one after the other), on any number of ranks. On one rank it replaced UMFPACK: 1.4x faster
// on the demo geometry at refinement 3 (44,944 unknowns), and UMFPACK's factors of the Newton
// Jacobian at refinement 4 (177,440 unknowns, Coulomb wall) left relative residuals of 1e2-1e7
// where MUMPS's leave 1e-12 (docs/performance.md). The solution's relative residual
// |A x - b| / |b| is checked after every solve: the worst goes to the report, and one above
// 1e-8 is logged (the nonlinear solver's line search then rejects the step).
//
// The analysis is made once per mesh: MUMPS pivots again in every factorisation, but its
// ordering and workspace come from the first matrix; a factorisation that fails, or a solve
// that leaves a residual above 1e-8, on a kept analysis is done again after a fresh one.
void FlowProblem::solve_direct(const VectorType& residual, VectorType& update) {
  const IndexSet& owned = dof_handler_.locally_owned_dofs();
  // what deal.II's SolverDirect("Amesos_Mumps") does, with MUMPS's own numbers at hand: its
  // memory estimate before the first factorisation on a mesh, its error codes on failure
  if (!direct_) {  // a new mesh (setup_system() drops the last one's)
    screen_direct_memory();
    direct_.reset(new DirectFactorization(direct_matrix_, owned, comm_));
    map_blocks_into_direct_matrix();
  }
  DirectFactorization& d = *direct_;
  auto to = d.destination.begin();
  for (unsigned int bi = 0; bi < 2; ++bi)
    for (unsigned int bj = 0; bj < 2; ++bj)
      for_each_row(system_matrix_.block(bi, bj).trilinos_matrix(),
                   [&](int, int n, double* values, int*) {
                     for (int k = 0; k < n; ++k) **to++ = values[k];
                   });
  for (const auto i : owned) d.b(i) = residual(i);
  d.b.compress(VectorOperation::insert);
  const bool kept = d.analysed;
  if (!kept) analyse(d);
  double rel = factorise_and_solve(d, kept);
  if (kept && !(rel <= 1e-8)) {  // the kept analysis may no longer suit: a fresh one
    analyse(d);
    rel = factorise_and_solve(d, false);
  }
  report_.worst_direct_residual = std::max(report_.worst_direct_residual, rel);
  if (!(rel <= 1e-8) && setup_.log) {
    std::ostringstream m;
    m.precision(2);
    m << "the direct solve left a relative linear residual of " << rel;
    setup_.log(m.str());
  }
  for (const auto i : owned) update(i) = -d.x(i);
  update.compress(VectorOperation::insert);
}

}  // namespace grainlift::continuum::internal
