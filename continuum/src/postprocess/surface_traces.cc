// Post-processor: the state and the consistent traction at a point of a boundary given by its
// angle about a centre (FlowProblem::boundary_state, FlowProblem::consistent_traction).
#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_direct.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>

#include <cmath>
#include <stdexcept>

#include "flow_problem.h"
#include "linear_algebra_utilities.h"
#include "quadrature_rheology.h"

namespace grainlift::continuum::internal {

using namespace dealii;

namespace {
double wrap_angle(double a) {
  while (a > M_PI) a -= 2 * M_PI;
  while (a <= -M_PI) a += 2 * M_PI;
  return a;
}
}  // namespace

int FlowProblem::visit_boundary_at_angle(
    types::boundary_id id, const Point2& centre, double angle, UpdateFlags flags, const char* who,
    const std::function<void(const FEFaceValues<dim>&)>& visit) const {
  int found = 0;
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    for (const auto& face : cell->face_iterators()) {
      if (!face->at_boundary() || face->boundary_id() != id) continue;
      const Vec2 v0 = face->vertex(0) - centre, v1 = face->vertex(1) - centre;
      const double a0 = std::atan2(v0[1], v0[0]);
      const double da = wrap_angle(std::atan2(v1[1], v1[0]) - a0);
      const double t = wrap_angle(angle - a0) / da;
      if (!(t >= -1e-10 && t <= 1 + 1e-10)) continue;
      const double tc = std::clamp(t, 0.0, 1.0);
      for (const double tt : {tc, 1.0 - tc}) {
        const Quadrature<dim - 1> q{Point<dim - 1>(tt)};
        FEFaceValues<dim> ffv(mapping_, fe_, q, flags | update_quadrature_points);
        ffv.reinit(cell, face);
        const Vec2 x = ffv.quadrature_point(0) - centre;
        if (std::abs(wrap_angle(std::atan2(x[1], x[0]) - angle)) > 0.25 * std::abs(da)) continue;
        visit(ffv);
        ++found;
        break;
      }
    }
  }
  if (Utilities::MPI::sum(found, comm_) == 0)
    throw std::runtime_error(std::string(who) + ": no boundary face at the requested angle");
  return found;  // on this rank; the callers sum over the ranks
}

PointState FlowProblem::boundary_state(types::boundary_id id, const Point2& centre, double angle,
                                       Vec2& normal_out_of_medium, Point2& where) const {
  // The stress is discontinuous across cells: a point on a vertex is shared by two faces, and
  // their states are averaged so that mirror-symmetric angles see mirror-symmetric values.
  const VectorType state = ghosted(solution_);
  const UpdateFlags flags =
      update_values | update_gradients | update_quadrature_points | update_normal_vectors;
  // the sums: stress (3), velocity (2), normal (2), point (2), p, eta, I, count
  std::vector<double> sums(13, 0.0);
  std::vector<SymmetricTensor<2, dim>> sym(1);
  std::vector<double> p(1);
  std::vector<Vec2> u(1);
  visit_boundary_at_angle(id, centre, angle, flags, "boundary_state",
                          [&](const FEFaceValues<dim>& ffv) {
                            ffv[kVelocity].get_function_symmetric_gradients(state, sym);
                            ffv[kPressure].get_function_values(state, p);
                            ffv[kVelocity].get_function_values(state, u);
                            const PointState st = make_state(sym[0], p[0], u[0], ffv, 0);
                            const double v[13] = {st.stress[0][0],
                                                  st.stress[0][1],
                                                  st.stress[1][1],
                                                  u[0][0],
                                                  u[0][1],
                                                  ffv.normal_vector(0)[0],
                                                  ffv.normal_vector(0)[1],
                                                  ffv.quadrature_point(0)[0],
                                                  ffv.quadrature_point(0)[1],
                                                  p[0],
                                                  st.viscosity,
                                                  st.inertial_number,
                                                  1.0};
                            for (unsigned int k = 0; k < 13; ++k) sums[k] += v[k];
                          });
  sums = sum_over_ranks(sums, comm_);
  const double found = sums[12];
  const Vec2 n_sum({sums[5], sums[6]});
  normal_out_of_medium = n_sum / n_sum.norm();
  where = Point2(sums[7] / found, sums[8] / found);
  PointState st;
  st.velocity = Vec2({sums[3] / found, sums[4] / found});
  st.pressure = sums[9] / found;
  st.viscosity = sums[10] / found;
  st.inertial_number = sums[11] / found;
  st.stress[0][0] = sums[0] / found;
  st.stress[0][1] = sums[1] / found;
  st.stress[1][1] = sums[2] / found;
  return st;
}

Vec2 FlowProblem::consistent_traction(types::boundary_id id, const Point2& centre,
                                      double angle) const {
  if (traction_id_ != static_cast<int>(id)) {
    // the nodal reactions of all ranks (O(sqrt(N)) of them), in the order of the dofs
    std::map<types::global_dof_index, double> reaction_all;
    {
      const auto mine = boundary_reaction(id);
      std::vector<types::global_dof_index> keys;
      std::vector<double> values;
      for (const auto& [g, v] : mine) {
        keys.push_back(g);
        values.push_back(v);
      }
      const auto all_keys = Utilities::MPI::all_gather(comm_, keys);
      const auto all_values = Utilities::MPI::all_gather(comm_, values);
      for (std::size_t r = 0; r < all_keys.size(); ++r)
        for (std::size_t k = 0; k < all_keys[r].size(); ++k)
          reaction_all.emplace(all_keys[r][k], all_values[r][k]);
    }
    std::map<types::global_dof_index, unsigned int> local;
    for (const auto& [g, v] : reaction_all)
      local.emplace(g, static_cast<unsigned int>(local.size()));
    const unsigned int nb = static_cast<unsigned int>(local.size());
    // boundary mass matrix (vector-valued, so the two components decouple): the entries of
    // this rank's faces, then of all ranks, assembled and solved on every rank (it is small)
    std::vector<types::global_dof_index> rows, cols;
    std::vector<double> entries;
    {
      const QGauss<dim - 1> fquad(4);
      FEFaceValues<dim> ffv(mapping_, fe_, fquad, update_values | update_JxW_values);
      const unsigned int dpc = fe_.n_dofs_per_cell();
      std::vector<types::global_dof_index> idx(dpc);
      for (const auto& cell : dof_handler_.active_cell_iterators()) {
        if (!cell->is_locally_owned()) continue;
        for (const auto& face : cell->face_iterators()) {
          if (!face->at_boundary() || face->boundary_id() != id) continue;
          ffv.reinit(cell, face);
          cell->get_dof_indices(idx);
          for (unsigned int q = 0; q < fquad.size(); ++q)
            for (unsigned int i = 0; i < dpc; ++i) {
              if (!local.count(idx[i])) continue;
              for (unsigned int j = 0; j < dpc; ++j) {
                if (!local.count(idx[j])) continue;
                rows.push_back(idx[i]);
                cols.push_back(idx[j]);
                entries.push_back(ffv[kVelocity].value(i, q) * ffv[kVelocity].value(j, q) *
                                  ffv.JxW(q));
              }
            }
        }
      }
    }
    const auto all_rows = Utilities::MPI::all_gather(comm_, rows);
    const auto all_cols = Utilities::MPI::all_gather(comm_, cols);
    const auto all_entries = Utilities::MPI::all_gather(comm_, entries);
    DynamicSparsityPattern dsp(nb);
    for (std::size_t r = 0; r < all_rows.size(); ++r)
      for (std::size_t k = 0; k < all_rows[r].size(); ++k)
        dsp.add(local.at(all_rows[r][k]), local.at(all_cols[r][k]));
    SparsityPattern sp;
    sp.copy_from(dsp);
    SparseMatrix<double> mass(sp);
    for (std::size_t r = 0; r < all_rows.size(); ++r)
      for (std::size_t k = 0; k < all_rows[r].size(); ++k)
        mass.add(local.at(all_rows[r][k]), local.at(all_cols[r][k]), all_entries[r][k]);
    Vector<double> rhs(nb);
    for (const auto& [g, l] : local)
      rhs(l) = reaction_all.at(g);  // force of the medium on the body
    SparseDirectUMFPACK direct;
    direct.initialize(mass);
    direct.solve(rhs);
    traction_.clear();
    for (const auto& [g, l] : local) traction_.emplace(g, rhs(l));
    traction_id_ = static_cast<int>(id);
  }
  // evaluate t_h on the face(s) at the requested angle
  std::vector<double> sums(3, 0.0);  // t_x, t_y, count
  const unsigned int dpc = fe_.n_dofs_per_cell();
  std::vector<types::global_dof_index> idx(dpc);
  visit_boundary_at_angle(
      id, centre, angle, update_values, "consistent_traction", [&](const FEFaceValues<dim>& ffv) {
        const DoFHandler<dim>::active_cell_iterator cell(&tria_, ffv.get_cell()->level(),
                                                         ffv.get_cell()->index(), &dof_handler_);
        cell->get_dof_indices(idx);
        Vec2 t;
        for (unsigned int i = 0; i < dpc; ++i) {
          const auto it = traction_.find(idx[i]);
          if (it != traction_.end()) t += it->second * ffv[kVelocity].value(i, 0);
        }
        sums[0] += t[0];
        sums[1] += t[1];
        sums[2] += 1;
      });
  sums = sum_over_ranks(sums, comm_);
  return Vec2({sums[0] / sums[2], sums[1] / sums[2]});
}
}  // namespace grainlift::continuum::internal
