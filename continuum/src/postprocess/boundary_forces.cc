// Post-processor: force and torque of the medium on a boundary, from the consistent reaction
// (FlowProblem::reaction, the unconstrained volume residual tested with rigid motions) and by
// integration of sigma.n over the boundary faces (FlowProblem::surface_integral, a diagnostic).
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>

#include "flow_problem.h"
#include "linear_algebra_utilities.h"
#include "quadrature_rheology.h"

namespace grainlift::continuum::internal {

using namespace dealii;

std::map<types::global_dof_index, double> FlowProblem::boundary_reaction(
    types::boundary_id id) const {
  VectorType r;
  assemble_impl(ghosted(solution_), nullptr, false, r, true);
  const IndexSet bd =
      DoFTools::extract_boundary_dofs(dof_handler_, fe_.component_mask(kVelocity), {id});
  std::map<types::global_dof_index, double> out;
  // the medium's force on the body is minus the residual tested with a rigid motion
  for (const auto i : bd)
    if (dof_handler_.locally_owned_dofs().is_element(i)) out.emplace(i, -r(i));
  return out;
}

ForceTorque FlowProblem::reaction(types::boundary_id id, const Point2& centre) const {
  const auto f_nodal = boundary_reaction(id);
  std::map<types::global_dof_index, Point<dim>> support;
  DoFTools::map_dofs_to_support_points(mapping_, dof_handler_, support);
  const IndexSet x_dofs =
      DoFTools::extract_dofs(dof_handler_, fe_.component_mask(FEValuesExtractors::Scalar(0)));
  ForceTorque ft;
  for (const auto& [i, f] : f_nodal) {
    const unsigned int c = x_dofs.is_element(i) ? 0 : 1;
    const Vec2 arm = support.at(i) - centre;
    (c == 0 ? ft.fx : ft.fy) += f;
    ft.torque += c == 0 ? -arm[1] * f : arm[0] * f;
  }
  const auto sum = sum_over_ranks({ft.fx, ft.fy, ft.torque}, comm_);
  return {sum[0], sum[1], sum[2]};
}

ForceTorque FlowProblem::surface_integral(types::boundary_id id, const Point2& centre) const {
  const VectorType state = ghosted(solution_);
  const QGauss<dim - 1> fquad(4);
  FEFaceValues<dim> ffv(mapping_, fe_, fquad,
                        update_values | update_gradients | update_quadrature_points |
                            update_normal_vectors | update_JxW_values);
  std::vector<SymmetricTensor<2, dim>> sym(fquad.size());
  std::vector<double> p(fquad.size());
  std::vector<Vec2> u(fquad.size());
  ForceTorque ft;
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    for (const auto& face : cell->face_iterators()) {
      if (!face->at_boundary() || face->boundary_id() != id) continue;
      ffv.reinit(cell, face);
      ffv[kVelocity].get_function_symmetric_gradients(state, sym);
      ffv[kPressure].get_function_values(state, p);
      ffv[kVelocity].get_function_values(state, u);
      for (unsigned int q = 0; q < fquad.size(); ++q) {
        const PointState s = make_state(sym[q], p[q], u[q], ffv, q);
        const Vec2 n_body = -ffv.normal_vector(q);  // outward normal of the body
        const Vec2 t = s.stress * n_body;
        const Vec2 arm = ffv.quadrature_point(q) - centre;
        ft.fx += t[0] * ffv.JxW(q);
        ft.fy += t[1] * ffv.JxW(q);
        ft.torque += (arm[0] * t[1] - arm[1] * t[0]) * ffv.JxW(q);
      }
    }
  }
  const auto sum = sum_over_ranks({ft.fx, ft.fy, ft.torque}, comm_);
  return {sum[0], sum[1], sum[2]};
}
}  // namespace grainlift::continuum::internal
