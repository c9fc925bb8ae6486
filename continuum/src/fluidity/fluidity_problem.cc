// FluidityProblem's member functions (see fluidity_problem.h).
#include "fluidity_problem.h"

#include <deal.II/base/function.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_direct.h>
#include <deal.II/numerics/vector_tools.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

namespace grainlift::continuum::fluidity::internal {

using namespace dealii;

CoefficientSupplier pointwise_coefficients(ScalarField xi, ScalarField g_loc) {
  return [xi = std::move(xi), g_loc = std::move(g_loc)](
             const CellIterator&, const std::vector<Point2>& points, CellCoefficients& out) {
    for (std::size_t q = 0; q < points.size(); ++q) {
      out.xi[q] = xi(points[q]);
      out.g_loc[q] = g_loc(points[q]);
    }
  };
}

FluidityProblem::FluidityProblem(const Triangulation<dim>& tria, unsigned int degree,
                                 FluiditySetup setup)
    : tria_(tria),
      setup_(std::move(setup)),
      fe_(degree),
      mapping_(degree),
      quadrature_(degree + 1),
      dof_handler_(tria) {}

void FluidityProblem::run() {
  setup_system();
  assemble_system();
  solve();
}

void FluidityProblem::setup_system() {
  dof_handler_.distribute_dofs(fe_);
  solution_.reinit(dof_handler_.n_dofs());
  system_rhs_.reinit(dof_handler_.n_dofs());

  constraints_.clear();
  DoFTools::make_hanging_node_constraints(dof_handler_, constraints_);
  for (const auto& [id, value] : setup_.dirichlet) {
    const ScalarFunctionFromFunctionObject<dim> f(value);
    VectorTools::interpolate_boundary_values(mapping_, dof_handler_, id, f, constraints_);
  }
  constraints_.close();

  DynamicSparsityPattern dsp(dof_handler_.n_dofs());
  DoFTools::make_sparsity_pattern(dof_handler_, dsp, constraints_, false);
  sparsity_pattern_.copy_from(dsp);
  system_matrix_.reinit(sparsity_pattern_);

  std::ostringstream s;
  s << "fluidity: Q" << fe_.degree << ", " << tria_.n_active_cells() << " cells, "
    << dof_handler_.n_dofs() << " dofs";
  log(s.str());
}

void FluidityProblem::assemble_system() {
  system_matrix_ = 0;
  system_rhs_ = 0;
  FEValues<dim> fe_values(mapping_, fe_, quadrature_,
                          update_values | update_gradients | update_quadrature_points |
                              update_JxW_values);
  const unsigned int n_dofs = fe_.n_dofs_per_cell(), n_q = quadrature_.size();
  FullMatrix<double> cell_matrix(n_dofs, n_dofs);
  Vector<double> cell_rhs(n_dofs);
  std::vector<types::global_dof_index> dof_indices(n_dofs);
  CellCoefficients coef{std::vector<double>(n_q), std::vector<double>(n_q)};

  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    fe_values.reinit(cell);
    cell_matrix = 0;
    cell_rhs = 0;
    setup_.coefficients(CellIterator(cell), fe_values.get_quadrature_points(), coef);
    for (unsigned int q = 0; q < n_q; ++q) {
      // Kamrin & Koval 2012: g - xi^2 Laplacian(g) = g_loc, divided by xi^2 (> 0) so that
      // the weak form is symmetric: (grad g, grad v) + (g / xi^2, v) = (g_loc / xi^2, v);
      // zero flux is its natural condition
      const double inv_k = 1.0 / (coef.xi[q] * coef.xi[q]), jxw = fe_values.JxW(q);
      for (unsigned int i = 0; i < n_dofs; ++i) {
        const double vi = fe_values.shape_value(i, q);
        const Tensor<1, dim> grad_vi = fe_values.shape_grad(i, q);
        for (unsigned int j = 0; j < n_dofs; ++j)
          cell_matrix(i, j) += (grad_vi * fe_values.shape_grad(j, q) +
                                inv_k * vi * fe_values.shape_value(j, q)) * jxw;
        cell_rhs(i) += inv_k * coef.g_loc[q] * vi * jxw;
      }
    }
    cell->get_dof_indices(dof_indices);
    constraints_.distribute_local_to_global(cell_matrix, cell_rhs, dof_indices, system_matrix_,
                                            system_rhs_);
  }
}

void FluidityProblem::solve() {
  SparseDirectUMFPACK direct;
  direct.initialize(system_matrix_);
  solution_ = system_rhs_;
  direct.solve(solution_);
  constraints_.distribute(solution_);
}

std::array<double, 2> FluidityProblem::errors(const ScalarField& g,
                                              const GradientField& grad_g) const {
  const QGauss<dim> quad(fe_.degree + 2);
  FEValues<dim> fe_values(mapping_, fe_, quad,
                          update_values | update_gradients | update_quadrature_points |
                              update_JxW_values);
  std::vector<double> values(quad.size());
  std::vector<Tensor<1, dim>> gradients(quad.size());
  double l2 = 0, h1 = 0;
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    fe_values.reinit(cell);
    fe_values.get_function_values(solution_, values);
    fe_values.get_function_gradients(solution_, gradients);
    for (unsigned int q = 0; q < quad.size(); ++q) {
      const Point2& x = fe_values.quadrature_point(q);
      l2 += std::pow(values[q] - g(x), 2) * fe_values.JxW(q);
      h1 += (gradients[q] - grad_g(x)).norm_square() * fe_values.JxW(q);
    }
  }
  return {std::sqrt(l2), std::sqrt(h1)};
}

double FluidityProblem::max_nodal_error(const ScalarField& g) const {
  Vector<double> exact(dof_handler_.n_dofs());
  VectorTools::interpolate(mapping_, dof_handler_, ScalarFunctionFromFunctionObject<dim>(g),
                           exact);
  exact -= solution_;
  return exact.linfty_norm();
}

}  // namespace grainlift::continuum::fluidity::internal
