// Post-processor (diagnostic): the share of the medium that is sheared, and the part of it
// where the viscosity model is ill posed at the local inertial number
// (FlowProblem::ill_posed_share).
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>

#include <cmath>

#include "flow_problem.h"
#include "linear_algebra_utilities.h"
#include "quadrature_rheology.h"

namespace grainlift::continuum::internal {

using namespace dealii;

std::array<double, 2> FlowProblem::ill_posed_share() const {
  const VectorType state = ghosted(solution_);
  const QGauss<dim> quad(3);
  FEValues<dim> fev(mapping_, fe_, quad, update_values | update_gradients | update_JxW_values);
  QuadratureRheology qr(quad.size());
  const double rate = setup_.viscosity->regularised_strain_rate();
  double area[3] = {0, 0, 0};  // all, sheared, sheared and ill posed
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    fev.reinit(cell);
    qr.evaluate(fev, state, *setup_.viscosity);
    for (unsigned int q = 0; q < quad.size(); ++q) {
      area[0] += fev.JxW(q);
      if (!(std::sqrt(qr.in.strain_rate_sq[q]) > rate) || !(qr.pressure[q] > 0)) continue;
      area[1] += fev.JxW(q);
      if (setup_.viscosity->well_posedness(qr.out.inertial_number[q]) > 0) area[2] += fev.JxW(q);
    }
  }
  const auto total = sum_over_ranks({area[0], area[1], area[2]}, comm_);
  return {total[0] > 0 ? total[1] / total[0] : 0.0, total[1] > 0 ? total[2] / total[1] : 0.0};
}
}  // namespace grainlift::continuum::internal
