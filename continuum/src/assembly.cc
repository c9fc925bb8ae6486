// Finite-element engine of the continuum solver: steady incompressible generalised-Newtonian
// flow (Stokes, optional rho (u.grad)u) with Taylor-Hood Q2-Q1 elements on an isoparametric
// (MappingQ2) mesh. The weak form, with n the outward normal of the medium:
//   R_v = int 2 eta D(u):D(v) - p div v + rho ((grad u) u).v - f.v  - int_{Gamma_N} t.v
//         + int_{Gamma_wall} mu_w p+ g(s) (t_w.v),        g(s) = s / sqrt(s^2 + eps^2)
//   R_q = - int q div u
// Newton's Jacobian differentiates eta(|D|^2, p) in both arguments (see assemble_impl).
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/full_matrix.h>

#include <cmath>

#include "flow_problem.h"
#include "quadrature_rheology.h"

namespace grainlift::continuum::internal {

using namespace dealii;

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
}  // namespace grainlift::continuum::internal
