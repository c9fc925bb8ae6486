// CylinderProblem::solve_nonlocal_fluidity(): the nonlocal granular fluidity model (Kamrin &
// Koval 2012) on the cylinder problem, by splitting from the converged local mu(I) state:
//
//   1. mu = |tau| / p and p at the quadrature points of the current flow (the local law's at
//      the first iteration);
//   2. g from  g - xi(mu)^2 Laplacian(g) = g_loc(mu, p)  (FluidityProblem, Q2 on the flow's
//      mesh; zero flux on every boundary, the intruder's included), Anderson-mixed in log g
//      with the previous iterates;
//   3. the flow with g = g_loc(mu) + (g_k - g_loc(mu_prev)): the local part at the flow's own
//      stress ratio, the nonlocal excess held (FluidityViscosity's implicit form; Newton from
//      the previous flow). At the fixed point eta = p+ / g_k. Holding all of g instead (eta =
//      p+ / g_k) made the splitting a Picard iteration of the local law's stiff dependence on
//      the strain rate: on the demo at A = 0.21 it wandered for 44-60 iterations or failed;
//
// until the force and the torque move by less than the tolerance in two iterations running
// (|g_k - g_(k-1)| / |g_k| is reported). g_loc is the inverse of Jop's law, I(mu), capped at
// I = 1, and g_loc = gamma_dot / mu = I sqrt(p / rho_s) / (d mu); with xi -> 0, g = g_loc and
// eta = p / g_loc = mu(I) p / gamma_dot, the local law (up to I = 1).
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
/// the flow's Newton failed at iteration 3).
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

}  // namespace

void CylinderProblem::solve_nonlocal_fluidity() {
  const RheologyParams& r = config_.rheology;
  const NonlocalParams& nl = config_.nonlocal;
  const double xi_max = nl.xi_max > 0 ? nl.xi_max : 2 * R_;
  // the flow's state and model seen by the fluidity's coefficients (the local law first)
  const ViscosityModel* flow_model = &rheology_;
  VectorType ghosted = problem_->ghosted(problem_->solution());
  fluidity::internal::FluiditySetup fs;
  std::unique_ptr<FEValues<dim>> flow_values;
  std::unique_ptr<QuadratureRheology> qr;
  std::vector<double> g_loc_points;  // the flow step's table (fluidity_viscosity.h)
  fs.coefficients = [&](const fluidity::internal::CellIterator& cell,
                        const std::vector<fluidity::internal::Point2>&,
                        fluidity::internal::CellCoefficients& c) {
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
  fluidity_g_.reinit(fluidity_->dof_handler().n_dofs());
  fluidity_viscosity_ =
      std::make_unique<FluidityViscosity>(r, fluidity_->dof_handler(), fluidity_g_);

  // the mixing works on log g (g spans decades and must stay positive); g_min the floor of
  // FluidityViscosity
  const double g_floor = fluidity_viscosity_->g_min();
  auto log_of = [&](const Vector<double>& g) {
    Vector<double> x(g.size());
    for (unsigned int i = 0; i < g.size(); ++i) x[i] = std::log(std::max(g[i], g_floor));
    return x;
  };
  AndersonMixing mixing(kAndersonDepth, nl.relaxation);
  Vector<double> x;  // log g of the iterate
  double last_residual = 0;
  std::array<double, 3> last_force = {0, 0, 0};
  int settled_runs = 0;
  for (int k = 1; k <= nl.max_iterations; ++k) {
    fluidity_->assemble_system();
    fluidity_->solve();
    Vector<double> change(fluidity_->solution());  // G(g_(k-1)) - g_(k-1)
    change -= fluidity_g_;
    out_.nonlocal_change = change.l2_norm() / std::max(fluidity_->solution().l2_norm(), 1e-300);
    out_.nonlocal_iterations = k;
    if (k == 1) {
      fluidity_g_ = fluidity_->solution();  // from g = 0: the first fluidity whole
      x = log_of(fluidity_g_);
    } else {
      Vector<double> f = log_of(fluidity_->solution());
      f -= x;
      // a step that made the residual grow much: the history misleads, start it again
      if (f.l2_norm() > 2 * last_residual) mixing.restart();
      last_residual = f.l2_norm();
      mixing.step(x, f);
      for (unsigned int i = 0; i < x.size(); ++i) fluidity_g_[i] = std::exp(x[i]);
    }
    flow_model = fluidity_viscosity_.get();
    const bool converged = nonlocal_flow_step(k, g_loc_points);
    if (!converged) return;
    ghosted = problem_->ghosted(problem_->solution());
    // settled: the force and the torque moved by less than the tolerance (of |F| and |T|)
    // in two iterations running
    const double dF = std::hypot(out_.fx - last_force[0], out_.fy - last_force[1]);
    const double F = std::hypot(out_.fx, out_.fy), dT = std::abs(out_.torque - last_force[2]);
    const double T = std::max(std::abs(out_.torque), F * R_);  // a torque scale: |F| R
    const bool still = dF <= nl.tolerance * F && dT <= nl.tolerance * T;
    settled_runs = still ? settled_runs + 1 : 0;
    last_force = {out_.fx, out_.fy, out_.torque};
    out_.nonlocal_force_change = std::max(dF / std::max(F, 1e-300), dT / std::max(T, 1e-300));
    if (settled_runs >= 2) {
      out_.nonlocal_settled = true;
      return;
    }
  }
}

bool CylinderProblem::nonlocal_flow_step(int k, std::vector<double> g_loc) {
  // the flow step takes g_loc at its own stress ratio, the excess g - g_loc held
  fluidity_viscosity_->set_local_fluidity(fluidity_->quadrature(), std::move(g_loc));
  problem_->set_viscosity(fluidity_viscosity_.get());
  // Newton from the first step once the flow is near (Picard steps took a third of the time);
  // where that fails (the demo at refinement 3, iteration 7: stalled at 3e-4), the step again
  // from the previous flow with the Picard steps. (Again in the lagged form instead, eta =
  // p+ / g_k, threw the splitting back: 28 iterations and more, |dg|/|g| up to 4.)
  NonlinearSettings step_settings = setup_.nonlinear;
  if (k > 2) step_settings.picard_iterations = 0;
  const bool retry = step_settings.picard_iterations == 0;
  const VectorType previous = retry ? problem_->solution() : VectorType();
  problem_->solve_nonlinear(step_settings);
  if (!problem_->report().converged && retry) {
    say("continuum: the flow step without Picard steps did not converge; again with them");
    problem_->solution() = previous;
    problem_->solve_nonlinear(setup_.nonlinear);
  }
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
