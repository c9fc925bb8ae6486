// FlowProblem's linear solves: system_matrix * update = -residual, direct (MUMPS through
// Amesos, any number of ranks: direct_solver.cc) or FGMRES with the block preconditioner
// (block_preconditioner.h) on the diagonally scaled system.
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/solver_gmres.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_solver.h>

#include <cmath>
#include <sstream>

#include "block_preconditioner.h"
#include "flow_problem.h"
#include "linear_algebra_utilities.h"

namespace grainlift::continuum::internal {

using namespace dealii;

int FlowProblem::solve(const VectorType& residual, VectorType& update, double relative_tolerance) {
  int iterations = 0;
  update.reinit(owned_, comm_);
  if (setup_.linear_solver == LinearSolver::amg) {
    iterations = solve_iterative(residual, update, relative_tolerance);
    update *= -1.0;
  } else {
    solve_direct(residual, update);
  }
  zero_constraints_.distribute(update);
  ++report_.linear_solves;
  report_.krylov_iterations += iterations;
  return iterations;
}

int FlowProblem::solve_iterative(const VectorType& rhs, VectorType& x, double relative_tolerance) {
  const TrilinosWrappers::SparseMatrix& A = system_matrix_.block(0, 0);
  // AMG (Trilinos ML, smoothed aggregation) on the velocity block: the two velocity components
  // as the near-null space, Q2 elements. The block is symmetric without inertia (the Newton
  // term 2 eta_s (D:D_j)(D:D_i) is symmetric); "elliptic" (Chebyshev smoother) measured better
  // than the non-symmetric setting on the cylinder (76 against 103 FGMRES iterations per solve).
  TrilinosWrappers::PreconditionAMG a_amg;
  {
    TrilinosWrappers::PreconditionAMG::AdditionalData data;
    data.elliptic = true;
    data.higher_order_elements = true;
    data.smoother_sweeps = 2;
    data.aggregation_threshold = 0.02;
    data.constant_modes = velocity_constant_modes_;
    a_amg.initialize(A, data);
  }
  // Schur complement approximation
  TrilinosWrappers::MPI::Vector schur_diagonal(owned_[1], comm_);
  TrilinosWrappers::SparseMatrix schur_bdb;
  TrilinosWrappers::PreconditionAMG s_amg;
  const bool diagonal_a = setup_.schur_approximation == SchurApproximation::diagonal_a;
  if (diagonal_a) {
    // S = B diag(A)^{-1} B^T, a pressure Laplacian weighted by the actual velocity block:
    // unlike M_p / eta it sees the constraints and where eta jumps by decades between cells
    TrilinosWrappers::MPI::Vector inv_diag(owned_[0], comm_);
    extract_diagonal(A, inv_diag);
    for (auto& v : inv_diag) v = 1.0 / std::abs(v);
    system_matrix_.block(1, 0).mmult(schur_bdb, system_matrix_.block(0, 1), inv_diag);
    // rows without a (p,u) coupling (a pinned pressure): unit-scale diagonal
    extract_diagonal(schur_bdb, schur_diagonal);
    double dmax = 0;
    bool missing = false;
    for (const double v : schur_diagonal) {
      dmax = std::max(dmax, std::abs(v));
      missing = missing || !(std::abs(v) > 0);
    }
    dmax = Utilities::MPI::max(dmax, comm_);
    if (Utilities::MPI::logical_or(missing, comm_)) {
      add_missing_diagonal(schur_bdb, dmax);
      extract_diagonal(schur_bdb, schur_diagonal);
    }
    for (auto& v : schur_diagonal) v = std::abs(v);
    TrilinosWrappers::PreconditionAMG::AdditionalData data;
    data.elliptic = true;
    data.smoother_sweeps = 2;
    s_amg.initialize(schur_bdb, data);
  } else {
    TrilinosWrappers::MPI::Vector ones(owned_[1], comm_);
    ones = 1.0;
    schur_mass_.block(1, 1).vmult(schur_diagonal, ones);  // lumped: row sums, positive for Q1
  }
  const BlockTriangularPreconditioner prec(system_matrix_, a_amg, diagonal_a ? &s_amg : nullptr,
                                           schur_diagonal);
  // The momentum and continuity rows of K have different units and scales (forces against
  // h div u), and eta varies by decades: the Euclidean residual of K barely sees div u. FGMRES
  // therefore works on D K D y = D rhs, x = D y, D = diag(A_ii)^(-1/2) on the velocity and
  // diag(S_ii)^(-1/2) on the pressure (both blocks with unit diagonal, an energy-like norm);
  // the tolerance applies to |D r|.
  VectorType d = make_vector(), d_inverse = make_vector(), b = make_vector(), y = make_vector();
  extract_diagonal(A, d.block(0));
  d.block(1) = schur_diagonal;
  for (unsigned int blk = 0; blk < 2; ++blk) {
    auto di = d_inverse.block(blk).begin();
    for (auto& v : d.block(blk)) {
      const double a = std::abs(v);
      v = a > 0 && std::isfinite(a) ? 1.0 / std::sqrt(a) : 1.0;
      *di++ = 1.0 / v;
    }
  }
  b = rhs;
  b.scale(d);
  const DiagonallyScaled<MatrixType> scaled(system_matrix_, d);
  const DiagonallyScaled<BlockTriangularPreconditioner> scaled_prec(prec, d_inverse);
  const double b_norm = b.l2_norm();
  SolverControl control(1000, std::max(relative_tolerance * b_norm, 1e-300));
  SolverFGMRES<VectorType> fgmres(control, SolverFGMRES<VectorType>::AdditionalData(100));
  try {
    fgmres.solve(scaled, y, b, scaled_prec);
  } catch (const SolverControl::NoConvergence& e) {
    std::ostringstream os;
    os << "continuum: FGMRES did not reach " << relative_tolerance << " in " << e.last_step
       << " iterations (|D r|/|D b| = " << e.last_residual / std::max(b_norm, 1e-300)
       << "); the step is used as it is";
    log(os.str());
  }
  x = y;
  x.scale(d);
  return static_cast<int>(control.last_step());
}
}  // namespace grainlift::continuum::internal
