// FlowProblem's set-up: degrees of freedom (numbering, blocks), constraints (hanging nodes,
// periodicity, no normal flux, Dirichlet values), sparsity patterns and matrices, and the
// initial guess.
#include <deal.II/base/function.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/dofs/dof_renumbering.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/lac/block_sparsity_pattern.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>
#include <deal.II/numerics/vector_tools.h>

#include <cmath>
#include <map>
#include <stdexcept>
#include <vector>

#include "flow_problem.h"
#include "quadrature_rheology.h"

namespace grainlift::continuum::internal {

using namespace dealii;

namespace {
/// (u, p) as a deal.II Function with 3 components.
class VelocityPressure : public Function<dim> {
 public:
  VelocityPressure(VectorField u, ScalarField p)
      : Function<dim>(dim + 1), u_(std::move(u)), p_(std::move(p)) {}
  double value(const Point<dim>& x, const unsigned int c) const override {
    if (c < dim) return u_ ? u_(x)[c] : 0.0;
    return p_ ? p_(x) : 0.0;
  }
  void vector_value(const Point<dim>& x, Vector<double>& v) const override {
    const Vec2 u = u_ ? u_(x) : Vec2();
    v(0) = u[0]; v(1) = u[1];
    v(2) = p_ ? p_(x) : 0.0;
  }

 private:
  VectorField u_;
  ScalarField p_;
};

}  // namespace

void FlowProblem::make_constraints(AffineConstraints<double>& c, bool homogeneous) const {
  c.clear();
  c.reinit(DoFTools::extract_locally_relevant_dofs(dof_handler_));
  DoFTools::make_hanging_node_constraints(dof_handler_, c);
  for (const auto& [b1, b2] : setup_.bc.periodic_x)
    DoFTools::make_periodicity_constraints(dof_handler_, b1, b2, 0, c);
  if (setup_.bc.friction)
    VectorTools::compute_no_normal_flux_constraints(dof_handler_, 0, {setup_.bc.friction->id}, c,
                                                    mapping_);
  for (const auto& [id, f] : setup_.bc.dirichlet) {
    if (homogeneous)
      VectorTools::interpolate_boundary_values(mapping_, dof_handler_, id,
                                               Functions::ZeroFunction<dim>(dim + 1), c,
                                               fe_.component_mask(kVelocity));
    else
      VectorTools::interpolate_boundary_values(mapping_, dof_handler_, id,
                                               VelocityPressure(f, {}), c,
                                               fe_.component_mask(kVelocity));
  }
  if (setup_.bc.mean_pressure) add_mean_pressure_constraint(c, homogeneous);
  if (setup_.bc.pin_pressure) {
    const types::global_dof_index first_p = n_u_;  // the first pressure dof
    if (c.can_store_line(first_p) && !c.is_constrained(first_p)) {
      c.add_line(first_p);
      c.set_inhomogeneity(first_p, 0.0);
    }
  }
  c.close();
}

// The mean pressure on a boundary, sum_j w_j p_j = value * sum_j w_j with w_j the integral of
// the pressure shape function j over the boundary, as one line of the constraints: the
// pressure dof m of the largest weight is p_m = value * sum_j w_j / w_m - sum_{j != m} w_j /
// w_m p_j. Weights of dofs that are themselves constrained (periodic ends, hanging nodes) go
// to the dofs they are constrained to. The continuity equation of p_m's test function, which
// the constraint replaces, is the one the others leave free (the net flux through a box with
// no outflow is zero): the system stays square and regular. Distributed: each rank weighs the
// faces of its own cells (their dofs' constraints are among its relevant ones), the weights
// are gathered on every rank and summed in rank order (every rank gets the same line), and
// the ranks to which p_m is relevant store it; the rows the line adds to (every dof of the
// boundary) are then writable there (mean_pressure_rows_, setup_system()).
void FlowProblem::add_mean_pressure_constraint(AffineConstraints<double>& c,
                                               bool homogeneous) const {
  const MeanPressure& mp = *setup_.bc.mean_pressure;
  const QGauss<dim - 1> quadrature(fe_.degree + 1);
  FEFaceValues<dim> fv(mapping_, fe_, quadrature, update_values | update_JxW_values);
  std::vector<types::global_dof_index> dofs(fe_.n_dofs_per_cell());
  std::map<types::global_dof_index, double> own;
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    for (const unsigned int f : cell->face_indices()) {
      if (!cell->face(f)->at_boundary() || cell->face(f)->boundary_id() != mp.id) continue;
      fv.reinit(cell, f);
      cell->get_dof_indices(dofs);
      for (unsigned int i = 0; i < dofs.size(); ++i) {
        if (fe_.system_to_component_index(i).first != dim) continue;
        double s = 0;
        for (unsigned int q = 0; q < quadrature.size(); ++q)
          s += fv.shape_value_component(i, q, dim) * fv.JxW(q);
        if (s != 0) own[dofs[i]] += s;
      }
    }
  }
  for (int pass = 0; pass < 8; ++pass) {  // chains: a periodic end that hangs, ...
    std::map<types::global_dof_index, double> resolved;
    bool moved = false;
    for (const auto& [j, wj] : own) {
      if (!c.is_constrained(j)) {
        resolved[j] += wj;
        continue;
      }
      moved = true;
      for (const auto& [k, a] : *c.get_constraint_entries(j)) resolved[k] += wj * a;
    }
    own.swap(resolved);
    if (!moved) break;
  }
  std::map<types::global_dof_index, double> w;
  const auto gathered = Utilities::MPI::all_gather(
      comm_, std::vector<std::pair<types::global_dof_index, double>>(own.begin(), own.end()));
  for (const auto& part : gathered)
    for (const auto& [j, wj] : part) w[j] += wj;
  types::global_dof_index m = 0;
  double wm = 0, total = 0;
  for (const auto& [j, wj] : w) {
    total += wj;
    if (std::abs(wj) > std::abs(wm)) {
      m = j;
      wm = wj;
    }
  }
  if (!(wm != 0)) throw std::logic_error("mean pressure: the boundary has no pressure dofs");
  mean_pressure_rows_ = IndexSet(dof_handler_.n_dofs());
  for (const auto& [j, wj] : w) mean_pressure_rows_.add_index(j);
  mean_pressure_rows_.compress();
  if (!c.can_store_line(m)) return;
  c.add_line(m);
  for (const auto& [j, wj] : w)
    if (j != m) c.add_entry(m, j, -wj / wm);
  c.set_inhomogeneity(m, homogeneous ? 0.0 : mp.value * total / wm);
}

void FlowProblem::setup_system() {
  // manifold evaluations (transfinite interpolation) are costly: compute the Q2 mapping once
  mapping_.initialize(MappingQ<dim>(2), tria_);
  dof_handler_.distribute_dofs(fe_);
  const bool iterative = setup_.linear_solver == LinearSolver::amg;
  // two blocks, velocity then pressure; inside the velocity block the two components of a
  // node stay next to each other (the cell-wise numbering), which suits ML's aggregation (the
  // direct solver orders the unknowns itself)
  DoFRenumbering::component_wise(dof_handler_, std::vector<unsigned int>{0, 0, 1});
  const auto counts = DoFTools::count_dofs_per_fe_component(dof_handler_);
  n_u_ = counts[0] + counts[1];
  const types::global_dof_index n = dof_handler_.n_dofs();
  const IndexSet owned = dof_handler_.locally_owned_dofs();
  const IndexSet relevant = DoFTools::extract_locally_relevant_dofs(dof_handler_);
  owned_ = {owned.get_view(0, n_u_), owned.get_view(n_u_, n)};
  relevant_ = {relevant.get_view(0, n_u_), relevant.get_view(n_u_, n)};
  mean_pressure_rows_ = IndexSet(n);
  make_constraints(nonzero_constraints_, false);
  make_constraints(zero_constraints_, true);
  // rows this rank writes: its relevant ones, and the mean-pressure line's (its condensation
  // adds to every dof of that boundary)
  IndexSet writable = relevant;
  writable.add_indices(mean_pressure_rows_);
  const std::vector<IndexSet> writable_blocks = {writable.get_view(0, n_u_),
                                                 writable.get_view(n_u_, n)};
  TrilinosWrappers::BlockSparsityPattern sp(owned_, owned_, writable_blocks, comm_);
  DoFTools::make_sparsity_pattern(dof_handler_, sp, zero_constraints_, false);
  sp.compress();
  system_matrix_.reinit(sp);
  if (!iterative) {
    // MUMPS (through Amesos) takes one matrix: the blocks are copied into it for each solve
    TrilinosWrappers::SparsityPattern full(owned, owned, writable, comm_);
    DoFTools::make_sparsity_pattern(dof_handler_, full, zero_constraints_, false);
    full.compress();
    direct_.reset();  // MUMPS holds the old matrix: a new pattern is analysed again
    direct_matrix_.reinit(full);
  } else {
    if (setup_.schur_approximation == SchurApproximation::viscosity_mass) schur_mass_.reinit(sp);
    DoFTools::extract_constant_modes(dof_handler_, fe_.component_mask(kVelocity),
                                     velocity_constant_modes_);
  }
  solution_.reinit(owned_, comm_);
  cache_.reset();
  traction_id_ = -1;
}

void FlowProblem::interpolate_initial_guess() {
  VectorTools::interpolate(mapping_, dof_handler_,
                           VelocityPressure(setup_.initial_velocity, setup_.initial_pressure),
                           solution_);
  nonzero_constraints_.distribute(solution_);
}
}  // namespace grainlift::continuum::internal
