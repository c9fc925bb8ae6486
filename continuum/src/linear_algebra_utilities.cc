#include "linear_algebra_utilities.h"

#include <deal.II/base/mpi.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>

#include <Epetra_Vector.h>

#include <cmath>
#include <utility>

namespace grainlift::continuum::internal {

using namespace dealii;

void extract_diagonal(const TrilinosWrappers::SparseMatrix& m, TrilinosWrappers::MPI::Vector& d) {
  Epetra_Vector view(View, d.trilinos_vector(), 0);
  const int ierr = m.trilinos_matrix().ExtractDiagonalCopy(view);
  AssertThrow(ierr == 0, ExcMessage("continuum: cannot extract the matrix diagonal"));
}

std::vector<double> sum_over_ranks(std::vector<double> v, MPI_Comm comm) {
  MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), MPI_DOUBLE, MPI_SUM, comm);
  return v;
}

void add_missing_diagonal(TrilinosWrappers::SparseMatrix& m, double value) {
  const IndexSet rows = m.locally_owned_range_indices();
  TrilinosWrappers::SparsityPattern sp(rows, rows, m.get_mpi_communicator());
  std::vector<std::pair<types::global_dof_index, std::pair<types::global_dof_index, double>>>
      entries;
  for (const auto i : rows) sp.add(i, i);
  for_each_entry(m, [&](types::global_dof_index i, types::global_dof_index j, double v) {
    sp.add(i, j);
    entries.push_back({i, {j, v}});
  });
  sp.compress();
  m.reinit(sp);
  for (const auto& [i, e] : entries) m.set(i, e.first, e.second);
  for (const auto i : rows)
    if (!(std::abs(m.diag_element(i)) > 0)) m.set(i, i, value);
  m.compress(VectorOperation::insert);
}

}  // namespace grainlift::continuum::internal
