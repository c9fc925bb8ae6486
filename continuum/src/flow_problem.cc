// Finite-element engine of the continuum solver: steady incompressible generalised-Newtonian
// flow (Stokes, optional rho (u.grad)u) with Taylor-Hood Q2-Q1 elements on an isoparametric
// (MappingQ2) mesh. The weak form, with n the outward normal of the medium:
//   R_v = int 2 eta D(u):D(v) - p div v + rho ((grad u) u).v - f.v  - int_{Gamma_N} t.v
//         + int_{Gamma_wall} mu_w p+ g(s) (t_w.v),        g(s) = s / sqrt(s^2 + eps^2)
//   R_q = - int q div u
// Newton's Jacobian differentiates eta(|D|^2, p) in both arguments (see assemble_impl).
#include "flow_problem.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_renumbering.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/precondition.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/solver_gmres.h>
#include <deal.II/lac/sparse_direct.h>
#include <deal.II/lac/trilinos_index_access.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_solver.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/vector_tools.h>

#include <Epetra_Vector.h>
#include <mpi.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace grainlift::continuum::internal {

using namespace dealii;

namespace {
/// Largest growth of the plain residual |R| that a Newton step may cause (see solve_nonlinear).
constexpr double kResidualGrowth = 1.5;

/// (u, p) as a deal.II Function with 3 components.
class VelocityPressure : public Function<dim> {
 public:
  VelocityPressure(VectorField u, ScalarField p) : Function<dim>(dim + 1), u_(std::move(u)), p_(std::move(p)) {}
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

double wrap_angle(double a) {
  while (a > M_PI) a -= 2 * M_PI;
  while (a <= -M_PI) a += 2 * M_PI;
  return a;
}

const FEValuesExtractors::Vector kVelocity(0);
const FEValuesExtractors::Scalar kPressure(dim);

/// D(u), p and the viscosity model's outputs at the quadrature points of one cell (the
/// rheology as the assembly, the post-processing and the output see it).
struct QuadratureRheology {
  std::vector<SymmetricTensor<2, dim>> sym;  ///< D(u)
  std::vector<double> pressure;
  RheologyInputs in;
  RheologyOutputs out;
  explicit QuadratureRheology(unsigned int nq) : sym(nq), pressure(nq) {
    in.resize(nq);
    out.resize(nq);
  }
  /// At the points of @p fev (reinitialised on a cell) for the ghosted @p state.
  void evaluate(const FEValues<dim>& fev, const VectorType& state, const ViscosityModel& model) {
    fev[kVelocity].get_function_symmetric_gradients(state, sym);
    fev[kPressure].get_function_values(state, pressure);
    for (unsigned int q = 0; q < sym.size(); ++q) {
      in.strain_rate_sq[q] = 0.5 * (sym[q] * sym[q]);  // |D|^2 = D:D/2
      in.pressure[q] = pressure[q];
    }
    model.evaluate(in, out);
  }
};

/// Trilinos objects need MPI even on one process. When the program has not initialised MPI
/// (the tests, a serial run), do it here once and finalise at exit.
int ensure_mpi() {
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (initialised) return 0;
  MPI_Init(nullptr, nullptr);
  std::atexit([] {
    int finalised = 0;
    MPI_Finalized(&finalised);
    if (finalised) return;
    // (the solvers' pools of Trilinos vectors are statics made after this handler was
    // registered: they are destroyed before it runs, while MPI is still up)
    MPI_Finalize();
  });
  return 0;
}

/// The diagonal of a square Trilinos matrix (locally owned rows) into @p d.
void extract_diagonal(const TrilinosWrappers::SparseMatrix& m, TrilinosWrappers::MPI::Vector& d) {
  Epetra_Vector view(View, d.trilinos_vector(), 0);
  const int ierr = m.trilinos_matrix().ExtractDiagonalCopy(view);
  AssertThrow(ierr == 0, ExcMessage("continuum: cannot extract the matrix diagonal"));
}

/// Element-wise sum over the ranks.
std::vector<double> sum_over_ranks(std::vector<double> v, MPI_Comm comm) {
  MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), MPI_DOUBLE, MPI_SUM, comm);
  return v;
}

/// Sum over the locally owned entries of f(v_i, w_i), then over the ranks.
template <typename F>
double owned_sum(const VectorType& v, const VectorType& w, F f, MPI_Comm comm) {
  double sum = 0;
  for (unsigned int b = 0; b < v.n_blocks(); ++b) {
    auto wi = w.block(b).begin();
    for (auto vi = v.block(b).begin(); vi != v.block(b).end(); ++vi, ++wi) sum += f(*vi, *wi);
  }
  return Utilities::MPI::sum(sum, comm);
}

/// Block upper-triangular preconditioner of K = [A B^T; B 0]:
///   P = [A B^T; 0 -S],  P^{-1} (x_u, x_p):  y_p = -S^{-1} x_p,  y_u = A^{-1} (x_u - B^T y_p)
/// A^{-1}: one AMG V-cycle on the velocity block. S^{-1}: one AMG V-cycle on B diag(A)^{-1} B^T
/// (SchurApproximation::diagonal_a), or the inverse of the lumped 1/eta-weighted pressure mass
/// matrix (viscosity_mass). B^T y_p is the (u,p) block of K itself (in Newton's Jacobian it
/// also holds the d eta / dp term, so it is not the transpose of the (p,u) block).
class BlockTriangularPreconditioner {
 public:
  /// @p schur_diagonal: the diagonal of the Schur approximation (used for the scaling, and as
  /// S itself when @p schur_amg is null).
  BlockTriangularPreconditioner(const MatrixType& K, const TrilinosWrappers::PreconditionAMG& a_amg,
                                const TrilinosWrappers::PreconditionAMG* schur_amg,
                                const TrilinosWrappers::MPI::Vector& schur_diagonal)
      : K_(K), a_amg_(a_amg), schur_amg_(schur_amg), schur_diagonal_(schur_diagonal),
        xu_(K.block(0, 0).locally_owned_range_indices(), schur_diagonal.get_mpi_communicator()) {}

  void vmult(VectorType& dst, const VectorType& src) const {
    if (schur_amg_) {
      schur_amg_->vmult(dst.block(1), src.block(1));
    } else {
      auto s = schur_diagonal_.begin();
      auto y = dst.block(1).begin();
      for (auto x = src.block(1).begin(); x != src.block(1).end(); ++x, ++y, ++s) *y = *x / *s;
    }
    dst.block(1) *= -1.0;
    K_.block(0, 1).vmult(xu_, dst.block(1));  // B^T y_p
    xu_.sadd(-1.0, 1.0, src.block(0));        // x_u - B^T y_p
    a_amg_.vmult(dst.block(0), xu_);
  }

 private:
  const MatrixType& K_;
  const TrilinosWrappers::PreconditionAMG& a_amg_;
  const TrilinosWrappers::PreconditionAMG* schur_amg_;
  const TrilinosWrappers::MPI::Vector& schur_diagonal_;
  mutable TrilinosWrappers::MPI::Vector xu_;
};

/// E X E for an operator X (vmult) and a diagonal E (the vector @p e): with E = D the scaled
/// system D K D, with E = D^{-1} its preconditioner D^{-1} P^{-1} D^{-1}.
template <class Operator>
class DiagonallyScaled {
 public:
  DiagonallyScaled(const Operator& X, const VectorType& e) : X_(X), e_(e), t_(e) {}
  void vmult(VectorType& dst, const VectorType& src) const {
    t_ = src;
    t_.scale(e_);
    X_.vmult(dst, t_);
    dst.scale(e_);
  }

 private:
  const Operator& X_;
  const VectorType& e_;
  mutable VectorType t_;
};

/// Calls f(row, column, value) for the stored entries of the locally owned rows of @p m
/// (Epetra's row views: deal.II's iterators over a Trilinos matrix cost O(columns) per row).
template <typename F>
void for_each_entry(const TrilinosWrappers::SparseMatrix& m, F f) {
  const Epetra_CrsMatrix& e = m.trilinos_matrix();
  for (int r = 0; r < e.NumMyRows(); ++r) {
    int n = 0;
    double* values = nullptr;
    int* columns = nullptr;
    e.ExtractMyRowView(r, n, values, columns);
    const types::global_dof_index i = TrilinosWrappers::global_row_index(e, r);
    for (int k = 0; k < n; ++k) f(i, TrilinosWrappers::global_index(e.ColMap(), columns[k]), values[k]);
  }
}

/// @p m with a diagonal entry @p value added in the locally owned rows that have none (a
/// pinned pressure dof has no (p,u) coupling, so its row of B diag(A)^{-1} B^T is empty).
void add_missing_diagonal(TrilinosWrappers::SparseMatrix& m, double value) {
  const IndexSet rows = m.locally_owned_range_indices();
  TrilinosWrappers::SparsityPattern sp(rows, rows, m.get_mpi_communicator());
  std::vector<std::pair<types::global_dof_index, std::pair<types::global_dof_index, double>>> entries;
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

}  // namespace

FlowProblem::FlowProblem(Triangulation<dim>& tria, const ProblemSetup& setup)
    : mpi_ready_(ensure_mpi()), tria_(tria), comm_(tria.get_communicator()), setup_(setup),
      fe_(FE_Q<dim>(2), dim, FE_Q<dim>(1), 1), mapping_(2), dof_handler_(tria) {}

unsigned int FlowProblem::n_ranks() const { return Utilities::MPI::n_mpi_processes(comm_); }

VectorType FlowProblem::make_vector() const { return VectorType(owned_, comm_); }

VectorType FlowProblem::ghosted(const VectorType& v) const {
  VectorType g(owned_, relevant_, comm_);
  g = v;
  return g;
}

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
  if (setup_.bc.pin_pressure) {
    const types::global_dof_index first_p = n_u_;  // the first pressure dof
    if (c.can_store_line(first_p) && !c.is_constrained(first_p)) {
      c.add_line(first_p);
      c.set_inhomogeneity(first_p, 0.0);
    }
  }
  c.close();
}

void FlowProblem::setup_system() {
  // manifold evaluations (transfinite interpolation) are costly: compute the Q2 mapping once
  mapping_.initialize(MappingQ<dim>(2), tria_);
  dof_handler_.distribute_dofs(fe_);
  const bool iterative = setup_.linear_solver == LinearSolver::amg;
  const bool distributed_direct = !iterative && n_ranks() > 1;
  if (iterative || distributed_direct) {
    // two blocks, velocity then pressure; inside the velocity block the two components of a
    // node stay next to each other (the cell-wise numbering), which suits ML's aggregation
    DoFRenumbering::component_wise(dof_handler_, std::vector<unsigned int>{0, 0, 1});
  } else {
    DoFRenumbering::Cuthill_McKee(dof_handler_);
    DoFRenumbering::component_wise(dof_handler_);  // u_x, then u_y, then p
  }
  const auto counts = DoFTools::count_dofs_per_fe_component(dof_handler_);
  n_u_ = counts[0] + counts[1];
  const types::global_dof_index n = dof_handler_.n_dofs();
  const IndexSet owned = dof_handler_.locally_owned_dofs();
  const IndexSet relevant = DoFTools::extract_locally_relevant_dofs(dof_handler_);
  owned_ = {owned.get_view(0, n_u_), owned.get_view(n_u_, n)};
  relevant_ = {relevant.get_view(0, n_u_), relevant.get_view(n_u_, n)};
  make_constraints(nonzero_constraints_, false);
  make_constraints(zero_constraints_, true);
  TrilinosWrappers::BlockSparsityPattern sp(owned_, owned_, relevant_, comm_);
  DoFTools::make_sparsity_pattern(dof_handler_, sp, zero_constraints_, false);
  sp.compress();
  system_matrix_.reinit(sp);
  if (distributed_direct) {
    // MUMPS (through Amesos) takes one matrix: the blocks are copied into it for each solve
    TrilinosWrappers::SparsityPattern full(owned, owned, relevant, comm_);
    DoFTools::make_sparsity_pattern(dof_handler_, full, zero_constraints_, false);
    full.compress();
    direct_distributed_.reinit(full);
  } else if (!iterative) {
    DynamicSparsityPattern dsp(n);
    DoFTools::make_sparsity_pattern(dof_handler_, dsp, zero_constraints_, false);
    direct_sparsity_.copy_from(dsp);
    direct_matrix_.reinit(direct_sparsity_);
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

double FlowProblem::assemble_system(const VectorType& state, bool matrix, bool newton,
                                    VectorType& residual) {
  const bool schur = matrix && setup_.linear_solver == LinearSolver::amg &&
                     setup_.schur_approximation == SchurApproximation::viscosity_mass;
  return assemble_impl(ghosted(state), matrix ? &system_matrix_ : nullptr, newton, residual, false,
                       schur ? &schur_mass_ : nullptr);
}

double FlowProblem::assemble_impl(const VectorType& state, MatrixType* matrix, bool newton,
                                  VectorType& residual, bool reaction_mode,
                                  MatrixType* schur_mass) const {
  residual.reinit(owned_, comm_);
  if (matrix) *matrix = 0;
  if (schur_mass) *schur_mass = 0;
  FullMatrix<double> cmass(schur_mass ? fe_.n_dofs_per_cell() : 0,
                           schur_mass ? fe_.n_dofs_per_cell() : 0);
  const QGauss<dim> quad(3);
  const QGauss<dim - 1> fquad(3);
  FEValues<dim> fev(mapping_, fe_, quad,
                    update_values | update_gradients | update_quadrature_points | update_JxW_values);
  FEFaceValues<dim> ffv(mapping_, fe_, fquad,
                        update_values | update_quadrature_points | update_normal_vectors |
                            update_JxW_values);
  const unsigned int dpc = fe_.n_dofs_per_cell(), nq = quad.size(), nfq = fquad.size();
  FullMatrix<double> cm(dpc, dpc);
  Vector<double> cr(dpc);
  std::vector<types::global_dof_index> idx(dpc);
  QuadratureRheology qr(nq);
  const std::vector<SymmetricTensor<2, dim>>& sym = qr.sym;
  const std::vector<double>& pval = qr.pressure;
  const RheologyOutputs& out = qr.out;
  std::vector<Tensor<2, dim>> grad(nq);
  std::vector<Vec2> uval(nq), fu(nfq);
  std::vector<double> fp(nfq);
  std::vector<SymmetricTensor<2, dim>> phi_sym(dpc);
  std::vector<Tensor<2, dim>> phi_grad(dpc);
  std::vector<Vec2> phi_u(dpc);
  std::vector<double> phi_div(dpc), phi_p(dpc);
  const double rho = setup_.inertia_density;
  const bool inertia = rho > 0;

  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    fev.reinit(cell);
    cm = 0;
    cr = 0;
    if (schur_mass) cmass = 0;
    qr.evaluate(fev, state, *setup_.viscosity);
    if (inertia) {
      fev[kVelocity].get_function_gradients(state, grad);
      fev[kVelocity].get_function_values(state, uval);
    }

    for (unsigned int q = 0; q < nq; ++q) {
      const double JxW = fev.JxW(q);
      const double eta = out.viscosity[q];
      const double eta_s = newton ? out.deta_dstrain_sq[q] : 0.0;
      const double eta_p = newton ? out.deta_dpressure[q] : 0.0;
      const Vec2 f = setup_.body_force ? setup_.body_force(fev.quadrature_point(q)) : Vec2();
      const SymmetricTensor<2, dim>& D = sym[q];
      const double div_u = trace(D);
      const Vec2 conv = inertia ? Vec2(grad[q] * uval[q]) : Vec2();
      for (unsigned int k = 0; k < dpc; ++k) {
        phi_sym[k] = fev[kVelocity].symmetric_gradient(k, q);
        phi_div[k] = fev[kVelocity].divergence(k, q);
        phi_u[k] = fev[kVelocity].value(k, q);
        phi_p[k] = fev[kPressure].value(k, q);
        if (inertia && matrix) phi_grad[k] = fev[kVelocity].gradient(k, q);
      }
      for (unsigned int i = 0; i < dpc; ++i) {
        const double D_Di = D * phi_sym[i];
        cr(i) += (2 * eta * D_Di - pval[q] * phi_div[i] - phi_p[i] * div_u +
                  rho * (conv * phi_u[i]) - f * phi_u[i]) * JxW;
        if (!matrix) continue;
        for (unsigned int j = 0; j < dpc; ++j) {
          // d/dx_j of 2 eta D:D_i = 2 eta D_j:D_i + 2 (eta_s D:D_j + eta_p phi_p_j) D:D_i
          double a = 2 * eta * (phi_sym[j] * phi_sym[i]) - phi_p[j] * phi_div[i] -
                     phi_p[i] * phi_div[j];
          a += 2 * (eta_s * (D * phi_sym[j]) + eta_p * phi_p[j]) * D_Di;
          if (inertia) {
            a += rho * ((phi_grad[j] * uval[q]) * phi_u[i]);               // Oseen part
            if (newton) a += rho * ((grad[q] * phi_u[j]) * phi_u[i]);      // Newton part
          }
          cm(i, j) += a * JxW;
        }
        if (schur_mass)  // (1/eta) p_i p_j: the Schur complement B A^{-1} B^T is ~ M_p / eta
          for (unsigned int j = 0; j < dpc; ++j) cmass(i, j) += phi_p[i] * phi_p[j] / eta * JxW;
      }
    }

    if (!reaction_mode)
      for (const auto& face : cell->face_iterators()) {
        if (!face->at_boundary()) continue;
        const auto id = face->boundary_id();
        const auto tr = setup_.bc.traction.find(id);
        const bool is_friction = setup_.bc.friction && setup_.bc.friction->id == id;
        if (tr == setup_.bc.traction.end() && !is_friction) continue;
        ffv.reinit(cell, face);
        if (tr != setup_.bc.traction.end()) {
          for (unsigned int q = 0; q < nfq; ++q) {
            const Vec2 t = tr->second(ffv.quadrature_point(q), ffv.normal_vector(q));
            for (unsigned int i = 0; i < dpc; ++i)
              cr(i) -= t * ffv[kVelocity].value(i, q) * ffv.JxW(q);
          }
        }
        if (is_friction) {
          const FrictionWall& w = *setup_.bc.friction;
          ffv[kVelocity].get_function_values(state, fu);
          ffv[kPressure].get_function_values(state, fp);
          const double eps = w.slip_scale;
          for (unsigned int q = 0; q < nfq; ++q) {
            const Vec2 n = ffv.normal_vector(q);
            const Vec2 tw({-n[1], n[0]});
            const Vec2 uw = w.wall_velocity ? w.wall_velocity(ffv.quadrature_point(q)) : Vec2();
            const double s = (fu[q] - uw) * tw;
            const double pp = std::max(fp[q], 0.0);
            const double r = std::sqrt(s * s + eps * eps);
            const double g = s / r, dg = eps * eps / (r * r * r);
            for (unsigned int i = 0; i < dpc; ++i) {
              const double ti = tw * ffv[kVelocity].value(i, q);
              cr(i) += w.mu_w * pp * g * ti * ffv.JxW(q);
              if (!matrix) continue;
              for (unsigned int j = 0; j < dpc; ++j) {
                const double tj = tw * ffv[kVelocity].value(j, q);
                double a;
                if (newton)
                  a = pp * dg * tj + (fp[q] > 0 ? g * ffv[kPressure].value(j, q) : 0.0);
                else
                  a = pp / r * tj;  // Picard: secant slip coefficient
                cm(i, j) += w.mu_w * a * ti * ffv.JxW(q);
              }
            }
          }
        }
      }

    cell->get_dof_indices(idx);
    if (reaction_mode) {
      residual.add(idx, cr);  // entries of other ranks travel at compress()
    } else if (matrix) {
      zero_constraints_.distribute_local_to_global(cm, cr, idx, *matrix, residual);
      if (schur_mass) zero_constraints_.distribute_local_to_global(cmass, idx, *schur_mass);
    } else {
      zero_constraints_.distribute_local_to_global(cr, idx, residual);
    }
  }
  if (matrix) matrix->compress(VectorOperation::add);
  if (schur_mass) schur_mass->compress(VectorOperation::add);
  residual.compress(VectorOperation::add);
  return residual.l2_norm();
}

int FlowProblem::solve(const VectorType& residual, VectorType& update, double relative_tolerance) {
  int iterations = 0;
  update.reinit(owned_, comm_);
  if (setup_.linear_solver == LinearSolver::amg) {
    iterations = solve_iterative(residual, update, relative_tolerance);
    update *= -1.0;
  } else if (n_ranks() > 1) {
    // MUMPS on the blocks copied into one distributed matrix (global numbering: the blocks'
    // one after the other)
    const types::global_dof_index offset[2] = {0, n_u_};
    for (unsigned int bi = 0; bi < 2; ++bi)
      for (unsigned int bj = 0; bj < 2; ++bj)
        for_each_entry(system_matrix_.block(bi, bj), [&](types::global_dof_index i,
                                                         types::global_dof_index j, double v) {
          direct_distributed_.set(offset[bi] + i, offset[bj] + j, v);
        });
    direct_distributed_.compress(VectorOperation::insert);
    const IndexSet& owned = dof_handler_.locally_owned_dofs();
    TrilinosWrappers::MPI::Vector b(owned, comm_), x(owned, comm_);
    for (const auto i : owned) b(i) = residual(i);
    b.compress(VectorOperation::insert);
    SolverControl control(1, 0);
    TrilinosWrappers::SolverDirect direct(
        control, TrilinosWrappers::SolverDirect::AdditionalData(false, "Amesos_Mumps"));
    direct.solve(direct_distributed_, x, b);
    for (const auto i : owned) update(i) = -x(i);
    update.compress(VectorOperation::insert);
  } else {
    // one rank: UMFPACK on a deal.II copy of the matrix, whose global numbering is the
    // blocks' one after the other
    direct_matrix_ = 0;
    const types::global_dof_index offset[2] = {0, n_u_};
    for (unsigned int bi = 0; bi < 2; ++bi)
      for (unsigned int bj = 0; bj < 2; ++bj) {
        for_each_entry(system_matrix_.block(bi, bj), [&](types::global_dof_index i,
                                                         types::global_dof_index j, double v) {
          direct_matrix_.set(offset[bi] + i, offset[bj] + j, v);
        });
      }
    SparseDirectUMFPACK direct;
    direct.initialize(direct_matrix_);
    Vector<double> x(residual.size());
    auto xi = x.begin();  // one rank: the owned entries of the blocks are all of them, in order
    for (unsigned int b = 0; b < 2; ++b)
      for (const double v : residual.block(b)) *xi++ = v;
    direct.solve(x);
    x *= -1.0;
    xi = x.begin();
    for (unsigned int b = 0; b < 2; ++b)
      for (double& v : update.block(b)) v = *xi++;
  }
  zero_constraints_.distribute(update);
  ++report_.linear_solves;
  report_.krylov_iterations += iterations;
  return iterations;
}

int FlowProblem::solve_iterative(const VectorType& rhs, VectorType& x, double relative_tolerance) {
  const TrilinosWrappers::SparseMatrix& A = system_matrix_.block(0, 0);
  // AMG (Trilinos ML, smoothed aggregation) on the velocity block: the two velocity components
  // as the near-null space, Q2 elements. The block is symmetric without inertia (the Newton
  // term 2 eta_s (D:D_j)(D:D_i) is symmetric); "elliptic" (Chebyshev smoother) measured better
  // than the non-symmetric setting on the cylinder (76 against 103 FGMRES iterations per solve).
  TrilinosWrappers::PreconditionAMG a_amg;
  {
    TrilinosWrappers::PreconditionAMG::AdditionalData data;
    data.elliptic = true;
    data.higher_order_elements = true;
    data.smoother_sweeps = 2;
    data.aggregation_threshold = 0.02;
    data.constant_modes = velocity_constant_modes_;
    a_amg.initialize(A, data);
  }
  // Schur complement approximation
  TrilinosWrappers::MPI::Vector schur_diagonal(owned_[1], comm_);
  TrilinosWrappers::SparseMatrix schur_bdb;
  TrilinosWrappers::PreconditionAMG s_amg;
  const bool diagonal_a = setup_.schur_approximation == SchurApproximation::diagonal_a;
  if (diagonal_a) {
    // S = B diag(A)^{-1} B^T, a pressure Laplacian weighted by the actual velocity block:
    // unlike M_p / eta it sees the constraints and where eta jumps by decades between cells
    TrilinosWrappers::MPI::Vector inv_diag(owned_[0], comm_);
    extract_diagonal(A, inv_diag);
    for (auto& v : inv_diag) v = 1.0 / std::abs(v);
    system_matrix_.block(1, 0).mmult(schur_bdb, system_matrix_.block(0, 1), inv_diag);
    // rows without a (p,u) coupling (a pinned pressure): unit-scale diagonal
    extract_diagonal(schur_bdb, schur_diagonal);
    double dmax = 0;
    bool missing = false;
    for (const double v : schur_diagonal) {
      dmax = std::max(dmax, std::abs(v));
      missing = missing || !(std::abs(v) > 0);
    }
    dmax = Utilities::MPI::max(dmax, comm_);
    if (Utilities::MPI::logical_or(missing, comm_)) {
      add_missing_diagonal(schur_bdb, dmax);
      extract_diagonal(schur_bdb, schur_diagonal);
    }
    for (auto& v : schur_diagonal) v = std::abs(v);
    TrilinosWrappers::PreconditionAMG::AdditionalData data;
    data.elliptic = true;
    data.smoother_sweeps = 2;
    s_amg.initialize(schur_bdb, data);
  } else {
    TrilinosWrappers::MPI::Vector ones(owned_[1], comm_);
    ones = 1.0;
    schur_mass_.block(1, 1).vmult(schur_diagonal, ones);  // lumped: row sums, positive for Q1
  }
  const BlockTriangularPreconditioner prec(system_matrix_, a_amg, diagonal_a ? &s_amg : nullptr,
                                           schur_diagonal);
  // The momentum and continuity rows of K have different units and scales (forces against
  // h div u), and eta varies by decades: the Euclidean residual of K barely sees div u. FGMRES
  // therefore works on D K D y = D rhs, x = D y, D = diag(A_ii)^(-1/2) on the velocity and
  // diag(S_ii)^(-1/2) on the pressure (both blocks with unit diagonal, an energy-like norm);
  // the tolerance applies to |D r|.
  VectorType d = make_vector(), d_inverse = make_vector(), b = make_vector(), y = make_vector();
  extract_diagonal(A, d.block(0));
  d.block(1) = schur_diagonal;
  for (unsigned int blk = 0; blk < 2; ++blk) {
    auto di = d_inverse.block(blk).begin();
    for (auto& v : d.block(blk)) {
      const double a = std::abs(v);
      v = a > 0 && std::isfinite(a) ? 1.0 / std::sqrt(a) : 1.0;
      *di++ = 1.0 / v;
    }
  }
  b = rhs;
  b.scale(d);
  const DiagonallyScaled<MatrixType> scaled(system_matrix_, d);
  const DiagonallyScaled<BlockTriangularPreconditioner> scaled_prec(prec, d_inverse);
  const double b_norm = b.l2_norm();
  SolverControl control(1000, std::max(relative_tolerance * b_norm, 1e-300));
  SolverFGMRES<VectorType> fgmres(control, SolverFGMRES<VectorType>::AdditionalData(100));
  try {
    fgmres.solve(scaled, y, b, scaled_prec);
  } catch (const SolverControl::NoConvergence& e) {
    std::ostringstream os;
    os << "continuum: FGMRES did not reach " << relative_tolerance << " in " << e.last_step
       << " iterations (|D r|/|D b| = " << e.last_residual / std::max(b_norm, 1e-300)
       << "); the step is used as it is";
    log(os.str());
  }
  x = y;
  x.scale(d);
  return static_cast<int>(control.last_step());
}

void FlowProblem::run() {
  setup_system();
  interpolate_initial_guess();
  report_ = NonlinearReport{};
  solve_nonlinear(setup_.nonlinear);
}

void FlowProblem::solve_nonlinear(const NonlinearSettings& nl) {
  const auto n = dof_handler_.n_dofs();
  VectorType res = make_vector(), upd = make_vector(), trial = make_vector(),
             trial_res = make_vector(), weight = make_vector();
  double r = assemble_system(solution_, false, false, res);
  report_.converged = false;
  report_.message.clear();
  traction_id_ = -1;
  // the tolerance is relative to the residual of the initial guess of the first call
  if (report_.initial_residual <= 0) report_.initial_residual = r;
  const double r_ref = report_.initial_residual;
  const double r0 = r;
  const bool nonlinear =
      setup_.viscosity->is_nonlinear() || setup_.inertia_density > 0 || setup_.bc.friction;
  {
    std::ostringstream os;
    os << "continuum: " << tria_.n_global_active_cells() << " cells, " << n
       << " dofs, initial residual " << r0;
    if (n_ranks() > 1) os << " (" << n_ranks() << " MPI ranks)";
    log(os.str());
  }
  if (r0 <= nl.absolute_tolerance || r0 <= nl.relative_tolerance * r_ref) {
    report_.converged = true;
    report_.final_residual = r0;
    return;
  }
  // a linear problem takes one direct solve, or iterative solves until it meets the tolerance
  const bool iterative = setup_.linear_solver == LinearSolver::amg;
  const int max_it = nonlinear ? nl.max_iterations : (iterative ? 5 : 1);
  // Picard (eta frozen) for at least picard_iterations steps and until |R| < 0.5 |R0| (at most
  // 4 picard_iterations), then Newton with a backtracking line search (Armijo on the merit
  // below). A Newton step whose line search fails (no sufficient decrease down to a step of
  // 1/1024) is replaced by a Picard step. Convergence is always judged on the plain |R|.
  bool newton_phase = !nonlinear || nl.picard_iterations == 0;
  for (int it = 0; it < max_it; ++it) {
    if (!newton_phase && it >= nl.picard_iterations &&
        (r < 0.5 * r0 || it >= 4 * std::max(nl.picard_iterations, 1)))
      newton_phase = true;
    bool newton = newton_phase;
    double alpha = 1.0, rt = 0;
    int linear_its = 0;
    for (int attempt = 0; attempt < 2; ++attempt) {
      assemble_system(solution_, true, newton, res);
      // Line-search merit: without inertia the Jacobi-weighted norm sum_i R_i^2 / |J_ii| (the
      // stiff, nearly rigid zones where eta ~ eta_max otherwise dominate |R| and force tiny
      // steps; 46 -> 28 Newton steps on the spinning cylinder at refinement 2). With inertia
      // the convective diagonal makes the weights unreliable and the plain |R| did better.
      const bool scaled = setup_.inertia_density == 0;
      for (unsigned int b = 0; b < 2; ++b) {
        extract_diagonal(system_matrix_.block(b, b), weight.block(b));
        for (auto& w : weight.block(b)) {
          const double d = std::abs(w);
          w = d > 0 ? 1.0 / d : 1.0;
        }
      }
      const auto merit = [&](const VectorType& v) {
        if (!scaled) return v.l2_norm();
        return std::sqrt(owned_sum(v, weight, [](double x, double w) { return w * x * x; }, comm_));
      };
      const double m0 = merit(res);
      // inexact Newton: the linear residual only needs to be small against the nonlinear one;
      // forcing term 0.1 |R|/|R_0| (quadratic convergence is kept), at most 1e-3, at least 1e-10
      const double forcing =
          nonlinear ? std::clamp(0.1 * r / r_ref, 1e-10, 1e-3) : 1e-10;
      linear_its = solve(res, upd, forcing);
      alpha = 1.0;
      bool accepted = false;
      for (int ls = 0; ls <= 10; ++ls) {
        trial = solution_;
        trial.add(alpha, upd);
        rt = assemble_system(trial, false, false, trial_res);
        // Picard steps are fixed-point steps, not descent directions of |R|: taken in full.
        // The weighted merit can fall while |R| grows several-fold (seen at refinement 3: a
        // step taken at 1/8 raised |R| from 1.3 to 11 |R_0|, and the iteration never
        // recovered); a Newton step must also keep |R| within kResidualGrowth of its value.
        if (std::isfinite(rt) &&
            ((merit(trial_res) < (1 - 1e-4 * alpha) * m0 && rt <= kResidualGrowth * r) ||
             !nonlinear || !newton)) {
          accepted = true;
          break;
        }
        alpha *= 0.5;
      }
      if (accepted || !newton) break;
      newton = false;  // fall back to a full Picard step
    }
    solution_ = trial;
    r = rt;
    (newton ? report_.newton_steps : report_.picard_steps) += 1;
    {
      std::ostringstream os;
      os << "continuum: " << (newton ? "newton" : "picard") << " step " << it + 1
         << "  |R|/|R0| = " << r / r_ref << "  step length " << alpha;
      if (iterative) os << "  fgmres iterations " << linear_its;
      log(os.str());
    }
    if (!std::isfinite(r)) {
      report_.message = "nonlinear residual is not finite";
      break;
    }
    if (r <= nl.relative_tolerance * r_ref || r <= nl.absolute_tolerance) {
      report_.converged = true;
      break;
    }
  }
  if (!nonlinear && !iterative && std::isfinite(r)) report_.converged = true;  // one exact direct solve
  report_.final_residual = r;
  if (!report_.converged && report_.message.empty()) {
    std::ostringstream os;
    os << "no convergence after " << report_.picard_steps + report_.newton_steps
       << " nonlinear iterations: |R|/|R0| = " << r / r_ref;
    report_.message = os.str();
  }
}

// ---------------------------------------------------------------------------- post-processing

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

PointState FlowProblem::make_state(const SymmetricTensor<2, dim>& D, double p, const Vec2& u) const {
  RheologyInputs in;
  in.resize(1);
  RheologyOutputs out;
  out.resize(1);
  in.strain_rate_sq[0] = 0.5 * (D * D);
  in.pressure[0] = p;
  setup_.viscosity->evaluate(in, out);
  PointState s;
  s.velocity = u;
  s.pressure = p;
  s.viscosity = out.viscosity[0];
  s.inertial_number = out.inertial_number[0];
  s.stress = -p * unit_symmetric_tensor<dim>() + 2 * s.viscosity * D;
  return s;
}

std::map<types::global_dof_index, double> FlowProblem::boundary_reaction(types::boundary_id id) const {
  VectorType r;
  assemble_impl(ghosted(solution_), nullptr, false, r, true);
  const IndexSet bd = DoFTools::extract_boundary_dofs(dof_handler_, fe_.component_mask(kVelocity), {id});
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
  const IndexSet x_dofs = DoFTools::extract_dofs(dof_handler_, fe_.component_mask(
                                                                     FEValuesExtractors::Scalar(0)));
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
        const PointState s = make_state(sym[q], p[q], u[q]);
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

int FlowProblem::visit_boundary_at_angle(types::boundary_id id, const Point2& centre, double angle,
                                         UpdateFlags flags, const char* who,
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
  visit_boundary_at_angle(id, centre, angle, flags, "boundary_state", [&](const FEFaceValues<dim>& ffv) {
    ffv[kVelocity].get_function_symmetric_gradients(state, sym);
    ffv[kPressure].get_function_values(state, p);
    ffv[kVelocity].get_function_values(state, u);
    const PointState st = make_state(sym[0], p[0], u[0]);
    const double v[13] = {st.stress[0][0], st.stress[0][1], st.stress[1][1], u[0][0], u[0][1],
                          ffv.normal_vector(0)[0], ffv.normal_vector(0)[1],
                          ffv.quadrature_point(0)[0], ffv.quadrature_point(0)[1], p[0],
                          st.viscosity, st.inertial_number, 1.0};
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
    for (const auto& [g, v] : reaction_all) local.emplace(g, static_cast<unsigned int>(local.size()));
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
                entries.push_back(ffv[kVelocity].value(i, q) * ffv[kVelocity].value(j, q) * ffv.JxW(q));
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
    for (const auto& [g, l] : local) rhs(l) = reaction_all.at(g);  // force of the medium on the body
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
  visit_boundary_at_angle(id, centre, angle, update_values, "consistent_traction",
                          [&](const FEFaceValues<dim>& ffv) {
                            const DoFHandler<dim>::active_cell_iterator cell(
                                &tria_, ffv.get_cell()->level(), ffv.get_cell()->index(), &dof_handler_);
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
    local[k] = make_state(sym[0], p[0], u[0]);
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

std::array<double, 3> FlowProblem::errors(const VectorField& u_exact,
                                          const std::function<Tensor<2, dim>(const Point2&)>& grad_exact,
                                          const ScalarField& p_exact,
                                          bool remove_mean_pressure) const {
  const VectorType state = ghosted(solution_);
  const QGauss<dim> quad(5);
  FEValues<dim> fev(mapping_, fe_, quad,
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
    std::ofstream f(file);
    data_out.write_vtu(f);
  } else {
    // one .vtu, each rank writing its cells' patches (MPI I/O)
    data_out.write_vtu_in_parallel(file, comm_);
  }
}

}  // namespace grainlift::continuum::internal
