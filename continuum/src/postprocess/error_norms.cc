// Post-processor (verification): L2 and H1-seminorm errors of the velocity and the L2 error of
// the pressure against exact fields (FlowProblem::errors).
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>

#include <algorithm>
#include <cmath>

#include "flow_problem.h"
#include "linear_algebra_utilities.h"
#include "quadrature_rheology.h"

namespace grainlift::continuum::internal {

using namespace dealii;

std::array<double, 3> FlowProblem::errors(
    const VectorField& u_exact, const std::function<Tensor<2, dim>(const Point2&)>& grad_exact,
    const ScalarField& p_exact, bool remove_mean_pressure) const {
  const VectorType state = ghosted(solution_);
  const QGauss<dim> quad(5);
  FEValues<dim> fev(
      mapping_, fe_, quad,
      update_values | update_gradients | update_quadrature_points | update_JxW_values);
  std::vector<Vec2> u(quad.size());
  std::vector<Tensor<2, dim>> g(quad.size());
  std::vector<double> p(quad.size());
  std::vector<double> sums(5, 0.0);  // u, grad u, p errors squared, p error, area
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    fev.reinit(cell);
    fev[kVelocity].get_function_values(state, u);
    fev[kVelocity].get_function_gradients(state, g);
    fev[kPressure].get_function_values(state, p);
    for (unsigned int q = 0; q < quad.size(); ++q) {
      const Point2& x = fev.quadrature_point(q);
      const double w = fev.JxW(q);
      sums[0] += (u[q] - u_exact(x)).norm_square() * w;
      sums[1] += (g[q] - grad_exact(x)).norm_square() * w;
      const double e = p[q] - p_exact(x);
      sums[2] += e * e * w;
      sums[3] += e * w;
      sums[4] += w;
    }
  }
  sums = sum_over_ranks(sums, comm_);
  double ep = sums[2];
  if (remove_mean_pressure) ep -= sums[3] * sums[3] / sums[4];
  return {std::sqrt(sums[0]), std::sqrt(sums[1]), std::sqrt(std::max(ep, 0.0))};
}
}  // namespace grainlift::continuum::internal
