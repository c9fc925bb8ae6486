// Finite-element engine of the continuum solver: steady incompressible generalised-Newtonian
// flow (Stokes, optional rho (u.grad)u) with Taylor-Hood Q2-Q1 elements on an isoparametric
// (MappingQ2) mesh. The weak form, with n the outward normal of the medium:
//   R_v = int 2 eta D(u):D(v) - p div v + rho ((grad u) u).v - f.v  - int_{Gamma_N} t.v
//         + int_{Gamma_wall} mu_w p+ g(s) (t_w.v),        g(s) = s / sqrt(s^2 + eps^2)
//   R_q = - int q div u
// Newton's Jacobian differentiates eta(|D|^2, p) in both arguments (see assemble_impl).
#include "flow_problem.h"

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
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/vector_tools.h>

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

/// Trilinos objects need MPI even on one process. When the program has not initialised MPI
/// (the tests, a serial run), do it here once and finalise at exit.
void ensure_mpi() {
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (initialised) return;
  MPI_Init(nullptr, nullptr);
  std::atexit([] {
    int finalised = 0;
    MPI_Finalized(&finalised);
    if (finalised) return;
    MPI_Finalize();
  });
}

/// Block upper-triangular preconditioner of K = [A B^T; B 0]:
///   P = [A B^T; 0 -S],  P^{-1} (x_u, x_p):  y_p = -S^{-1} x_p,  y_u = A^{-1} (x_u - B^T y_p)
/// A^{-1}: one AMG V-cycle on the velocity block. S^{-1}: one AMG V-cycle on B diag(A)^{-1} B^T
/// (SchurApproximation::diagonal_a), or the inverse of the lumped 1/eta-weighted pressure mass
/// matrix (viscosity_mass). B^T y_p is taken from K itself (in Newton's Jacobian the (u,p)
/// block also holds the d eta / dp term, so it is not the transpose of the (p,u) block).
class BlockTriangularPreconditioner {
 public:
  /// @p schur_diagonal: the diagonal of the Schur approximation (used for the scaling, and as
  /// S itself when @p schur_amg is null).
  BlockTriangularPreconditioner(const SparseMatrix<double>& K, types::global_dof_index n_u,
                                const TrilinosWrappers::PreconditionAMG& a_amg,
                                const TrilinosWrappers::PreconditionAMG* schur_amg,
                                Vector<double> schur_diagonal)
      : K_(K), n_u_(n_u), a_amg_(a_amg), schur_amg_(schur_amg), n_p_(K.m() - n_u),
        schur_diagonal_(std::move(schur_diagonal)), tmp_(K.m()), ku_(K.m()), xu_(n_u),
        yu_(n_u), xp_(n_p_), yp_(n_p_) {}

  void vmult(Vector<double>& dst, const Vector<double>& src) const {
    for (types::global_dof_index i = 0; i < n_p_; ++i) xp_(i) = src(n_u_ + i);
    if (schur_amg_) {
      schur_amg_->vmult(yp_, xp_);
    } else {
      for (types::global_dof_index i = 0; i < n_p_; ++i) yp_(i) = xp_(i) / schur_diagonal_(i);
    }
    yp_ *= -1.0;
    tmp_ = 0;
    for (types::global_dof_index i = 0; i < n_p_; ++i) tmp_(n_u_ + i) = yp_(i);
    K_.vmult(ku_, tmp_);  // (B^T y_p, 0 y_p)
    for (types::global_dof_index i = 0; i < n_u_; ++i) xu_(i) = src(i) - ku_(i);
    a_amg_.vmult(yu_, xu_);
    for (types::global_dof_index i = 0; i < n_u_; ++i) dst(i) = yu_(i);
    for (types::global_dof_index i = 0; i < n_p_; ++i) dst(n_u_ + i) = yp_(i);
  }

  double schur_diagonal(types::global_dof_index i) const { return schur_diagonal_(i); }

 private:
  const SparseMatrix<double>& K_;
  const types::global_dof_index n_u_;
  const TrilinosWrappers::PreconditionAMG& a_amg_;
  const TrilinosWrappers::PreconditionAMG* schur_amg_;
  const types::global_dof_index n_p_;
  const Vector<double> schur_diagonal_;
  mutable Vector<double> tmp_, ku_, xu_, yu_, xp_, yp_;
};

/// D K D for a diagonal D (the vector @p d).
class ScaledMatrix {
 public:
  ScaledMatrix(const SparseMatrix<double>& K, const Vector<double>& d) : K_(K), d_(d), t_(d.size()) {}
  void vmult(Vector<double>& dst, const Vector<double>& src) const {
    t_ = src;
    t_.scale(d_);
    K_.vmult(dst, t_);
    dst.scale(d_);
  }

 private:
  const SparseMatrix<double>& K_;
  const Vector<double>& d_;
  mutable Vector<double> t_;
};

/// D^{-1} P^{-1} D^{-1}: the preconditioner of K carried over to D K D.
class ScaledPreconditioner {
 public:
  ScaledPreconditioner(const BlockTriangularPreconditioner& P, const Vector<double>& d)
      : P_(P), d_(d), t_(d.size()) {}
  void vmult(Vector<double>& dst, const Vector<double>& src) const {
    for (unsigned int i = 0; i < t_.size(); ++i) t_(i) = src(i) / d_(i);
    P_.vmult(dst, t_);
    for (unsigned int i = 0; i < t_.size(); ++i) dst(i) /= d_(i);
  }

 private:
  const BlockTriangularPreconditioner& P_;
  const Vector<double>& d_;
  mutable Vector<double> t_;
};

/// Copy the entries of @p full in rows [row0, row0 + block.m()) and columns
/// [col0, col0 + block.n()) into @p block.
void copy_block(const SparseMatrix<double>& full, types::global_dof_index row0,
                types::global_dof_index col0, SparseMatrix<double>& block) {
  const types::global_dof_index m = block.m(), n = block.n();
  for (types::global_dof_index i = 0; i < m; ++i)
    for (auto it = full.begin(row0 + i); it != full.end(row0 + i); ++it) {
      const types::global_dof_index j = it->column();
      if (j >= col0 && j < col0 + n) block.set(i, j - col0, it->value());
    }
}

}  // namespace

FlowProblem::FlowProblem(Triangulation<dim>& tria, const ProblemSetup& setup)
    : tria_(tria), setup_(setup), fe_(FE_Q<dim>(2), dim, FE_Q<dim>(1), 1), mapping_(2),
      dof_handler_(tria) {}

void FlowProblem::make_constraints(AffineConstraints<double>& c, bool homogeneous) const {
  c.clear();
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
    const auto counts = DoFTools::count_dofs_per_fe_component(dof_handler_);
    const types::global_dof_index first_p = counts[0] + counts[1];
    if (!c.is_constrained(first_p)) {
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
  if (iterative) {
    // two blocks, velocity then pressure; inside the velocity block the two components of a
    // node stay next to each other (the cell-wise numbering), which suits ML's aggregation
    ensure_mpi();
    DoFRenumbering::component_wise(dof_handler_, std::vector<unsigned int>{0, 0, 1});
  } else {
    DoFRenumbering::Cuthill_McKee(dof_handler_);
    DoFRenumbering::component_wise(dof_handler_);  // u_x, then u_y, then p
  }
  make_constraints(nonzero_constraints_, false);
  make_constraints(zero_constraints_, true);
  DynamicSparsityPattern dsp(dof_handler_.n_dofs());
  DoFTools::make_sparsity_pattern(dof_handler_, dsp, zero_constraints_, false);
  sparsity_.copy_from(dsp);
  system_matrix_.reinit(sparsity_);
  if (iterative) {
    const auto counts = DoFTools::count_dofs_per_fe_component(dof_handler_);
    n_u_ = counts[0] + counts[1];
    const types::global_dof_index n = dof_handler_.n_dofs(), n_p = n - n_u_;
    DynamicSparsityPattern uu(n_u_), pp(n_p), up(n_u_, n_p), pu(n_p, n_u_);
    for (types::global_dof_index i = 0; i < n; ++i)
      for (auto it = sparsity_.begin(i); it != sparsity_.end(i); ++it) {
        const types::global_dof_index j = it->column();
        if (i < n_u_ && j < n_u_) uu.add(i, j);
        else if (i >= n_u_ && j >= n_u_) pp.add(i - n_u_, j - n_u_);
        else if (i < n_u_) up.add(i, j - n_u_);
        else pu.add(i - n_u_, j);
      }
    sparsity_uu_.copy_from(uu);
    sparsity_pp_.copy_from(pp);
    sparsity_up_.copy_from(up);
    sparsity_pu_.copy_from(pu);
    block_uu_.reinit(sparsity_uu_);
    block_pp_.reinit(sparsity_pp_);
    block_up_.reinit(sparsity_up_);
    block_pu_.reinit(sparsity_pu_);
    schur_bdb_.clear();
    if (setup_.schur_approximation == SchurApproximation::viscosity_mass)
      schur_mass_.reinit(sparsity_);
    DoFTools::extract_constant_modes(dof_handler_, fe_.component_mask(kVelocity),
                                     velocity_constant_modes_);
  }
  solution_.reinit(dof_handler_.n_dofs());
  cache_.reset();
  traction_id_ = -1;
}

void FlowProblem::interpolate_initial_guess() {
  VectorTools::interpolate(mapping_, dof_handler_,
                           VelocityPressure(setup_.initial_velocity, setup_.initial_pressure),
                           solution_);
  nonzero_constraints_.distribute(solution_);
}

double FlowProblem::assemble_system(const Vector<double>& state, bool matrix, bool newton,
                                    Vector<double>& residual) {
  const bool schur = matrix && setup_.linear_solver == LinearSolver::amg &&
                     setup_.schur_approximation == SchurApproximation::viscosity_mass;
  return assemble_impl(state, matrix ? &system_matrix_ : nullptr, newton, residual, false,
                       schur ? &schur_mass_ : nullptr);
}

double FlowProblem::assemble_impl(const Vector<double>& state, SparseMatrix<double>* matrix,
                                  bool newton, Vector<double>& residual,
                                  bool reaction_mode, SparseMatrix<double>* schur_mass) const {
  residual.reinit(dof_handler_.n_dofs());
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
  std::vector<SymmetricTensor<2, dim>> sym(nq);
  std::vector<Tensor<2, dim>> grad(nq);
  std::vector<Vec2> uval(nq), fu(nfq);
  std::vector<double> pval(nq), fp(nfq);
  std::vector<SymmetricTensor<2, dim>> phi_sym(dpc);
  std::vector<Tensor<2, dim>> phi_grad(dpc);
  std::vector<Vec2> phi_u(dpc);
  std::vector<double> phi_div(dpc), phi_p(dpc);
  RheologyInputs in;
  in.resize(nq);
  RheologyOutputs out;
  out.resize(nq);
  const double rho = setup_.inertia_density;
  const bool inertia = rho > 0;

  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    fev.reinit(cell);
    cm = 0;
    cr = 0;
    if (schur_mass) cmass = 0;
    fev[kVelocity].get_function_symmetric_gradients(state, sym);
    fev[kPressure].get_function_values(state, pval);
    if (inertia) {
      fev[kVelocity].get_function_gradients(state, grad);
      fev[kVelocity].get_function_values(state, uval);
    }
    for (unsigned int q = 0; q < nq; ++q) {
      in.strain_rate_sq[q] = 0.5 * (sym[q] * sym[q]);  // |D|^2 = D:D/2
      in.pressure[q] = pval[q];
    }
    setup_.viscosity->evaluate(in, out);

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
      for (unsigned int i = 0; i < dpc; ++i) residual(idx[i]) += cr(i);
    } else if (matrix) {
      zero_constraints_.distribute_local_to_global(cm, cr, idx, *matrix, residual);
      if (schur_mass) zero_constraints_.distribute_local_to_global(cmass, idx, *schur_mass);
    } else {
      zero_constraints_.distribute_local_to_global(cr, idx, residual);
    }
  }
  return residual.l2_norm();
}

int FlowProblem::solve(const Vector<double>& residual, Vector<double>& update,
                       double relative_tolerance) {
  int iterations = 0;
  if (setup_.linear_solver == LinearSolver::amg) {
    update.reinit(residual.size());
    iterations = solve_iterative(residual, update, relative_tolerance);
    update *= -1.0;
  } else {
    SparseDirectUMFPACK direct;
    direct.initialize(system_matrix_);
    update = residual;
    direct.solve(update);
    update *= -1.0;
  }
  zero_constraints_.distribute(update);
  ++report_.linear_solves;
  report_.krylov_iterations += iterations;
  return iterations;
}

int FlowProblem::solve_iterative(const Vector<double>& rhs, Vector<double>& x,
                                 double relative_tolerance) {
  const types::global_dof_index n = rhs.size(), n_p = n - n_u_;
  copy_block(system_matrix_, 0, 0, block_uu_);
  // AMG (Trilinos ML, smoothed aggregation) on the velocity block: the two velocity components
  // as the near-null space, Q2 elements. The block is symmetric without inertia (the Newton
  // term 2 eta_s (D:D_j)(D:D_i) is symmetric); "elliptic" (Chebyshev smoother) measured better
  // than the non-symmetric setting on the cylinder (76 against 103 FGMRES iterations per solve).
  TrilinosWrappers::SparseMatrix a_uu;
  a_uu.reinit(block_uu_);
  TrilinosWrappers::PreconditionAMG a_amg;
  {
    TrilinosWrappers::PreconditionAMG::AdditionalData data;
    data.elliptic = true;
    data.higher_order_elements = true;
    data.smoother_sweeps = 2;
    data.aggregation_threshold = 0.02;
    data.constant_modes = velocity_constant_modes_;
    a_amg.initialize(a_uu, data);
  }
  // Schur complement approximation
  Vector<double> schur_diagonal(n_p);
  TrilinosWrappers::SparseMatrix s_tril;
  TrilinosWrappers::PreconditionAMG s_amg;
  const bool diagonal_a = setup_.schur_approximation == SchurApproximation::diagonal_a;
  if (diagonal_a) {
    // S = B diag(A)^{-1} B^T, a pressure Laplacian weighted by the actual velocity block:
    // unlike M_p / eta it sees the constraints and where eta jumps by decades between cells
    copy_block(system_matrix_, 0, n_u_, block_up_);
    copy_block(system_matrix_, n_u_, 0, block_pu_);
    Vector<double> inv_diag(n_u_);
    for (types::global_dof_index i = 0; i < n_u_; ++i)
      inv_diag(i) = 1.0 / std::abs(block_uu_.diag_element(i));
    if (schur_bdb_.empty()) {
      sparsity_s_.copy_from(sparsity_pp_);
      schur_bdb_.reinit(sparsity_s_);
      block_pu_.mmult(schur_bdb_, block_up_, inv_diag, true);  // rebuilds sparsity_s_ once
    } else {
      schur_bdb_ = 0;  // mmult adds to C when the pattern is kept
      block_pu_.mmult(schur_bdb_, block_up_, inv_diag, false);
    }
    // rows without a (p,u) coupling (a pinned pressure): unit-scale diagonal
    double dmax = 0;
    for (types::global_dof_index i = 0; i < n_p; ++i)
      dmax = std::max(dmax, std::abs(schur_bdb_.diag_element(i)));
    for (types::global_dof_index i = 0; i < n_p; ++i) {
      if (!(std::abs(schur_bdb_.diag_element(i)) > 0)) schur_bdb_.diag_element(i) = dmax;
      schur_diagonal(i) = std::abs(schur_bdb_.diag_element(i));
    }
    s_tril.reinit(schur_bdb_);
    TrilinosWrappers::PreconditionAMG::AdditionalData data;
    data.elliptic = true;
    data.smoother_sweeps = 2;
    s_amg.initialize(s_tril, data);
  } else {
    copy_block(schur_mass_, n_u_, n_u_, block_pp_);
    for (types::global_dof_index i = 0; i < n_p; ++i) {
      double sum = 0;  // lumped: row sums, positive for Q1
      for (auto it = block_pp_.begin(i); it != block_pp_.end(i); ++it) sum += it->value();
      schur_diagonal(i) = sum;
    }
  }
  const BlockTriangularPreconditioner prec(system_matrix_, n_u_, a_amg,
                                           diagonal_a ? &s_amg : nullptr, schur_diagonal);
  // The momentum and continuity rows of K have different units and scales (forces against
  // h div u), and eta varies by decades: the Euclidean residual of K barely sees div u. FGMRES
  // therefore works on D K D y = D rhs, x = D y, D = diag(A_ii)^(-1/2) on the velocity and
  // diag(S_ii)^(-1/2) on the pressure (both blocks with unit diagonal, an energy-like norm);
  // the tolerance applies to |D r|.
  Vector<double> d(n), b(n), y(n);
  for (types::global_dof_index i = 0; i < n; ++i) {
    const double a = i < n_u_ ? std::abs(system_matrix_.diag_element(i)) : prec.schur_diagonal(i - n_u_);
    d(i) = a > 0 && std::isfinite(a) ? 1.0 / std::sqrt(a) : 1.0;
    b(i) = d(i) * rhs(i);
  }
  const ScaledMatrix scaled(system_matrix_, d);
  const ScaledPreconditioner scaled_prec(prec, d);
  SolverControl control(1000, std::max(relative_tolerance * b.l2_norm(), 1e-300));
  SolverFGMRES<Vector<double>> fgmres(control, SolverFGMRES<Vector<double>>::AdditionalData(100));
  try {
    fgmres.solve(scaled, y, b, scaled_prec);
  } catch (const SolverControl::NoConvergence& e) {
    std::ostringstream os;
    os << "continuum: FGMRES did not reach " << relative_tolerance << " in " << e.last_step
       << " iterations (|D r|/|D b| = " << e.last_residual / std::max(b.l2_norm(), 1e-300)
       << "); the step is used as it is";
    log(os.str());
  }
  for (types::global_dof_index i = 0; i < n; ++i) x(i) = d(i) * y(i);
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
  Vector<double> res(n), upd(n), trial(n), trial_res(n), weight(n);
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
    os << "continuum: " << tria_.n_active_cells() << " cells, " << n << " dofs, initial residual "
       << r0;
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
      for (unsigned int i = 0; i < n; ++i) {
        const double d = std::abs(system_matrix_.diag_element(i));
        weight(i) = d > 0 ? 1.0 / d : 1.0;
      }
      const auto merit = [&](const Vector<double>& v) {
        if (!scaled) return v.l2_norm();
        double sum = 0;
        for (unsigned int i = 0; i < n; ++i) sum += weight(i) * v(i) * v(i);
        return std::sqrt(sum);
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

ForceTorque FlowProblem::reaction(types::boundary_id id, const Point2& centre) const {
  Vector<double> r;
  assemble_impl(solution_, nullptr, false, r, true);
  const IndexSet bd = DoFTools::extract_boundary_dofs(dof_handler_, fe_.component_mask(kVelocity), {id});
  std::map<types::global_dof_index, Point<dim>> support;
  DoFTools::map_dofs_to_support_points(mapping_, dof_handler_, support);
  const IndexSet x_dofs = DoFTools::extract_dofs(dof_handler_, fe_.component_mask(
                                                                     FEValuesExtractors::Scalar(0)));
  ForceTorque ft;
  for (const auto i : bd) {
    const unsigned int c = x_dofs.is_element(i) ? 0 : 1;
    const Vec2 arm = support.at(i) - centre;
    // the medium's force on the body is minus the residual tested with a rigid motion
    const double f = -r(i);
    (c == 0 ? ft.fx : ft.fy) += f;
    ft.torque += c == 0 ? -arm[1] * f : arm[0] * f;
  }
  return ft;
}

ForceTorque FlowProblem::surface_integral(types::boundary_id id, const Point2& centre) const {
  const QGauss<dim - 1> fquad(4);
  FEFaceValues<dim> ffv(mapping_, fe_, fquad,
                        update_values | update_gradients | update_quadrature_points |
                            update_normal_vectors | update_JxW_values);
  std::vector<SymmetricTensor<2, dim>> sym(fquad.size());
  std::vector<double> p(fquad.size());
  std::vector<Vec2> u(fquad.size());
  ForceTorque ft;
  for (const auto& cell : dof_handler_.active_cell_iterators())
    for (const auto& face : cell->face_iterators()) {
      if (!face->at_boundary() || face->boundary_id() != id) continue;
      ffv.reinit(cell, face);
      ffv[kVelocity].get_function_symmetric_gradients(solution_, sym);
      ffv[kPressure].get_function_values(solution_, p);
      ffv[kVelocity].get_function_values(solution_, u);
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
  return ft;
}

int FlowProblem::visit_boundary_at_angle(types::boundary_id id, const Point2& centre, double angle,
                                         UpdateFlags flags, const char* who,
                                         const std::function<void(const FEFaceValues<dim>&)>& visit) const {
  int found = 0;
  for (const auto& cell : dof_handler_.active_cell_iterators())
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
  if (found == 0)
    throw std::runtime_error(std::string(who) + ": no boundary face at the requested angle");
  return found;
}

PointState FlowProblem::boundary_state(types::boundary_id id, const Point2& centre, double angle,
                                       Vec2& normal_out_of_medium, Point2& where) const {
  // The stress is discontinuous across cells: a point on a vertex is shared by two faces, and
  // their states are averaged so that mirror-symmetric angles see mirror-symmetric values.
  const UpdateFlags flags =
      update_values | update_gradients | update_quadrature_points | update_normal_vectors;
  SymmetricTensor<2, dim> stress_sum;
  Vec2 u_sum, n_sum;
  Point2 x_sum;
  double p_sum = 0, eta_sum = 0, I_sum = 0;
  std::vector<SymmetricTensor<2, dim>> sym(1);
  std::vector<double> p(1);
  std::vector<Vec2> u(1);
  const int found =
      visit_boundary_at_angle(id, centre, angle, flags, "boundary_state", [&](const FEFaceValues<dim>& ffv) {
        ffv[kVelocity].get_function_symmetric_gradients(solution_, sym);
        ffv[kPressure].get_function_values(solution_, p);
        ffv[kVelocity].get_function_values(solution_, u);
        const PointState st = make_state(sym[0], p[0], u[0]);
        stress_sum += st.stress;
        eta_sum += st.viscosity;
        I_sum += st.inertial_number;
        p_sum += p[0];
        u_sum += u[0];
        n_sum += ffv.normal_vector(0);
        x_sum += Vec2(ffv.quadrature_point(0));
      });
  normal_out_of_medium = n_sum / n_sum.norm();
  where = x_sum / found;
  PointState st;
  st.velocity = u_sum / found;
  st.pressure = p_sum / found;
  st.viscosity = eta_sum / found;
  st.inertial_number = I_sum / found;
  st.stress = stress_sum / found;
  return st;
}

Vec2 FlowProblem::consistent_traction(types::boundary_id id, const Point2& centre,
                                      double angle) const {
  if (traction_id_ != static_cast<int>(id) || traction_.size() != dof_handler_.n_dofs()) {
    Vector<double> r;
    assemble_impl(solution_, nullptr, false, r, true);
    const IndexSet bd =
        DoFTools::extract_boundary_dofs(dof_handler_, fe_.component_mask(kVelocity), {id});
    std::map<types::global_dof_index, unsigned int> local;
    for (const auto i : bd) local.emplace(i, static_cast<unsigned int>(local.size()));
    const unsigned int nb = static_cast<unsigned int>(local.size());
    // boundary mass matrix (vector-valued, so the two components decouple)
    const QGauss<dim - 1> fquad(4);
    FEFaceValues<dim> ffv(mapping_, fe_, fquad, update_values | update_JxW_values);
    const unsigned int dpc = fe_.n_dofs_per_cell();
    std::vector<types::global_dof_index> idx(dpc);
    DynamicSparsityPattern dsp(nb);
    for (const auto& cell : dof_handler_.active_cell_iterators())
      for (const auto& face : cell->face_iterators()) {
        if (!face->at_boundary() || face->boundary_id() != id) continue;
        cell->get_dof_indices(idx);
        for (unsigned int i = 0; i < dpc; ++i)
          for (unsigned int j = 0; j < dpc; ++j)
            if (local.count(idx[i]) && local.count(idx[j])) dsp.add(local[idx[i]], local[idx[j]]);
      }
    SparsityPattern sp;
    sp.copy_from(dsp);
    SparseMatrix<double> mass(sp);
    for (const auto& cell : dof_handler_.active_cell_iterators())
      for (const auto& face : cell->face_iterators()) {
        if (!face->at_boundary() || face->boundary_id() != id) continue;
        ffv.reinit(cell, face);
        cell->get_dof_indices(idx);
        for (unsigned int q = 0; q < fquad.size(); ++q)
          for (unsigned int i = 0; i < dpc; ++i) {
            const auto li = local.find(idx[i]);
            if (li == local.end()) continue;
            for (unsigned int j = 0; j < dpc; ++j) {
              const auto lj = local.find(idx[j]);
              if (lj == local.end()) continue;
              mass.add(li->second, lj->second,
                       ffv[kVelocity].value(i, q) * ffv[kVelocity].value(j, q) * ffv.JxW(q));
            }
          }
      }
    Vector<double> rhs(nb);
    for (const auto& [g, l] : local) rhs(l) = -r(g);  // force of the medium on the body
    SparseDirectUMFPACK direct;
    direct.initialize(mass);
    direct.solve(rhs);
    traction_.reinit(dof_handler_.n_dofs());
    for (const auto& [g, l] : local) traction_(g) = rhs(l);
    traction_id_ = static_cast<int>(id);
  }
  // evaluate t_h on the face(s) at the requested angle
  Vec2 sum;
  std::vector<Vec2> t(1);
  const int found = visit_boundary_at_angle(id, centre, angle, update_values, "consistent_traction",
                                            [&](const FEFaceValues<dim>& ffv) {
                                              ffv[kVelocity].get_function_values(traction_, t);
                                              sum += t[0];
                                            });
  return sum / found;
}

bool FlowProblem::point_state(const Point2& x, PointState& out) const {
  if (!cache_) cache_ = std::make_unique<GridTools::Cache<dim>>(tria_, mapping_);
  std::pair<Triangulation<dim>::active_cell_iterator, Point<dim>> found;
  try {
    found = GridTools::find_active_cell_around_point(*cache_, x);
  } catch (...) {
    return false;
  }
  if (found.first == tria_.end() || found.first.state() != IteratorState::valid) return false;
  const DoFHandler<dim>::active_cell_iterator cell(&tria_, found.first->level(),
                                                   found.first->index(), &dof_handler_);
  const Quadrature<dim> q(GeometryInfo<dim>::project_to_unit_cell(found.second));
  FEValues<dim> fv(mapping_, fe_, q, update_values | update_gradients);
  fv.reinit(cell);
  std::vector<SymmetricTensor<2, dim>> sym(1);
  std::vector<double> p(1);
  std::vector<Vec2> u(1);
  fv[kVelocity].get_function_symmetric_gradients(solution_, sym);
  fv[kPressure].get_function_values(solution_, p);
  fv[kVelocity].get_function_values(solution_, u);
  out = make_state(sym[0], p[0], u[0]);
  return true;
}

std::array<double, 3> FlowProblem::errors(const VectorField& u_exact,
                                          const std::function<Tensor<2, dim>(const Point2&)>& grad_exact,
                                          const ScalarField& p_exact,
                                          bool remove_mean_pressure) const {
  const QGauss<dim> quad(5);
  FEValues<dim> fev(mapping_, fe_, quad,
                    update_values | update_gradients | update_quadrature_points | update_JxW_values);
  std::vector<Vec2> u(quad.size());
  std::vector<Tensor<2, dim>> g(quad.size());
  std::vector<double> p(quad.size());
  double eu = 0, eg = 0, ep = 0, ep1 = 0, area = 0;
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    fev.reinit(cell);
    fev[kVelocity].get_function_values(solution_, u);
    fev[kVelocity].get_function_gradients(solution_, g);
    fev[kPressure].get_function_values(solution_, p);
    for (unsigned int q = 0; q < quad.size(); ++q) {
      const Point2& x = fev.quadrature_point(q);
      const double w = fev.JxW(q);
      eu += (u[q] - u_exact(x)).norm_square() * w;
      eg += (g[q] - grad_exact(x)).norm_square() * w;
      const double e = p[q] - p_exact(x);
      ep += e * e * w;
      ep1 += e * w;
      area += w;
    }
  }
  if (remove_mean_pressure) ep -= ep1 * ep1 / area;
  return {std::sqrt(eu), std::sqrt(eg), std::sqrt(std::max(ep, 0.0))};
}

void FlowProblem::output_results(const std::string& directory, const std::string& basename) const {
  std::filesystem::create_directories(directory);
  // cell averages of the viscosity and of the inertial number
  Vector<float> eta(tria_.n_active_cells()), inertial(tria_.n_active_cells());
  {
    const QGauss<dim> quad(3);
    FEValues<dim> fev(mapping_, fe_, quad, update_gradients | update_values);
    std::vector<SymmetricTensor<2, dim>> sym(quad.size());
    std::vector<double> p(quad.size());
    RheologyInputs in;
    in.resize(quad.size());
    RheologyOutputs out;
    out.resize(quad.size());
    for (const auto& cell : dof_handler_.active_cell_iterators()) {
      fev.reinit(cell);
      fev[kVelocity].get_function_symmetric_gradients(solution_, sym);
      fev[kPressure].get_function_values(solution_, p);
      for (unsigned int q = 0; q < quad.size(); ++q) {
        in.strain_rate_sq[q] = 0.5 * (sym[q] * sym[q]);
        in.pressure[q] = p[q];
      }
      setup_.viscosity->evaluate(in, out);
      double a = 0, b = 0;
      for (unsigned int q = 0; q < quad.size(); ++q) {
        a += out.viscosity[q];
        b += std::min(out.inertial_number[q], 1e30);
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
  data_out.add_data_vector(solution_, names, DataOut<dim>::type_dof_data, interp);
  data_out.add_data_vector(eta, "viscosity", DataOut<dim>::type_cell_data);
  data_out.add_data_vector(inertial, "inertial_number", DataOut<dim>::type_cell_data);
  data_out.build_patches(mapping_, 2, DataOut<dim>::curved_inner_cells);
  std::ofstream f(std::filesystem::path(directory) / (basename + ".vtu"));
  data_out.write_vtu(f);
}

}  // namespace grainlift::continuum::internal
