// Post-processor: the solution, the cell-averaged viscosity and inertial number in one .vtu
// file (FlowProblem::output_results).
#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/numerics/data_out.h>

#include <mpi.h>

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "flow_problem.h"
#include "quadrature_rheology.h"

namespace grainlift::continuum::internal {

using namespace dealii;

namespace {
/// @p text to @p file through a temporary file renamed into place; std::runtime_error naming
/// the file and the cause (strerror) when it cannot be written, the temporary file removed.
void write_file_atomically(const std::string& file, const std::string& text) {
  const std::string tmp = file + ".tmp." + std::to_string(::getpid());
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  int err = f ? 0 : errno;
  if (f) {
    if (std::fwrite(text.data(), 1, text.size(), f) != text.size()) err = errno;
    if (std::fclose(f) != 0 && err == 0) err = errno;
  }
  if (err == 0 && std::rename(tmp.c_str(), file.c_str()) != 0) err = errno;
  if (err != 0) {
    std::remove(tmp.c_str());
    throw std::runtime_error(file + ": cannot write the file: " + std::strerror(err));
  }
}
}  // namespace

void FlowProblem::output_results(const std::string& directory, const std::string& basename) const {
  if (Utilities::MPI::this_mpi_process(comm_) == 0) std::filesystem::create_directories(directory);
  MPI_Barrier(comm_);
  const VectorType state = ghosted(solution_);
  // cell averages of the viscosity and of the inertial number (this rank's cells)
  Vector<float> eta(tria_.n_active_cells()), inertial(tria_.n_active_cells());
  {
    const QGauss<dim> quad(3);
    FEValues<dim> fev(mapping_, fe_, quad, update_gradients | update_values);
    QuadratureRheology qr(quad.size());
    for (const auto& cell : dof_handler_.active_cell_iterators()) {
      if (!cell->is_locally_owned()) continue;
      fev.reinit(cell);
      qr.evaluate(fev, state, *setup_.viscosity);
      double a = 0, b = 0;
      for (unsigned int q = 0; q < quad.size(); ++q) {
        a += qr.out.viscosity[q];
        b += std::min(qr.out.inertial_number[q], 1e30);
      }
      eta(cell->active_cell_index()) = static_cast<float>(a / quad.size());
      inertial(cell->active_cell_index()) = static_cast<float>(b / quad.size());
    }
  }
  DataOut<dim> data_out;
  data_out.attach_dof_handler(dof_handler_);
  std::vector<std::string> names{"velocity", "velocity", "pressure"};
  std::vector<DataComponentInterpretation::DataComponentInterpretation> interp{
      DataComponentInterpretation::component_is_part_of_vector,
      DataComponentInterpretation::component_is_part_of_vector,
      DataComponentInterpretation::component_is_scalar};
  data_out.add_data_vector(state, names, DataOut<dim>::type_dof_data, interp);
  data_out.add_data_vector(eta, "viscosity", DataOut<dim>::type_cell_data);
  data_out.add_data_vector(inertial, "inertial_number", DataOut<dim>::type_cell_data);
  data_out.build_patches(mapping_, 2, DataOut<dim>::curved_inner_cells);
  const std::string file = (std::filesystem::path(directory) / (basename + ".vtu")).string();
  if (n_ranks() == 1) {
    // written whole to a temporary name and renamed: the previous file stays on a failure
    std::ostringstream text;
    data_out.write_vtu(text);
    write_file_atomically(file, text.str());
  } else {
    // one .vtu, each rank writing its cells' patches (MPI I/O)
    data_out.write_vtu_in_parallel(file, comm_);
  }
}
}  // namespace grainlift::continuum::internal
