// FlowProblem's nonlinear iterations: Picard (eta frozen), then Newton with a backtracking
// line search on a Jacobi-weighted merit (see solve_nonlinear()).
#include <algorithm>
#include <cmath>
#include <deque>
#include <sstream>

#include "flow_problem.h"
#include "linear_algebra_utilities.h"

namespace grainlift::continuum::internal {

using namespace dealii;

namespace {
/// Largest growth of the plain residual |R| that a Newton step may cause (see solve_nonlinear).
constexpr double kResidualGrowth = 1.5;
}  // namespace

/// The vectors of the nonlinear iterations (owned entries): the residual, the update, the
/// trial state of the line search and its residual, the merit's Jacobi weights.
struct FlowProblem::NonlinearWork {
  VectorType res, upd, trial, trial_res, weight;
};

/// One nonlinear step: Newton or Picard as taken, its step length, its residual |R| and the
/// Krylov iterations of its linear solve.
struct FlowProblem::NonlinearStep {
  bool newton = false;
  double alpha = 1.0, residual = 0;
  int linear_its = 0;
};

void FlowProblem::solve_nonlinear(const NonlinearSettings& nl) {
  NonlinearWork w{make_vector(), make_vector(), make_vector(), make_vector(), make_vector()};
  tangent_floor_ = nl.tangent_floor;
  double r = assemble_system(solution_, false, false, w.res);
  report_.converged = false;
  report_.message.clear();
  traction_id_ = -1;
  // the tolerance is relative to the residual of the initial guess of the first call
  if (report_.initial_residual <= 0) report_.initial_residual = r;
  const double r_ref = report_.initial_residual;
  const double r0 = r;
  const bool nonlinear =
      setup_.viscosity->is_nonlinear() || setup_.inertia_density > 0 || setup_.bc.friction;
  log_nonlinear_start(r0);
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
  std::deque<double> log_steps;  // log2 of the last Newton steps' lengths (nl.stall_window)
  for (int it = 0; it < max_it; ++it) {
    if (!newton_phase && it >= nl.picard_iterations &&
        (r < 0.5 * r0 || it >= 4 * std::max(nl.picard_iterations, 1)))
      newton_phase = true;
    const NonlinearStep step = nonlinear_step(w, newton_phase, nonlinear, r, r_ref);
    solution_ = w.trial;
    r = step.residual;
    (step.newton ? report_.newton_steps : report_.picard_steps) += 1;
    report_.residual_history.push_back(r / r_ref);
    log_nonlinear_step(step, it, r / r_ref, iterative);
    if (!std::isfinite(r)) {
      report_.message = "nonlinear residual is not finite";
      break;
    }
    if (r <= nl.relative_tolerance * r_ref || r <= nl.absolute_tolerance) {
      report_.converged = true;
      break;
    }
    if (stalled(nl, newton_phase, step, log_steps)) {
      std::ostringstream os;
      os << "stalled: the last " << nl.stall_window << " Newton steps' lengths average (geometric"
         << " mean) at most " << nl.stall_step << ", |R|/|R0| = " << r / r_ref;
      report_.message = os.str();
      break;
    }
  }
  if (!nonlinear && !iterative && std::isfinite(r))
    report_.converged = true;  // one exact direct solve
  report_.final_residual = r;
  report_nonconvergence(r / r_ref);
}

/// Whether the Newton phase has stalled by NonlinearSettings::stall_window: @p log_steps keeps
/// log2 of the last Newton-phase step lengths (a Newton step redone as Picard: log2 1/1024).
bool FlowProblem::stalled(const NonlinearSettings& nl, bool newton_phase,
                          const NonlinearStep& step, std::deque<double>& log_steps) const {
  if (nl.stall_window <= 0 || !newton_phase) return false;
  log_steps.push_back(step.newton ? std::log2(step.alpha) : -10.0);
  if (static_cast<int>(log_steps.size()) > nl.stall_window) log_steps.pop_front();
  if (static_cast<int>(log_steps.size()) < nl.stall_window) return false;
  double sum = 0;
  for (const double l : log_steps) sum += l;
  return sum / nl.stall_window <= std::log2(nl.stall_step);
}

/// A Newton step from solution_ with its line search (@p newton), or a Picard step taken in
/// full, at |R| = @p r; a Newton step whose line search fails is redone as a Picard step. The
/// new state is left in w.trial.
FlowProblem::NonlinearStep FlowProblem::nonlinear_step(NonlinearWork& w, bool newton,
                                                       bool nonlinear, double r, double r_ref) {
  NonlinearStep step;
  step.newton = newton;
  for (int attempt = 0; attempt < 2; ++attempt) {
    assemble_system(solution_, true, step.newton, w.res);
    // Line-search merit: without inertia the Jacobi-weighted norm sum_i R_i^2 / |J_ii| (the
    // stiff, nearly rigid zones where eta ~ eta_max otherwise dominate |R| and force tiny
    // steps; 46 -> 28 Newton steps on the spinning cylinder at refinement 2). With inertia
    // the convective diagonal makes the weights unreliable and the plain |R| did better.
    const bool scaled = setup_.inertia_density == 0;
    jacobi_weights(w.weight);
    const double m0 = merit(w.res, w.weight, scaled);
    // inexact Newton: the linear residual only needs to be small against the nonlinear one;
    // forcing term 0.1 |R|/|R_0| (quadratic convergence is kept), at most 1e-3, at least 1e-10
    const double forcing =
        nonlinear ? std::clamp(0.1 * r / r_ref, 1e-10, 1e-3) : 1e-10;
    step.linear_its = solve(w.res, w.upd, forcing);
    const bool accepted = line_search(w, m0, scaled, r, nonlinear, step);
    if (accepted || !step.newton) break;
    step.newton = false;  // fall back to a full Picard step
  }
  return step;
}

/// The inverse diagonal 1/|J_ii| of system_matrix_'s velocity block (1 where it is 0), and 1
/// on the continuity rows: they have no diagonal to scale by (0 for an incompressible medium,
/// and for a dilatant one only d delta / dp, nearly 0 where p is large: weighted by its inverse
/// the depth sweep's 4 D case stalled in Picard steps); constrained rows carry no residual.
void FlowProblem::jacobi_weights(VectorType& weight) const {
  extract_diagonal(system_matrix_.block(0, 0), weight.block(0));
  for (auto& w : weight.block(0)) {
    const double d = std::abs(w);
    w = d > 0 ? 1.0 / d : 1.0;
  }
  weight.block(1) = 1.0;
}

/// The line search's merit of the residual @p v: sqrt(sum_i w_i v_i^2) when @p scaled, |v|
/// otherwise. Collective.
double FlowProblem::merit(const VectorType& v, const VectorType& weight, bool scaled) const {
  if (!scaled) return v.l2_norm();
  return std::sqrt(owned_sum(v, weight, [](double x, double w) { return w * x * x; }, comm_));
}

/// Backtracking from the full step along w.upd (halved down to 1/1024) until the merit falls
/// by Armijo's factor below @p m0 and |R| stays within kResidualGrowth of @p r (Picard steps
/// and linear problems: the full step); true when a step was accepted. step.alpha and
/// step.residual are those of the last trial, in w.trial.
bool FlowProblem::line_search(NonlinearWork& w, double m0, bool scaled, double r,
                              bool nonlinear, NonlinearStep& step) {
  step.alpha = 1.0;
  for (int ls = 0; ls <= 10; ++ls) {
    w.trial = solution_;
    w.trial.add(step.alpha, w.upd);
    step.residual = assemble_system(w.trial, false, false, w.trial_res);
    // Picard steps are fixed-point steps, not descent directions of |R|: taken in full.
    // The weighted merit can fall while |R| grows several-fold (seen at refinement 3: a
    // step taken at 1/8 raised |R| from 1.3 to 11 |R_0|, and the iteration never
    // recovered); a Newton step must also keep |R| within kResidualGrowth of its value.
    if (std::isfinite(step.residual) &&
        ((merit(w.trial_res, w.weight, scaled) < (1 - 1e-4 * step.alpha) * m0 &&
          step.residual <= kResidualGrowth * r) ||
         !nonlinear || !step.newton))
      return true;
    step.alpha *= 0.5;
  }
  return false;
}

/// The first line of a solve: mesh, dofs, ranks and the initial residual @p r0.
void FlowProblem::log_nonlinear_start(double r0) const {
  std::ostringstream os;
  os << "continuum: " << tria_.n_global_active_cells() << " cells, " << dof_handler_.n_dofs()
     << " dofs, initial residual " << r0;
  if (n_ranks() > 1) os << " (" << n_ranks() << " MPI ranks)";
  log(os.str());
}

/// One line per nonlinear step: its kind, |R|/|R0| (@p relative), step length, Krylov count.
void FlowProblem::log_nonlinear_step(const NonlinearStep& step, int it, double relative,
                                     bool iterative) const {
  std::ostringstream os;
  os << "continuum: " << (step.newton ? "newton" : "picard") << " step " << it + 1
     << "  |R|/|R0| = " << relative << "  step length " << step.alpha;
  if (iterative) os << "  fgmres iterations " << step.linear_its;
  log(os.str());
}

/// When the solve did not converge: the message with the last |R|/|R0| (@p relative) and
/// the residual history of the last 12 steps (stalled, oscillating or growing).
void FlowProblem::report_nonconvergence(double relative) {
  if (report_.converged) return;
  if (report_.message.empty()) {
    std::ostringstream os;
    os << "no convergence after " << report_.picard_steps + report_.newton_steps
       << " nonlinear iterations: |R|/|R0| = " << relative;
    report_.message = os.str();
  }
  std::ostringstream os;
  const auto& h = report_.residual_history;
  os << "; residual history |R|/|R0|" << (h.size() > 12 ? " (last 12)" : "") << ":";
  for (std::size_t k = h.size() > 12 ? h.size() - 12 : 0; k < h.size(); ++k) os << " " << h[k];
  report_.message += os.str();
}
}  // namespace grainlift::continuum::internal
