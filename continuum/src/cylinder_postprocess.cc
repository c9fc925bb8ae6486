// CylinderProblem's post-processing (cylinder_problem.h): the first-order gravity correction,
// the convergence report, the well-posedness check, forces and surface stresses on the
// intruder, the fields on the grid and the VTU output.
#include "cylinder_problem.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

namespace grainlift::continuum::internal {

using namespace dealii;

/// Linearised gravity: one Newton step from the base state of the problem with gravity; du_ is
/// the first-order correction.
void CylinderProblem::correct_for_gravity() {
  say("continuum: first-order gravity correction (one linear solve at the base state)");
  const auto t0 = std::chrono::steady_clock::now();
  const ProblemSetup with_gravity = make_setup(g_);
  corrected_ = std::make_unique<FlowProblem>(mesh_->tria(), with_gravity);
  corrected_->set_viscosity(&rheology_);
  corrected_->setup_system();
  corrected_->solution() = problem_->solution();
  if (with_gravity.bc.mean_pressure && setup_.bc.mean_pressure)
    // the pressure level with gravity: the base state shifted by the change of the top's
    // lithostatic pressure (a constant), so that it meets the constraint the update keeps
    corrected_->solution().block(1).add(with_gravity.bc.mean_pressure->value -
                                        setup_.bc.mean_pressure->value);
  corrected_base_ = corrected_->solution();
  VectorType residual;
  corrected_->assemble_system(corrected_->solution(), true, true, residual);
  corrected_->solve(residual, du_);
  std::ostringstream os;
  out_.correction_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  os << "continuum: gravity correction: |R_g(u_0)| = " << residual.l2_norm() << ", "
     << out_.correction_seconds << " s";
  say(os.str());
}

/// Convergence and work counts of the nonlinear solve (the base state when linearised).
void CylinderProblem::report_convergence() {
  const auto& rep = problem_->report();
  out_.converged = rep.converged;
  out_.message = rep.message;
  out_.picard_steps = rep.picard_steps;
  out_.newton_steps = rep.newton_steps;
  out_.nonlinear_iterations = rep.picard_steps + rep.newton_steps;
  out_.linear_iterations = rep.linear_solves;
  out_.krylov_iterations = rep.krylov_iterations;
  out_.worst_direct_residual = rep.worst_direct_residual;
  out_.initial_residual = rep.initial_residual;
  out_.final_residual = rep.initial_residual > 0 ? rep.final_residual / rep.initial_residual : 0;
  out_.residual_history = rep.residual_history;
  out_.cells = static_cast<int>(mesh_->tria().n_global_active_cells());
  out_.dofs = static_cast<int>(problem_->dof_handler().n_dofs());
}

void CylinderProblem::check_well_posedness() {
  // where the law is ill posed the solution depends on the mesh: say so
  const InertialRange w = well_posed_range(config_.rheology);
  const double radius = 0.5 * config_.intruder_diameter;
  const auto share = problem_->ill_posed_share(Point2(), radius, 1.25 * radius, w.high);
  out_.sheared_share = share[0];
  out_.ill_posed_share = share[1];
  out_.ill_posed_wall_share = share[2];
  if (out_.ill_posed_share > 0.05) {
    std::ostringstream os;
    os << "continuum: warning: in " << std::lround(100 * out_.ill_posed_share)
       << "% of the sheared medium (" << std::lround(100 * out_.sheared_share)
       << "% of the area) mu(I) is ill posed at the local I (Barker et al. 2015; Jop's law "
          "with these parameters only for "
       << w.low << " < I < " << w.high << "): the solution will change with the mesh. ";
    if (config_.rheology.regularisation == Regularisation::barker_gray)
      os << "Barker-Gray's branch removes the ill-posedness at low I only; here the flow is "
            "too fast (I > " << w.high
         << "): raise the confining pressure or lower the speeds (docs/continuum-model.md)";
    else
      os << "continuum.regularisation = \"barker_gray\" is well posed at low I "
            "(docs/continuum-model.md)";
    say(os.str());
  }
}

// ---- forces (consistent reaction on the hole; surface integral as a diagnostic) and the
// surface stresses at theta measured from V counter-clockwise, from the consistent traction
// (the reaction forces spread by the boundary mass matrix), which converges like the
// forces; sigma(grad u_h).n at the wall converges at rate < 2
void CylinderProblem::compute_boundary_outputs() {
  const std::size_t n_angles = config_.surface_theta.size();
  std::vector<double> v;
  if (!corrected_) {
    v = boundary_outputs(*problem_);
  } else {
    // First order throughout: the outputs are linear functionals of the residual, so they
    // are taken as S(u_0; g) + dS/du . du, the derivative by a central difference along du
    // (exact for the linear gravity terms; O(h^2) for the rheology, h = 1e-4).
    const VectorType u0 = corrected_base_;
    constexpr double h = 1e-4;
    const auto at = [&](double t) {
      corrected_->solution() = u0;
      corrected_->solution().add(t, du_);
      return boundary_outputs(*corrected_);
    };
    v = at(0);
    const std::vector<double> vp = at(h), vm = at(-h);
    for (std::size_t k = 0; k < v.size(); ++k) v[k] += (vp[k] - vm[k]) / (2 * h);
    corrected_->solution() = u0;  // fields and VTU: the corrected state u_0 + du
    corrected_->solution() += du_;
  }
  outputs_stage_ = stage_number_;
  out_.fx = v[0];
  out_.fy = v[1];
  out_.torque = v[2];
  out_.force_fx_surface = v[3];
  out_.force_fy_surface = v[4];
  out_.torque_surface = v[5];
  out_.sigma_n.assign(v.begin() + 6, v.begin() + 6 + n_angles);
  out_.sigma_t.assign(v.begin() + 6 + n_angles, v.end());
  {
    std::ostringstream os;
    os << "continuum: force (" << out_.fx << ", " << out_.fy << ") N/m, torque " << out_.torque
       << " N [surface integral (" << out_.force_fx_surface << ", " << out_.force_fy_surface
       << "), " << out_.torque_surface << "]";
    say(os.str());
  }
}

std::vector<double> CylinderProblem::boundary_outputs(const FlowProblem& fp) const {
  const double phi0 = speed_ > 0 ? std::atan2(V_[1], V_[0]) : 0.0;
  const std::size_t n_angles = config_.surface_theta.size();
  const auto reac = fp.reaction(kHole, Point2());
  const auto surf = fp.surface_integral(kHole, Point2());
  std::vector<double> v = {reac.fx, reac.fy, reac.torque, surf.fx, surf.fy, surf.torque};
  v.resize(6 + 2 * n_angles);
  for (std::size_t k = 0; k < n_angles; ++k) {
    const double phi = phi0 + config_.surface_theta[k];
    const Vec2 n_body({std::cos(phi), std::sin(phi)});  // outward normal of the intruder
    const Vec2 t = fp.consistent_traction(kHole, Point2(), phi);  // medium on intruder
    const Vec2 e_phi({-n_body[1], n_body[0]});           // counter-clockwise tangent
    v[6 + k] = -(t * n_body);           // sigma_n > 0 compressive
    v[6 + n_angles + k] = t * e_phi;    // sigma_t > 0 pulls the surface counter-clockwise
  }
  return v;
}

/// Fields on the grid (intruder frame, lab axes).
void CylinderProblem::sample_fields() {
  if (!config_.fields.enabled) return;
  const std::size_t n = static_cast<std::size_t>(config_.fields.nx) * config_.fields.ny;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (auto* v : {&out_.vx, &out_.vy, &out_.pressure, &out_.sxx, &out_.sxy, &out_.syy})
    v->assign(n, nan);
  // bin (i, j) has its lower-left corner at (x0 + i h, y0 + j h), as in the DEM; the
  // fields are the point values at the bin centres (evaluated together: one reduction)
  std::vector<Point2> points;
  std::vector<std::size_t> where;
  for (int j = 0; j < config_.fields.ny; ++j)
    for (int i = 0; i < config_.fields.nx; ++i) {
      const Point2 x(config_.fields.x0 + (i + 0.5) * config_.fields.spacing,
                     config_.fields.y0 + (j + 0.5) * config_.fields.spacing);
      if (x.norm() < R_) continue;
      points.push_back(x);
      where.push_back(static_cast<std::size_t>(j) * config_.fields.nx + i);
    }
  std::vector<char> found;
  const auto states = post().point_states(points, found);
  for (std::size_t m = 0; m < points.size(); ++m) {
    if (!found[m]) continue;
    const PointState& st = states[m];
    const std::size_t k = where[m];
    out_.vx[k] = st.velocity[0];
    out_.vy[k] = st.velocity[1];
    out_.pressure[k] = st.pressure;
    out_.sxx[k] = st.stress[0][0];
    out_.sxy[k] = st.stress[0][1];
    out_.syy[k] = st.stress[1][1];
  }
}

void CylinderProblem::output_results() const {
  if (config_.vtu_directory.empty()) return;
  // the VTU is a picture of the result, not the result: a VTU that cannot be written (a full
  // disk) is a warning, and the run goes on to write its result file
  try {
    post().output_results(config_.vtu_directory, "continuum");
  } catch (const std::exception& e) {
    say(std::string("warning: the VTU file was not written, the run goes on: ") + e.what());
  }
}

}  // namespace grainlift::continuum::internal
