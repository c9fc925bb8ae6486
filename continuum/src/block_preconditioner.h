// Internal: the preconditioner of FGMRES for the saddle-point system of FlowProblem (used by
// FlowProblem::solve_iterative, linear_solver.cc). Includes deal.II: never include it from a
// public header.
#pragma once

#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_vector.h>

#include "flow_problem.h"

namespace grainlift::continuum::internal {

/// Block upper-triangular preconditioner of K = [A B^T; B 0]:
///   P = [A B^T; 0 -S],  P^{-1} (x_u, x_p):  y_p = -S^{-1} x_p,  y_u = A^{-1} (x_u - B^T y_p)
/// A^{-1}: one AMG V-cycle on the velocity block. S^{-1}: one AMG V-cycle on B diag(A)^{-1} B^T
/// (SchurApproximation::diagonal_a), or the inverse of the lumped 1/eta-weighted pressure mass
/// matrix (viscosity_mass). B^T y_p is the (u,p) block of K itself (in Newton's Jacobian it
/// also holds the d eta / dp term, so it is not the transpose of the (p,u) block).
class BlockTriangularPreconditioner {
 public:
  /// @p schur_diagonal: the diagonal of the Schur approximation (used for the scaling, and as
  /// S itself when @p schur_amg is null).
  BlockTriangularPreconditioner(const MatrixType& K,
                                const dealii::TrilinosWrappers::PreconditionAMG& a_amg,
                                const dealii::TrilinosWrappers::PreconditionAMG* schur_amg,
                                const dealii::TrilinosWrappers::MPI::Vector& schur_diagonal)
      : K_(K), a_amg_(a_amg), schur_amg_(schur_amg), schur_diagonal_(schur_diagonal),
        xu_(K.block(0, 0).locally_owned_range_indices(), schur_diagonal.get_mpi_communicator()) {}

  void vmult(VectorType& dst, const VectorType& src) const {
    if (schur_amg_) {
      schur_amg_->vmult(dst.block(1), src.block(1));
    } else {
      auto s = schur_diagonal_.begin();
      auto y = dst.block(1).begin();
      for (auto x = src.block(1).begin(); x != src.block(1).end(); ++x, ++y, ++s) *y = *x / *s;
    }
    dst.block(1) *= -1.0;
    K_.block(0, 1).vmult(xu_, dst.block(1));  // B^T y_p
    xu_.sadd(-1.0, 1.0, src.block(0));        // x_u - B^T y_p
    a_amg_.vmult(dst.block(0), xu_);
  }

 private:
  const MatrixType& K_;
  const dealii::TrilinosWrappers::PreconditionAMG& a_amg_;
  const dealii::TrilinosWrappers::PreconditionAMG* schur_amg_;
  const dealii::TrilinosWrappers::MPI::Vector& schur_diagonal_;
  mutable dealii::TrilinosWrappers::MPI::Vector xu_;
};

/// E X E for an operator X (vmult) and a diagonal E (the vector @p e): with E = D the scaled
/// system D K D, with E = D^{-1} its preconditioner D^{-1} P^{-1} D^{-1}.
template <class Operator>
class DiagonallyScaled {
 public:
  DiagonallyScaled(const Operator& X, const VectorType& e) : X_(X), e_(e), t_(e) {}
  void vmult(VectorType& dst, const VectorType& src) const {
    t_ = src;
    t_.scale(e_);
    X_.vmult(dst, t_);
    dst.scale(e_);
  }

 private:
  const Operator& X_;
  const VectorType& e_;
  mutable VectorType t_;
};
}  // namespace grainlift::continuum::internal
