// Finite-element engine of the continuum solver: steady incompressible generalised-Newtonian
// flow (Stokes, optional rho (u.grad)u) with Taylor-Hood Q2-Q1 elements on an isoparametric
// (MappingQ2) mesh. The weak form, with n the outward normal of the medium:
//   R_v = int 2 eta D(u):D(v) - p div v + rho ((grad u) u).v - f.v  - int_{Gamma_N} t.v
//         + int_{Gamma_wall} mu_w p+ g(s) (t_w.v),        g(s) = s / sqrt(s^2 + eps^2)
//   with mu_w constant or the grains' slip law mu_a + (mu_b - mu_a) |s| / (|s| + v0)
//   R_q = - int q div u
//   dilatant (ProblemSetup::dilatancy): R_q = - int q div((1 - delta) u), written
//         - int q div u - int delta u.grad q + int_{dOmega} q delta u.n (delta need not be
//         continuous), and f -> (1 - delta) f
// Newton's Jacobian differentiates eta(|D|^2, p) in both arguments (see assemble_cell_volume).
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/full_matrix.h>

#include <cmath>

#include "flow_problem.h"
#include "quadrature_rheology.h"

namespace grainlift::continuum::internal {

using namespace dealii;

/// Work arrays of one cell's assembly: the FE values on the cell and its faces, the local
/// residual and matrices, the state and the shape functions at the quadrature points.
struct FlowProblem::AssemblyScratch {
  AssemblyScratch(const Mapping<dim>& mapping, const FiniteElement<dim>& fe, bool schur)
      : quad(3), fquad(3),
        fev(mapping, fe, quad,
            update_values | update_gradients | update_quadrature_points | update_JxW_values),
        ffv(mapping, fe, fquad,
            update_values | update_quadrature_points | update_normal_vectors |
                update_JxW_values),
        dfv(mapping, fe, fquad,
            update_values | update_gradients | update_normal_vectors | update_JxW_values),
        dpc(fe.n_dofs_per_cell()), nq(quad.size()), nfq(fquad.size()),
        cmass(schur ? dpc : 0, schur ? dpc : 0), cm(dpc, dpc), cr(dpc), idx(dpc), qr(nq),
        grad(nq), uval(nq), fu(nfq), fp(nfq), fsym(nfq), phi_sym(dpc), phi_grad(dpc),
        phi_u(dpc), phi_div(dpc), phi_p(dpc), phi_gp(dpc) {
    face_in.resize(nfq);
    face_out.resize(nfq);
  }

  const QGauss<dim> quad;
  const QGauss<dim - 1> fquad;
  FEValues<dim> fev;
  FEFaceValues<dim> ffv;
  FEFaceValues<dim> dfv;  ///< with gradients: the dilatant flux's I on a face
  const unsigned int dpc, nq, nfq;
  FullMatrix<double> cmass;  ///< (1/eta)-weighted pressure mass matrix (schur_mass only)
  FullMatrix<double> cm;
  Vector<double> cr;
  std::vector<types::global_dof_index> idx;
  QuadratureRheology qr;  ///< D(u), p and the viscosity model's outputs
  std::vector<Tensor<2, dim>> grad;  ///< grad u (inertia only)
  std::vector<Vec2> uval, fu;        ///< u in the cell (inertia, dilatancy), u on a face
  std::vector<double> fp;            ///< p on a face
  std::vector<SymmetricTensor<2, dim>> fsym;  ///< D(u) on a face (dilatancy only)
  RheologyInputs face_in;                     ///< the rheology on a face (dilatancy only)
  RheologyOutputs face_out;
  std::vector<SymmetricTensor<2, dim>> phi_sym;
  std::vector<Tensor<2, dim>> phi_grad;
  std::vector<Vec2> phi_u;
  std::vector<double> phi_div, phi_p;
  std::vector<Vec2> phi_gp;  ///< grad q (dilatancy only)
};

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
  AssemblyScratch s(mapping_, fe_, schur_mass != nullptr);
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    if (!cell->is_locally_owned()) continue;
    s.fev.reinit(cell);
    s.cm = 0;
    s.cr = 0;
    if (schur_mass) s.cmass = 0;
    assemble_cell_volume(s, state, matrix != nullptr, newton, schur_mass != nullptr);
    if (!reaction_mode) assemble_cell_boundary(s, cell, state, matrix != nullptr, newton);
    cell->get_dof_indices(s.idx);
    distribute_cell(s, matrix, residual, reaction_mode, schur_mass);
  }
  if (matrix) matrix->compress(VectorOperation::add);
  if (schur_mass) schur_mass->compress(VectorOperation::add);
  residual.compress(VectorOperation::add);
  return residual.l2_norm();
}

/// The volume integrals of R_v and R_q (momentum and continuity summed per test function, in
/// one expression) and their Jacobian or Picard matrix, on the cell of s.fev.
void FlowProblem::assemble_cell_volume(AssemblyScratch& s, const VectorType& state, bool matrix,
                                       bool newton, bool schur) const {
  const unsigned int dpc = s.dpc, nq = s.nq;
  const FEValues<dim>& fev = s.fev;
  const std::vector<SymmetricTensor<2, dim>>& sym = s.qr.sym;
  const std::vector<double>& pval = s.qr.pressure;
  const RheologyOutputs& out = s.qr.out;
  const std::vector<Tensor<2, dim>>& grad = s.grad;
  const std::vector<Vec2>& uval = s.uval;
  std::vector<SymmetricTensor<2, dim>>& phi_sym = s.phi_sym;
  std::vector<Tensor<2, dim>>& phi_grad = s.phi_grad;
  std::vector<Vec2>& phi_u = s.phi_u;
  std::vector<double>& phi_div = s.phi_div;
  std::vector<double>& phi_p = s.phi_p;
  const double rho = setup_.inertia_density;
  const bool inertia = rho > 0;
  const DilatancyLaw* dil = setup_.dilatancy ? &*setup_.dilatancy : nullptr;
  s.qr.evaluate(fev, state, *setup_.viscosity);
  if (inertia) fev[kVelocity].get_function_gradients(state, s.grad);
  if (inertia || dil) fev[kVelocity].get_function_values(state, s.uval);

  for (unsigned int q = 0; q < nq; ++q) {
    const double JxW = fev.JxW(q);
    const double eta = out.viscosity[q];
    const SymmetricTensor<2, dim>& D = sym[q];
    double eta_s = newton ? out.deta_dstrain_sq[q] : 0.0;
    // along D the tangent is 2 (eta + eta_s D:D), the secant 2 eta: keep their ratio 1 - s
    // at least tangent_floor_ (NonlinearSettings::tangent_floor)
    if (newton && tangent_floor_ > 0 && eta > 0) {
      const double s_soft = -eta_s * (D * D) / eta;
      if (s_soft > 1 - tangent_floor_) eta_s *= (1 - tangent_floor_) / s_soft;
    }
    const double eta_p = newton ? out.deta_dpressure[q] : 0.0;
    Vec2 f = setup_.body_force ? setup_.body_force(fev.quadrature_point(q)) : Vec2();
    const Vec2 f_dense = f;
    const double delta = dil ? dil->deficit(out.inertial_number[q]) : 0.0;
    // Newton: d delta = ddelta_dI (dI/d|D|^2 D:D_j + dI/dp p_j)
    const double ddelta_dI = dil && newton ? dil->slope(out.inertial_number[q]) : 0.0;
    if (dil) f *= 1 - delta;  // the dilated medium's weight
    const double source =
        setup_.continuity_source ? setup_.continuity_source(fev.quadrature_point(q)) : 0.0;
    const double div_u = trace(D);
    const Vec2 conv = inertia ? Vec2(grad[q] * uval[q]) : Vec2();
    for (unsigned int k = 0; k < dpc; ++k) {
      phi_sym[k] = fev[kVelocity].symmetric_gradient(k, q);
      phi_div[k] = fev[kVelocity].divergence(k, q);
      phi_u[k] = fev[kVelocity].value(k, q);
      phi_p[k] = fev[kPressure].value(k, q);
      if (inertia && matrix) phi_grad[k] = fev[kVelocity].gradient(k, q);
      if (dil) s.phi_gp[k] = fev[kPressure].gradient(k, q);
    }
    for (unsigned int i = 0; i < dpc; ++i) {
      const double D_Di = D * phi_sym[i];
      s.cr(i) += (2 * eta * D_Di - pval[q] * phi_div[i] - phi_p[i] * div_u +
                  rho * (conv * phi_u[i]) - f * phi_u[i]) * JxW;
      if (dil) s.cr(i) -= delta * (uval[q] * s.phi_gp[i]) * JxW;  // - int delta u.grad q
      if (setup_.continuity_source) s.cr(i) += phi_p[i] * source * JxW;
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
        if (dil) a -= delta * (phi_u[j] * s.phi_gp[i]);
        if (ddelta_dI != 0)  // -(1 - delta) f.v_i - delta u.grad q_i through delta
          a += ddelta_dI *
               (out.dI_dstrain_sq[q] * (D * phi_sym[j]) + out.dI_dpressure[q] * phi_p[j]) *
               (f_dense * phi_u[i] - uval[q] * s.phi_gp[i]);
        s.cm(i, j) += a * JxW;
      }
      if (schur)  // (1/eta) p_i p_j: the Schur complement B A^{-1} B^T is ~ M_p / eta
        for (unsigned int j = 0; j < dpc; ++j) s.cmass(i, j) += phi_p[i] * phi_p[j] / eta * JxW;
    }
  }
}

/// The boundary integrals of R_v on the faces of @p cell: -int t.v on the traction
/// boundaries, then the wall friction (add_friction_terms).
void FlowProblem::assemble_cell_boundary(AssemblyScratch& s,
                                         const DoFHandler<dim>::active_cell_iterator& cell,
                                         const VectorType& state, bool matrix,
                                         bool newton) const {
  FEFaceValues<dim>& ffv = s.ffv;
  for (const auto& face : cell->face_iterators()) {
    if (!face->at_boundary()) continue;
    const auto id = face->boundary_id();
    if (setup_.dilatancy) add_dilatancy_flux(s, cell, face, state, matrix, newton);
    const auto tr = setup_.bc.traction.find(id);
    const bool is_friction = setup_.bc.friction && setup_.bc.friction->id == id;
    if (tr == setup_.bc.traction.end() && !is_friction) continue;
    ffv.reinit(cell, face);
    if (tr != setup_.bc.traction.end()) {
      for (unsigned int q = 0; q < s.nfq; ++q) {
        const Vec2 t = tr->second(ffv.quadrature_point(q), ffv.normal_vector(q));
        for (unsigned int i = 0; i < s.dpc; ++i)
          s.cr(i) -= t * ffv[kVelocity].value(i, q) * ffv.JxW(q);
      }
    }
    if (is_friction) add_friction_terms(s, state, matrix, newton);
  }
}

/// The regularised Coulomb friction int mu_w p+ g(s) (t_w.v) on the face of sc.ffv and its
/// Jacobian (Newton) or secant slip coefficient (Picard).
void FlowProblem::add_friction_terms(AssemblyScratch& sc, const VectorType& state, bool matrix,
                                     bool newton) const {
  const FEFaceValues<dim>& ffv = sc.ffv;
  const std::vector<Vec2>& fu = sc.fu;
  const std::vector<double>& fp = sc.fp;
  const unsigned int dpc = sc.dpc;
  const FrictionWall& w = *setup_.bc.friction;
  ffv[kVelocity].get_function_values(state, sc.fu);
  ffv[kPressure].get_function_values(state, sc.fp);
  const double eps = w.slip_scale;
  const bool law = w.v0 > 0;  // the slip law; otherwise the constant mu_w (unchanged arithmetic)
  for (unsigned int q = 0; q < sc.nfq; ++q) {
    const Vec2 n = ffv.normal_vector(q);
    const Vec2 tw({-n[1], n[0]});
    const Vec2 uw = w.wall_velocity ? w.wall_velocity(ffv.quadrature_point(q)) : Vec2();
    const double s = (fu[q] - uw) * tw;
    const double pp = std::max(fp[q], 0.0);
    const double r = std::sqrt(s * s + eps * eps);
    const double g = s / r, dg = eps * eps / (r * r * r);
    // mu(s) = mu_a + (mu_b - mu_a) |s| / (|s| + v0); d(mu g)/ds = mu dg + mu' g (the law)
    const double as = std::fabs(s);
    const double mu = law ? w.mu_a + (w.mu_b - w.mu_a) * as / (as + w.v0) : w.mu_w;
    const double dmu =
        law ? (w.mu_b - w.mu_a) * w.v0 / ((as + w.v0) * (as + w.v0)) * (s < 0 ? -1.0 : 1.0) : 0;
    const double dmug = law ? mu * dg + dmu * g : dg;  // the law folds mu in; else x mu_w below
    const double gp = law ? mu * g : g;
    const double outer = law ? 1.0 : w.mu_w;
    for (unsigned int i = 0; i < dpc; ++i) {
      const double ti = tw * ffv[kVelocity].value(i, q);
      sc.cr(i) += mu * pp * g * ti * ffv.JxW(q);
      if (!matrix) continue;
      for (unsigned int j = 0; j < dpc; ++j) {
        const double tj = tw * ffv[kVelocity].value(j, q);
        double a;
        if (newton)
          a = pp * dmug * tj + (fp[q] > 0 ? gp * ffv[kPressure].value(j, q) : 0.0);
        else
          a = (law ? mu * pp : pp) / r * tj;  // Picard: secant slip coefficient
        sc.cm(i, j) += outer * a * ti * ffv.JxW(q);
      }
    }
  }
}

/// The boundary part of the dilatant continuity, int q delta u.n, on the boundary @p face of
/// @p cell (none on periodic ends: there the two sides' terms are one interior face's, which
/// the volume form already holds). delta from the law's I on the face, as in the volume.
void FlowProblem::add_dilatancy_flux(AssemblyScratch& s,
                                     const DoFHandler<dim>::active_cell_iterator& cell,
                                     const DoFHandler<dim>::face_iterator& face,
                                     const VectorType& state, bool matrix, bool newton) const {
  for (const auto& [b1, b2] : setup_.bc.periodic_x)
    if (face->boundary_id() == b1 || face->boundary_id() == b2) return;
  FEFaceValues<dim>& dfv = s.dfv;
  dfv.reinit(cell, face);
  dfv[kVelocity].get_function_values(state, s.fu);
  dfv[kVelocity].get_function_symmetric_gradients(state, s.fsym);
  dfv[kPressure].get_function_values(state, s.fp);
  for (unsigned int q = 0; q < s.nfq; ++q) {
    s.face_in.strain_rate_sq[q] = 0.5 * (s.fsym[q] * s.fsym[q]);  // |D|^2 = D:D/2
    s.face_in.pressure[q] = s.fp[q];
  }
  setup_.viscosity->evaluate(s.face_in, s.face_out);
  const DilatancyLaw& law = *setup_.dilatancy;
  for (unsigned int q = 0; q < s.nfq; ++q) {
    const double I = s.face_out.inertial_number[q];
    const double delta = law.deficit(I), JxW = dfv.JxW(q);
    const double ddelta_dI = newton ? law.slope(I) : 0.0;
    if (delta == 0 && ddelta_dI == 0) continue;
    const Vec2 n = dfv.normal_vector(q);
    const double un = s.fu[q] * n;
    for (unsigned int i = 0; i < s.dpc; ++i) {
      const double qi = dfv[kPressure].value(i, q);
      if (qi == 0) continue;
      s.cr(i) += delta * un * qi * JxW;
      if (!matrix) continue;
      for (unsigned int j = 0; j < s.dpc; ++j) {
        double a = delta * (dfv[kVelocity].value(j, q) * n);
        if (ddelta_dI != 0) {  // through delta
          const double D_Dj = s.fsym[q] * dfv[kVelocity].symmetric_gradient(j, q);
          a += ddelta_dI * un *
               (s.face_out.dI_dstrain_sq[q] * D_Dj +
                s.face_out.dI_dpressure[q] * dfv[kPressure].value(j, q));
        }
        s.cm(i, j) += a * qi * JxW;
      }
    }
  }
}

/// The cell's local residual and matrices into the global ones (s.idx set): with the zero
/// constraints, or, in reaction mode, the residual alone and unconstrained.
void FlowProblem::distribute_cell(const AssemblyScratch& s, MatrixType* matrix,
                                  VectorType& residual, bool reaction_mode,
                                  MatrixType* schur_mass) const {
  if (reaction_mode) {
    residual.add(s.idx, s.cr);  // entries of other ranks travel at compress()
  } else if (matrix) {
    zero_constraints_.distribute_local_to_global(s.cm, s.cr, s.idx, *matrix, residual);
    if (schur_mass) zero_constraints_.distribute_local_to_global(s.cmass, s.idx, *schur_mass);
  } else {
    zero_constraints_.distribute_local_to_global(s.cr, s.idx, residual);
  }
}
}  // namespace grainlift::continuum::internal
