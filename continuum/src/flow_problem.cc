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
#include <deal.II/lac/sparse_direct.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/vector_tools.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace grainlift::continuum::internal {

using namespace dealii;

namespace {

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
  DoFRenumbering::Cuthill_McKee(dof_handler_);
  DoFRenumbering::component_wise(dof_handler_);  // u_x, then u_y, then p
  make_constraints(nonzero_constraints_, false);
  make_constraints(zero_constraints_, true);
  DynamicSparsityPattern dsp(dof_handler_.n_dofs());
  DoFTools::make_sparsity_pattern(dof_handler_, dsp, zero_constraints_, false);
  sparsity_.copy_from(dsp);
  system_matrix_.reinit(sparsity_);
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
  return assemble_impl(state, matrix ? &system_matrix_ : nullptr, newton, residual, false);
}

double FlowProblem::assemble_impl(const Vector<double>& state, SparseMatrix<double>* matrix,
                                  bool newton, Vector<double>& residual,
                                  bool reaction_mode) const {
  residual.reinit(dof_handler_.n_dofs());
  if (matrix) *matrix = 0;
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
    } else {
      zero_constraints_.distribute_local_to_global(cr, idx, residual);
    }
  }
  return residual.l2_norm();
}

void FlowProblem::solve(const Vector<double>& residual, Vector<double>& update) {
  SparseDirectUMFPACK direct;
  direct.initialize(system_matrix_);
  update = residual;
  direct.solve(update);
  update *= -1.0;
  zero_constraints_.distribute(update);
  ++report_.linear_solves;
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
  const int max_it = nonlinear ? nl.max_iterations : 1;
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
      solve(res, upd);
      alpha = 1.0;
      bool accepted = false;
      for (int ls = 0; ls <= 10; ++ls) {
        trial = solution_;
        trial.add(alpha, upd);
        rt = assemble_system(trial, false, false, trial_res);
        // Picard steps are fixed-point steps, not descent directions of |R|: taken in full.
        if (std::isfinite(rt) &&
            (merit(trial_res) < (1 - 1e-4 * alpha) * m0 || !nonlinear || !newton)) {
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
  if (!nonlinear && std::isfinite(r)) report_.converged = true;  // one exact direct solve
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
  const auto counts = DoFTools::count_dofs_per_fe_component(dof_handler_);
  ForceTorque ft;
  for (const auto i : bd) {
    const unsigned int c = i < counts[0] ? 0 : 1;
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
