// Internal: small operations on the Trilinos matrices and vectors of FlowProblem (diagonal,
// entries of the owned rows) and sums over the MPI ranks.
// Includes deal.II: never include it from a public header.
#pragma once

#include <deal.II/base/mpi.h>
#include <deal.II/lac/trilinos_index_access.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include <Epetra_CrsMatrix.h>
#include <mpi.h>

#include <vector>

#include "flow_problem.h"

namespace grainlift::continuum::internal {

/// The diagonal of a square Trilinos matrix (locally owned rows) into @p d.
void extract_diagonal(const dealii::TrilinosWrappers::SparseMatrix& m,
                      dealii::TrilinosWrappers::MPI::Vector& d);

/// Element-wise sum over the ranks.
std::vector<double> sum_over_ranks(std::vector<double> v, MPI_Comm comm);

/// Sum over the locally owned entries of f(v_i, w_i), then over the ranks.
template <typename F>
double owned_sum(const VectorType& v, const VectorType& w, F f, MPI_Comm comm) {
  double sum = 0;
  for (unsigned int b = 0; b < v.n_blocks(); ++b) {
    auto wi = w.block(b).begin();
    for (auto vi = v.block(b).begin(); vi != v.block(b).end(); ++vi, ++wi) sum += f(*vi, *wi);
  }
  return dealii::Utilities::MPI::sum(sum, comm);
}

/// Calls f(local row, its length, values, local columns) for the locally owned rows of @p e
/// (Epetra's row views; the values may be written).
template <typename F>
void for_each_row(const Epetra_CrsMatrix& e, F f) {
  for (int r = 0; r < e.NumMyRows(); ++r) {
    int n = 0;
    double* values = nullptr;
    int* columns = nullptr;
    e.ExtractMyRowView(r, n, values, columns);
    f(r, n, values, columns);
  }
}

/// Calls f(row, column, value) for the stored entries of the locally owned rows of @p m
/// (Epetra's row views: deal.II's iterators over a Trilinos matrix cost O(columns) per row).
template <typename F>
void for_each_entry(const dealii::TrilinosWrappers::SparseMatrix& m, F f) {
  const Epetra_CrsMatrix& e = m.trilinos_matrix();
  for_each_row(e, [&](int r, int n, const double* values, const int* columns) {
    const dealii::types::global_dof_index i = dealii::TrilinosWrappers::global_row_index(e, r);
    for (int k = 0; k < n; ++k)
      f(i, dealii::TrilinosWrappers::global_index(e.ColMap(), columns[k]), values[k]);
  });
}

/// @p m with a diagonal entry @p value added in the locally owned rows that have none (a
/// pinned pressure dof has no (p,u) coupling, so its row of B diag(A)^{-1} B^T is empty).
void add_missing_diagonal(dealii::TrilinosWrappers::SparseMatrix& m, double value);

}  // namespace grainlift::continuum::internal
