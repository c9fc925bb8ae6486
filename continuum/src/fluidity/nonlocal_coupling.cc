// CylinderProblem::solve_nonlocal_fluidity(): the nonlocal granular fluidity model (Kamrin &
// Koval 2012) on the cylinder problem, by splitting, on every nested level (each from the
// coarser level's converged g, flow and table; the coarsest from the local mu(I) state):
//
//   1. mu = |tau| / p and p at the quadrature points of the current flow (the local law's at
//      the first iteration);
//   2. g from  g - xi(mu)^2 Laplacian(g) = g_loc(mu, p)  (FluidityProblem, Q2 on the flow's
//      mesh; zero flux on every boundary, the intruder's included), Anderson-mixed in log g
//      with the previous iterates;
//   3. the flow with g = g_loc(mu) + (g_k - g_loc(mu_prev)): the local part at the flow's own
//      stress ratio, the nonlocal excess held (FluidityViscosity's implicit form; Newton from
//      the previous flow; a step that fails is retried with half the fluidity's step). At the
//      fixed point eta = p+ / g_k. Holding all of g instead (eta = p+ / g_k) made the splitting
//      a Picard iteration of the local law's stiff dependence on the strain rate: on the demo
//      at A = 0.21 it wandered for 44-60 iterations or failed;
//
// until the force and the torque move by less than the tolerance in two iterations running
// (|g_k - g_(k-1)| / |g_k| is reported). g_loc is the inverse of Jop's law, I(mu), capped at
// I = 1, and g_loc = gamma_dot / mu = I sqrt(p / rho_s) / (d mu); with xi -> 0, g = g_loc and
// eta = p / g_loc = mu(I) p / gamma_dot, the local law (up to I = 1).
//
// Measured on the demo at refinement 3 (A 0.206, Omega 2, one thread, AVX-512): on the finest
// level alone, from the local law's state, 15 iterations (142 s at 4b1dca6); nested, 39 + 6 +
// 6 + 3 iterations at levels 0-3 (11.7 s; the local law 7.1 s). Mixing in g instead of log g
// (floored at g_min) took 15 + 7 + 11 + 4 (14.8 s).
#include <deal.II/fe/fe_values.h>

#include <algorithm>
#include <array>
#include <deque>
#include <cmath>
#include <sstream>
#include <utility>
#include <vector>

#include "cylinder_problem.h"
#include "grainlift/shared/rheology/fluidity_law.h"
#include "quadrature_rheology.h"

namespace grainlift::continuum::internal {

using namespace dealii;

namespace {

/// g_loc (1/s) at stress ratio @p mu and pressure @p p (Pa): the shared law
/// (fluidity_law.h), the inverse of Jop's law capped at I = kMaxLocalFluidityInertial.
/// Uncapped (or capped at 1000 I0) its pole at mu_2 made the splitting swing between
/// g -> infinity and g -> 0 where the flow's mu = gamma_dot / g passed mu_2 (|dg|/|g| about 1
/// after 60 iterations on the spinning-cylinder test); Kamrin & Koval's linearised law
/// I = (mu - mu_s) / b, b = (mu_2 - mu_s) / I0, has no pole but gives g below the local
/// solution's where I is not small, and the first flow solve from the local state did not
/// converge (same test).
double local_fluidity(double mu, double p, const RheologyParams& r) {
  return grainlift::local_fluidity(
      mu, p, {r.mu_s, r.mu_2, r.I0, r.solid_density, r.grain_diameter});
}

/// Anderson mixing (Walker & Ni, SIAM J. Numer. Anal. 49, 1715, 2011) of the fixed point
/// g = G(g): with the last m differences of the iterates (dX) and of the residuals
/// f = G(g) - g (dF), gamma minimises |f - dF gamma| and
///     g <- g + w f - (dX + w dF) gamma,
/// which is the relaxed step g + w f when m = 0. On the demo the plain relaxed iteration of g
/// oscillated (w = 0.5: |dg|/|g| between 0.5 and 1.1 after 40 iterations) or crept (w = 0.2:
/// 0.023 after 40), and the plain relaxed iteration of log g diverged at Omega 0 (w = 0.3:
/// the flow's Newton failed at iteration 3) (with the lagged flow step of a546042).
class AndersonMixing {
 public:
  AndersonMixing(unsigned int depth, double relaxation) : m_(depth), w_(relaxation) {}

  /// Forgets the history (the next step is the relaxed one).
  void restart() {
    dX_.clear();
    dF_.clear();
    have_previous_ = false;
  }

  /// One step from the iterate @p g and its residual @p f = G(g) - g; @p g is updated.
  void step(Vector<double>& g, const Vector<double>& f) {
    if (have_previous_) {
      dX_.push_back(g);
      dX_.back() -= g_prev_;
      dF_.push_back(f);
      dF_.back() -= f_prev_;
      if (dX_.size() > m_) {
        dX_.pop_front();
        dF_.pop_front();
      }
    }
    g_prev_ = g;
    f_prev_ = f;
    have_previous_ = true;
    const std::vector<double> gamma = least_squares(f);
    g.add(w_, f);
    for (std::size_t i = 0; i < gamma.size(); ++i) {
      g.add(-gamma[i], dX_[i]);
      g.add(-w_ * gamma[i], dF_[i]);
    }
  }

 private:
  /// gamma of the normal equations (dF^T dF + lambda I) gamma = dF^T f, lambda a relative 1e-10
  /// (Gaussian elimination with partial pivoting: m <= 5).
  std::vector<double> least_squares(const Vector<double>& f) const {
    const std::size_t n = dF_.size();
    std::vector<std::vector<double>> a(n, std::vector<double>(n + 1));
    double trace = 0;
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < n; ++j) a[i][j] = dF_[i] * dF_[j];
      a[i][n] = dF_[i] * f;
      trace += a[i][i];
    }
    for (std::size_t i = 0; i < n; ++i) a[i][i] += 1e-10 * trace + 1e-300;
    for (std::size_t c = 0; c < n; ++c) {
      std::size_t piv = c;
      for (std::size_t r = c + 1; r < n; ++r)
        if (std::abs(a[r][c]) > std::abs(a[piv][c])) piv = r;
      std::swap(a[c], a[piv]);
      for (std::size_t r = c + 1; r < n; ++r) {
        const double factor = a[r][c] / a[c][c];
        for (std::size_t k = c; k <= n; ++k) a[r][k] -= factor * a[c][k];
      }
    }
    std::vector<double> x(n);
    for (std::size_t i = n; i-- > 0;) {
      double v = a[i][n];
      for (std::size_t k = i + 1; k < n; ++k) v -= a[i][k] * x[k];
      x[i] = v / a[i][i];
    }
    return x;
  }

  std::size_t m_;
  double w_;
  std::deque<Vector<double>> dX_, dF_;
  Vector<double> g_prev_, f_prev_;
  bool have_previous_ = false;
};

constexpr unsigned int kAndersonDepth = 5;
/// Newton steps a flow step may take (5-18 where it converges, demo refinements 2 and 3);
/// one that needs more is retried with half the fluidity's step
constexpr int kFlowStepIterations = 25;

/// One step of @p mixing from the iterate @p g to its image @p image = G(g), in log g (g spans
/// decades and must stay positive; both floored at FluidityViscosity's @p g_min); the history
/// restarts after a step that made the residual grow more than twofold (@p last_residual).
void mix_in_log(AndersonMixing& mixing, Vector<double>& g, const Vector<double>& image,
                double g_min, double& last_residual) {
  Vector<double> x(g.size()), f(g.size());
  for (unsigned int i = 0; i < g.size(); ++i) {
    x[i] = std::log(std::max(g[i], g_min));
    f[i] = std::log(std::max(image[i], g_min)) - x[i];
  }
  if (f.l2_norm() > 2 * last_residual) mixing.restart();
  last_residual = f.l2_norm();
  mixing.step(x, f);
  for (unsigned int i = 0; i < x.size(); ++i) g[i] = std::exp(x[i]);
}

/// The coefficients of the L2 projection of @p table (the flow step's g_loc at the points of
/// every cell) on g's space: g_loc the table, xi a thousandth of a grain @p d (the gradient
/// term ~(xi / h)^2 < 1e-5 of the mass term on these meshes; xi = 0 divides by zero).
void projection_coefficients(const fluidity::internal::CellIterator& cell,
                             const std::vector<double>& table, double d,
                             fluidity::internal::CellCoefficients& c) {
  for (unsigned int q = 0; q < c.xi.size(); ++q) {
    c.xi[q] = 1e-3 * d;
    c.g_loc[q] = table[cell->active_cell_index() * c.xi.size() + q];
  }
}

}  // namespace

void CylinderProblem::solve_nonlocal_fluidity() {
  const RheologyParams& r = config_.rheology;
  const NonlocalParams& nl = config_.nonlocal;
  const double xi_max = nl.xi_max > 0 ? nl.xi_max : 2 * R_;
  // a nested level after a coarser one's: g interpolated from it (refine_flagged_cells()) and
  // the flow its interpolated state, a near pair; otherwise from the local law's flow
  const bool carried = fluidity_ && fluidity_g_.size() == fluidity_->dof_handler().n_dofs();
  out_.nonlocal_settled = false;
  // the flow's state and model seen by the fluidity's coefficients (the local law first)
  const ViscosityModel* flow_model = &rheology_;
  VectorType ghosted = problem_->ghosted(problem_->solution());
  fluidity::internal::FluiditySetup fs;
  std::unique_ptr<FEValues<dim>> flow_values;
  std::unique_ptr<QuadratureRheology> qr;
  std::vector<double> g_loc_points;  // the flow step's table (fluidity_viscosity.h)
  bool projecting = false;  // the table's L2 projection (projection_coefficients())
  fs.coefficients = [&](const fluidity::internal::CellIterator& cell,
                        const std::vector<fluidity::internal::Point2>&,
                        fluidity::internal::CellCoefficients& c) {
    if (projecting) return projection_coefficients(cell, g_loc_points, r.grain_diameter, c);
    const typename DoFHandler<dim>::active_cell_iterator flow_cell(
        &mesh_->tria(), cell->level(), cell->index(), &problem_->dof_handler());
    flow_values->reinit(flow_cell);
    qr->evaluate(*flow_values, ghosted, *flow_model);
    for (unsigned int q = 0; q < c.xi.size(); ++q) {
      const double p = qr->pressure[q];
      const double rate = std::sqrt(std::max(qr->in.strain_rate_sq[q], 0.0));
      const double mu = p > 0 ? 2 * qr->out.viscosity[q] * rate / p : 0;
      c.xi[q] = grainlift::cooperativity_length(mu, r.mu_s, nl.amplitude, r.grain_diameter, xi_max);
      c.g_loc[q] = local_fluidity(mu, p, r);
      // the flow step's table: g_loc at the model's own stress ratio (fluidity_viscosity.h)
      g_loc_points[cell->active_cell_index() * c.xi.size() + q] =
          local_fluidity(qr->out.friction[q], p, r);
    }
  };
  fluidity_ = std::make_unique<fluidity::internal::FluidityProblem>(mesh_->tria(), 2, fs);
  fluidity_->setup_system();
  flow_values = std::make_unique<FEValues<dim>>(
      problem_->mapping(), problem_->dof_handler().get_fe(), fluidity_->quadrature(),
      update_values | update_gradients);
  qr = std::make_unique<QuadratureRheology>(fluidity_->quadrature().size());
  g_loc_points.assign(mesh_->tria().n_active_cells() * fluidity_->quadrature().size(), 0.0);
  // carried: the same mesh and element as the g carried over, the same numbering
  if (!carried) fluidity_g_.reinit(fluidity_->dof_handler().n_dofs());
  fluidity_viscosity_ =
      std::make_unique<FluidityViscosity>(r, fluidity_->dof_handler(), fluidity_g_);
  if (carried) {
    // the flow's own stress ratio needs the coarser level's table too: the lagged form's,
    // gamma_dot / g, sent g_loc to its cap where g_loc is steep (|G(g) - g| / |g| = 0.8)
    g_loc_points = carried_table();
    fluidity_viscosity_->set_local_fluidity(fluidity_->quadrature(), g_loc_points);
    flow_model = fluidity_viscosity_.get();
  }
  AndersonMixing mixing(kAndersonDepth, nl.relaxation);
  double last_residual = 0;
  int settled_runs = 0;
  std::array<double, 3> last_force = {0, 0, 0};
  for (int k = 1; k <= nl.max_iterations; ++k) {
    fluidity_->assemble_system();
    fluidity_->solve();
    Vector<double> f(fluidity_->solution());  // G(g_(k-1)) - g_(k-1)
    f -= fluidity_g_;
    out_.nonlocal_change = f.l2_norm() / std::max(fluidity_->solution().l2_norm(), 1e-300);
    out_.nonlocal_iterations = k;
    const Vector<double> g_before = fluidity_g_;
    const VectorType flow_before = problem_->solution();
    if (k == 1 && !carried) {
      fluidity_g_ = fluidity_->solution();  // from g = 0: the first fluidity whole
    } else {
      mix_in_log(mixing, fluidity_g_, fluidity_->solution(), fluidity_viscosity_->g_min(),
                 last_residual);
    }
    flow_model = fluidity_viscosity_.get();
    // Picard steps in the flow's first two steps from the local law's state only
    const bool with_picard = !carried && k <= 2;
    bool converged = nonlocal_flow_step(k, with_picard, g_loc_points);
    if (!converged && (k > 1 || carried)) {
      mixing.restart();
      converged = nonlocal_flow_step_halved(k, with_picard, g_loc_points, g_before, flow_before);
    }
    if (!converged) return;
    ghosted = problem_->ghosted(problem_->solution());
    settled_runs = nonlocal_forces_still(last_force) ? settled_runs + 1 : 0;
    if (settled_runs >= 2) {
      out_.nonlocal_settled = true;
      break;
    }
  }
  // the last flow step's table, projected on g's space, goes with g to the next level
  projecting = true;
  fluidity_->assemble_system();
  fluidity_->solve();
  fluidity_table_ = fluidity_->solution();
}

bool CylinderProblem::nonlocal_flow_step_halved(int k, bool with_picard,
                                                const std::vector<double>& g_loc,
                                                const Vector<double>& g_before,
                                                const VectorType& flow_before) {
  // a flow step that fails (the demo at refinement 3 without nested levels: a stall at
  // |R|/|R0| ~ 7e-4, with Picard steps too): the fluidity's step halved, from the previous flow
  for (int half = 0; half < 4; ++half) {
    say("continuum: the flow step did not converge; again with half the fluidity's step");
    fluidity_g_ += g_before;
    fluidity_g_ *= 0.5;
    problem_->solution() = flow_before;
    if (nonlocal_flow_step(k, with_picard, g_loc)) return true;
  }
  return false;
}

bool CylinderProblem::nonlocal_forces_still(std::array<double, 3>& last) {
  // the force and the torque moved by less than the tolerance (of |F| and |T|)
  const double tolerance = config_.nonlocal.tolerance;
  const double dF = std::hypot(out_.fx - last[0], out_.fy - last[1]);
  const double F = std::hypot(out_.fx, out_.fy), dT = std::abs(out_.torque - last[2]);
  const double T = std::max(std::abs(out_.torque), F * R_);  // a torque scale: |F| R
  last = {out_.fx, out_.fy, out_.torque};
  out_.nonlocal_force_change = std::max(dF / std::max(F, 1e-300), dT / std::max(T, 1e-300));
  return dF <= tolerance * F && dT <= tolerance * T;
}

std::vector<double> CylinderProblem::carried_table() const {
  const unsigned int nq = fluidity_->quadrature().size();
  std::vector<double> table(mesh_->tria().n_active_cells() * nq), values(nq);
  FEValues<dim> fev(fluidity_->mapping(), fluidity_->dof_handler().get_fe(),
                    fluidity_->quadrature(), update_values);
  for (const auto& cell : fluidity_->dof_handler().active_cell_iterators()) {
    fev.reinit(cell);
    fev.get_function_values(fluidity_table_, values);
    std::copy(values.begin(), values.end(), table.begin() + cell->active_cell_index() * nq);
  }
  return table;
}

bool CylinderProblem::nonlocal_flow_step(int k, bool with_picard, std::vector<double> g_loc) {
  // the flow step takes g_loc at its own stress ratio, the excess g - g_loc held
  fluidity_viscosity_->set_local_fluidity(fluidity_->quadrature(), std::move(g_loc));
  problem_->set_viscosity(fluidity_viscosity_.get());
  // Newton from the first step once the flow is near (Picard steps took a third of the time),
  // at most kFlowStepIterations steps: a failing step (the demo at refinement 3 without the
  // nested levels: a stall at |R|/|R0| ~ 7e-4, with Picard steps too) is retried by the
  // caller with half the fluidity's step. (Again in the lagged form instead, eta = p+ / g_k,
  // threw the splitting back: 28 iterations and more, |dg|/|g| up to 4.)
  NonlinearSettings step_settings = setup_.nonlinear;
  if (!with_picard) step_settings.picard_iterations = 0;
  // the first step of a level (from the interpolated flow) may take the whole count
  if (!with_picard && k > 1) step_settings.max_iterations = kFlowStepIterations;
  problem_->solve_nonlinear(step_settings);
  out_.residual_stage.resize(problem_->report().residual_history.size(), stage_number_);
  ++stage_number_;
  std::ostringstream os;
  compute_boundary_outputs();
  os << "continuum: nonlocal fluidity iteration " << k << ": |dg|/|g| = "
     << out_.nonlocal_change << ", flow " << (problem_->report().converged ? "" : "not ")
     << "converged, force (" << out_.fx << ", " << out_.fy << ") N/m, torque " << out_.torque
     << " N";
  say(os.str());
  return problem_->report().converged;
}

}  // namespace grainlift::continuum::internal
