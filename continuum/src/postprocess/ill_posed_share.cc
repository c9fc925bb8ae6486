// Post-processor (diagnostic): the share of the medium that is sheared, the part of it where
// the viscosity model is ill posed at the local inertial number, and the share of the layer
// next to the intruder's wall sheared above the high end of the well-posed range
// (FlowProblem::ill_posed_share).
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>

#include <cmath>

#include "flow_problem.h"
#include "linear_algebra_utilities.h"
#include "quadrature_rheology.h"

namespace grainlift::continuum::internal {

using namespace dealii;

std::array<double, 3> FlowProblem::ill_posed_share(const Point2& centre, double r0, double r1,
                                                   double high_i) const {
  const VectorType state = ghosted(solution_);
  const QGauss<dim> quad(3);
  FEValues<dim> fev(mapping_, fe_, quad,
                    update_values | update_gradients | update_JxW_values |
                        update_quadrature_points);
  QuadratureRheology qr(quad.size());
  const double rate = setup_.viscosity->regularised_strain_rate();
  // all, sheared, sheared and ill posed; the layer, the layer sheared above high_i
  double area[5] = {0, 0, 0, 0, 0};
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    fev.reinit(cell);
    qr.evaluate(fev, state, *setup_.viscosity);
    for (unsigned int q = 0; q < quad.size(); ++q) {
      const double dist = fev.quadrature_point(q).distance(centre);
      const bool layer = dist >= r0 && dist < r1;
      area[0] += fev.JxW(q);
      if (layer) area[3] += fev.JxW(q);
      if (!(std::sqrt(qr.in.strain_rate_sq[q]) > rate) || !(qr.pressure[q] > 0)) continue;
      area[1] += fev.JxW(q);
      if (setup_.viscosity->well_posedness(qr.out.inertial_number[q]) > 0) area[2] += fev.JxW(q);
      if (layer && qr.out.inertial_number[q] > high_i) area[4] += fev.JxW(q);
    }
  }
  const auto total = sum_over_ranks({area[0], area[1], area[2], area[3], area[4]}, comm_);
  return {total[0] > 0 ? total[1] / total[0] : 0.0, total[1] > 0 ? total[2] / total[1] : 0.0,
          total[3] > 0 ? total[4] / total[3] : 0.0};
}
}  // namespace grainlift::continuum::internal
