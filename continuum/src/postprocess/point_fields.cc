// Post-processor: the state (velocity, pressure, viscosity, inertial number, stress) at
// arbitrary points of the medium (FlowProblem::point_state, FlowProblem::point_states).
#include <deal.II/base/mpi.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_tools.h>

#include <mpi.h>

#include <algorithm>

#include "flow_problem.h"
#include "linear_algebra_utilities.h"
#include "quadrature_rheology.h"

namespace grainlift::continuum::internal {

using namespace dealii;

bool FlowProblem::point_state(const Point2& x, PointState& out) const {
  std::vector<char> found;
  const auto states = point_states({x}, found);
  out = states[0];
  return found[0] != 0;
}

std::vector<PointState> FlowProblem::point_states(const std::vector<Point2>& points,
                                                  std::vector<char>& found) const {
  if (!cache_) cache_ = std::make_unique<GridTools::Cache<dim>>(tria_, mapping_);
  const VectorType state = ghosted(solution_);
  const unsigned int me = Utilities::MPI::this_mpi_process(comm_), n_ranks = this->n_ranks();
  const std::size_t n = points.size();
  constexpr unsigned int kValues = 8;  // u (2), p, eta, I, stress (3)
  std::vector<PointState> local(n);
  std::vector<unsigned int> owner(n, n_ranks);  // lowest rank that found the point
  std::vector<SymmetricTensor<2, dim>> sym(1);
  std::vector<double> p(1);
  std::vector<Vec2> u(1);
  const auto before = [](const Point<dim>& a, const Point<dim>& b) {
    return a[0] < b[0] || (a[0] == b[0] && a[1] < b[1]);
  };
  for (std::size_t k = 0; k < n; ++k) {
    std::pair<Triangulation<dim>::active_cell_iterator, Point<dim>> cp;
    try {
      cp = GridTools::find_active_cell_around_point(*cache_, points[k]);
    } catch (...) {
      continue;
    }
    if (cp.first == tria_.end() || cp.first.state() != IteratorState::valid) continue;
    // A point on a cell edge lies in several cells, where the stress differs: take the one
    // whose centre comes first (x, then y), whatever the partition (all of them are ours or
    // ghosts when the point is in one of ours), and evaluate on the rank that owns it.
    const auto& vertex_to_cells = cache_->get_vertex_to_cell_map();
    const auto first = cp.first;
    for (const unsigned int v : first->vertex_indices())
      for (const auto& c : vertex_to_cells[first->vertex_index(v)]) {
        if (c->is_artificial() || !before(c->center(), cp.first->center())) continue;
        try {
          const Point<dim> xi = mapping_.transform_real_to_unit_cell(c, points[k]);
          if (GeometryInfo<dim>::is_inside_unit_cell(xi, 1e-10)) cp = {c, xi};
        } catch (const Mapping<dim>::ExcTransformationFailed&) {
        }
      }
    if (!cp.first->is_locally_owned()) continue;
    const DoFHandler<dim>::active_cell_iterator cell(&tria_, cp.first->level(), cp.first->index(),
                                                     &dof_handler_);
    const Quadrature<dim> q(GeometryInfo<dim>::project_to_unit_cell(cp.second));
    FEValues<dim> fv(mapping_, fe_, q, update_values | update_gradients);
    fv.reinit(cell);
    fv[kVelocity].get_function_symmetric_gradients(state, sym);
    fv[kPressure].get_function_values(state, p);
    fv[kVelocity].get_function_values(state, u);
    local[k] = make_state(sym[0], p[0], u[0], cell, q.point(0));
    owner[k] = me;
  }
  found.assign(n, 0);
  if (n_ranks == 1) {
    for (std::size_t k = 0; k < n; ++k) found[k] = owner[k] == me;
    return local;
  }
  MPI_Allreduce(MPI_IN_PLACE, owner.data(), static_cast<int>(n), MPI_UNSIGNED, MPI_MIN, comm_);
  std::vector<double> values(kValues * n, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    if (owner[k] != me) continue;
    const PointState& s = local[k];
    const double v[kValues] = {s.velocity[0], s.velocity[1], s.pressure, s.viscosity,
                               s.inertial_number, s.stress[0][0], s.stress[0][1], s.stress[1][1]};
    std::copy(v, v + kValues, values.begin() + kValues * k);
  }
  values = sum_over_ranks(values, comm_);
  std::vector<PointState> out(n);
  for (std::size_t k = 0; k < n; ++k) {
    found[k] = owner[k] < n_ranks;
    if (!found[k]) continue;
    const double* v = values.data() + kValues * k;
    out[k].velocity = Vec2({v[0], v[1]});
    out[k].pressure = v[2];
    out[k].viscosity = v[3];
    out[k].inertial_number = v[4];
    out[k].stress[0][0] = v[5];
    out[k].stress[0][1] = v[6];
    out[k].stress[1][1] = v[7];
  }
  return out;
}
}  // namespace grainlift::continuum::internal
