// CylinderProblem: the cylinder problem (geometry, boundary conditions, continuation, adaptive
// refinement, outputs) on top of the FlowProblem engine (cylinder_problem.h).
// Conventions: docs/continuum-model.md (theta from V, counter-clockwise).
#include "cylinder_problem.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/grid_refinement.h>
#include <deal.II/distributed/solution_transfer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/fe/fe_values_extractors.h>
#include <deal.II/grid/grid_refinement.h>
#include <deal.II/numerics/error_estimator.h>
#include <deal.II/numerics/solution_transfer.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include "fault_injection.h"

namespace grainlift::continuum::internal {

using namespace dealii;

namespace {
constexpr int kMaxSplits = 6, kStageIterations = 20;
}  // namespace

CylinderProblem::CylinderProblem(const ContinuumConfig& config,
                                 std::function<void(const std::string&)> log)
    : config_(config), log_(std::move(log)), R_(0.5 * config.intruder_diameter),
      V_({config.intruder_velocity[0], config.intruder_velocity[1]}),
      g_({config.gravity[0], config.gravity[1]}), omega_(config.intruder_omega),
      rho_(config.bulk_density), P0_(config.ambient_pressure), speed_(V_.norm()),
      vref_(std::max(speed_, std::abs(omega_) * R_)),
      linearised_(config.linearised_gravity && g_.norm() > 0), rheology_(config.rheology) {}

CylinderProblem::~CylinderProblem() = default;

ContinuumOutput CylinderProblem::run() {
  const bool nested = config_.nested && config_.refinement > 0;
  auto level_start = std::chrono::steady_clock::now();
  make_mesh(nested ? 0 : config_.refinement);
  setup_system();
  schedule_continuation();
  fail_here_if_requested("before the nonlinear solve");  // test hook (fault_injection.h)
  solve_with_continuation();
  if (nested) record_level(0, level_start);
  // before each refinement: a signal stops the study on the converged mesh
  // (ContinuumConfig::stop_refining); otherwise that mesh's result is handed out first, so a
  // study killed during the next level keeps it (ContinuumConfig::level_converged)
  auto stop = [&] {
    // one decision for all ranks (a signal may reach them at different times)
    const bool s = config_.stop_refining &&
                   Utilities::MPI::logical_or(config_.stop_refining(),
                                              mesh_->tria().get_communicator());
    if (s)
      out_.interrupted = true;
    else
      hand_out_converged_level();
    return s;
  };
  for (int level = 1; nested && level <= config_.refinement && problem_->report().converged;
       ++level) {
    if (stop()) break;
    level_start = std::chrono::steady_clock::now();
    solve_next_level(level);
    record_level(level, level_start);
  }
  for (int cycle = 0; cycle < config_.adaptive_cycles && problem_->report().converged; ++cycle) {
    if (stop()) break;
    refine_mesh(cycle);
    schedule_after_refinement();
    solve_with_continuation();
  }
  out_.continuation_splits = splits_;
  if (linearised_) correct_for_gravity();
  report_convergence();
  check_well_posedness();
  compute_boundary_outputs();
  if (nested && config_.adaptive_cycles == 0 && !out_.levels.empty() &&
      out_.levels.back().refinement == config_.refinement) {
    LevelResult& last = out_.levels.back();
    last.fx = out_.fx;
    last.fy = out_.fy;
    last.torque = out_.torque;
  }
  sample_fields();
  output_results();
  return out_;
}

/// The converged state of the mesh about to be refined, post-processed as at the end of run()
/// (forces, surface stresses, fields), to ContinuumConfig::level_converged.
void CylinderProblem::hand_out_converged_level() {
  if (!config_.level_converged) return;
  if (linearised_ && !corrected_) correct_for_gravity();
  out_.continuation_splits = splits_;
  report_convergence();
  // a nested level's forces are already those of this state (record_level)
  if (outputs_stage_ != stage_number_) compute_boundary_outputs();
  sample_fields();
  config_.level_converged(out_);
}

void CylinderProblem::say(const std::string& s) const {
  if (log_) log_(s);
}

/// The box with the intruder's hole, finest at the intruder (see IntruderMesh).
void CylinderProblem::make_mesh(int refinement) {
  mesh_ = std::make_unique<IntruderMesh>(R_, box_edges(config_), refinement,
                                         config_.far_field == FarField::periodic);
}

ProblemSetup CylinderProblem::make_setup(const Vec2& g_used) const {
  const ContinuumConfig& c = config_;
  const auto& log = log_;
  const Vec2 V = V_;
  const double omega = omega_, rho = rho_, P0 = P0_, speed = speed_, vref = vref_;
  const auto p_lith = [=](const Point2& x) { return P0 + rho * (g_used * x); };
  ProblemSetup setup;
  setup.viscosity = &rheology_;
  setup.log = log;
  setup.linear_solver = c.linear_solver;
  setup.schur_approximation = c.schur_approximation;
  if (g_used.norm() > 0) setup.body_force = [=](const Point2&) { return Vec2(rho * g_used); };
  // far field: Dirichlet u = -V where the flow enters or slides along the box (and on the
  // walls, at rest in the lab frame), the lithostatic traction -p_lith n where it leaves (or
  // at both x ends if V = 0)
  const auto far_velocity = [=](const Point2&) { return Vec2(-V); };
  const auto lithostatic = [=](const Point2& x, const Vec2& n) { return Vec2(-p_lith(x) * n); };
  const auto inflow_or_outflow = [&](types::boundary_id id, const Vec2& n) {
    if (speed == 0 || (-V) * n > 1e-12 * speed)
      setup.bc.traction[id] = lithostatic;
    else
      setup.bc.dirichlet[id] = far_velocity;
  };
  if (c.far_field == FarField::symmetric_box) {
    inflow_or_outflow(kLeft, Vec2({-1, 0}));
    inflow_or_outflow(kRight, Vec2({1, 0}));
    inflow_or_outflow(kBottom, Vec2({0, -1}));
    inflow_or_outflow(kTop, Vec2({0, 1}));
  } else {
    setup.bc.dirichlet[kBottom] = far_velocity;
    // a free surface carries the lithostatic pressure there: zero when P0 is the weight of
    // the bed above the intruder, continuum.ambient_pressure's surcharge otherwise, and P0 in
    // the base state of linearised gravity (no gravity)
    if (c.top == TopEdge::wall)
      setup.bc.dirichlet[kTop] = far_velocity;
    else
      setup.bc.traction[kTop] = lithostatic;
    if (c.far_field == FarField::open) {
      inflow_or_outflow(kLeft, Vec2({-1, 0}));
      inflow_or_outflow(kRight, Vec2({1, 0}));
    } else {
      setup.bc.periodic_x.push_back({kLeft, kRight});
      // no traction anywhere: the pressure level is the lithostatic pressure's mean on the
      // top wall (there, with u uniform along the wall, the normal stress is -p: the lid's
      // load per length is the mean pressure on it)
      if (c.top == TopEdge::wall)
        setup.bc.mean_pressure = MeanPressure{
            kTop, P0 + rho * (g_used[0] * 0.5 * (c.box_left + c.box_right) + g_used[1] * c.box_top)};
    }
  }
  const auto wall_velocity = [omega](const Point2& x) { return Vec2({-omega * x[1], omega * x[0]}); };
  if (c.wall == WallCondition::no_slip) {
    setup.bc.dirichlet[kHole] = wall_velocity;
  } else {
    FrictionWall w;
    w.id = kHole;
    w.wall_velocity = wall_velocity;
    w.mu_w = c.wall_friction;
    w.slip_scale = c.wall_slip_regularisation > 0 ? c.wall_slip_regularisation
                                                  : std::max(1e-3 * vref, 1e-12);
    setup.bc.friction = w;
  }
  setup.initial_velocity = far_velocity;
  setup.initial_pressure = p_lith;
  setup.nonlinear.relative_tolerance = c.nonlinear_tolerance;
  setup.nonlinear.max_iterations = c.max_nonlinear_iterations;
  setup.nonlinear.picard_iterations = c.picard_iterations;
  switch (c.inertia) {
    case InertiaMode::off: break;
    case InertiaMode::on: setup.inertia_density = rho; break;
    case InertiaMode::automatic:
      if (rho * vref * vref / P0 >= c.inertia_threshold) setup.inertia_density = rho;
      break;
  }
  return setup;
}

/// The problem without gravity when it is linearised (the base state), with it otherwise; its
/// dofs, constraints and matrices; the initial guess (far-field velocity, lithostatic pressure).
void CylinderProblem::setup_system() {
  setup_ = make_setup(linearised_ ? Vec2() : g_);
  out_.inertia_used = setup_.inertia_density > 0;
  problem_ = std::make_unique<FlowProblem>(mesh_->tria(), setup_);
  problem_->setup_system();
  problem_->interpolate_initial_guess();
}

void CylinderProblem::schedule_continuation() {
  // ---- continuation: the target problem is approached through stages of the case's friction
  // law (Jop's mu(I), or Barker-Gray's) with the strain-rate regularisation delta_k = 0.1
  // gamma_ref, 0.01 gamma_ref, ... (> 2 delta, > 1e-6 gamma_ref), gamma_ref = v_ref / R,
  // without inertia, each solved to 1e-3 |R_0|; the last stage is the requested rheology and
  // inertia, solved to nonlinear_tolerance |R_0|. A stage that does not converge is retried
  // from the last converged state after an intermediate stage at the geometric mean of the
  // two deltas (at most kMaxSplits times in a run): a factor of 10 in delta is too large a
  // step for some problems (e.g. low P0 with an opening behind the intruder at refinement 2).
  const double gamma_ref = std::max(vref_, 1e-12) / R_;
  for (double delta = 0.1 * gamma_ref;
       config_.continuation && delta > 2 * config_.rheology.delta && delta > 1e-6 * gamma_ref;
       delta *= 0.1)
    schedule_.push_back(delta);
  for (const double delta : schedule_) todo_.push_back({delta, false});
  todo_.push_back({config_.rheology.delta, true});
}

/// Runs the stages in todo_, splitting those that fail; the residual history of each solve is
/// labelled with its stage number.
void CylinderProblem::solve_with_continuation() {
  while (!todo_.empty()) {
    const Stage st = todo_.front();
    NonlinearSettings nl = setup_.nonlinear;
    nl.picard_iterations = stage_number_ == 0 ? config_.picard_iterations : 0;
    std::ostringstream os;
    if (st.final) {
      problem_->set_viscosity(&rheology_);
      problem_->set_inertia_density(setup_.inertia_density);
      os << "continuum: final stage";
    } else {
      RheologyParams prm = config_.rheology;
      prm.delta = st.delta;
      stage_rheology_.push_back(std::make_unique<MuIRheology>(prm));
      problem_->set_viscosity(stage_rheology_.back().get());
      problem_->set_inertia_density(0);
      nl.relative_tolerance = std::max(1e-3, config_.nonlinear_tolerance);
      // a stage that needs more than 20 steps is better split than pushed
      nl.max_iterations = std::min(nl.max_iterations, kStageIterations);
      os << "continuum: continuation stage " << stage_number_ + 1 << ", delta = " << st.delta
         << " 1/s";
    }
    say(os.str());
    const VectorType saved = problem_->solution();
    problem_->solve_nonlinear(nl);
    out_.residual_stage.resize(problem_->report().residual_history.size(), stage_number_);
    ++stage_number_;
    if (!problem_->report().converged && done_delta_ > 0 && splits_ < kMaxSplits) {
      // back to the last converged state, through an intermediate delta
      problem_->solution() = saved;
      const double mid = std::sqrt(done_delta_ * st.delta);
      todo_.push_front({mid, false});
      ++splits_;
      std::ostringstream msg;
      msg << "continuum: stage did not converge; retrying through delta = " << mid << " 1/s";
      say(msg.str());
      continue;
    }
    if (problem_->report().converged) done_delta_ = st.delta;
    todo_.pop_front();
  }
}

// ---- adaptive refinement: Kelly's indicator (jump of the velocity gradient across faces,
// weighted by the face size) marks the 30% of the cells with the largest values; the
// solution is carried over to the refined mesh and the problem solved again from it.
// Distributed mesh: each rank estimates its own cells (the ghosted solution gives the
// neighbours across the partition), the 30% are counted over all ranks, and the old solution
// travels with the cells (parallel::distributed::SolutionTransfer, from a ghosted vector).
// The marked cells are those of one process, and both meshes limit level jumps across
// vertices (see IntruderMesh): the refined mesh is the one-process mesh.
void CylinderProblem::refine_mesh(int cycle) {
  Triangulation<dim>& tria = mesh_->tria();
  auto* const distributed = dynamic_cast<parallel::distributed::Triangulation<dim>*>(&tria);
  Vector<float> indicator(tria.n_active_cells());  // distributed: 0 on the others' cells
  const FEValuesExtractors::Vector velocity(0);
  const VectorType old_ghosted = problem_->ghosted(problem_->solution());
  KellyErrorEstimator<dim>::estimate(
      problem_->mapping(), problem_->dof_handler(), QGauss<dim - 1>(3), {}, old_ghosted,
      indicator, problem_->dof_handler().get_fe().component_mask(velocity));
  if (distributed)
    parallel::distributed::GridRefinement::refine_and_coarsen_fixed_number(
        *distributed, indicator, 0.3, 0.0);
  else
    GridRefinement::refine_and_coarsen_fixed_number(tria, indicator, 0.3, 0.0);
  refine_flagged_cells();
  std::ostringstream os;
  os << "continuum: adaptive cycle " << cycle + 1 << " of " << config_.adaptive_cycles << ": "
     << tria.n_global_active_cells() << " cells, " << problem_->dof_handler().n_dofs() << " dofs";
  say(os.str());
}

/// Refines the flagged cells and carries the solution over to the new mesh.
void CylinderProblem::refine_flagged_cells() {
  corrected_.reset();  // a level's gravity correction (record_level) lives on the old mesh
  Triangulation<dim>& tria = mesh_->tria();
  auto* const distributed = dynamic_cast<parallel::distributed::Triangulation<dim>*>(&tria);
  if (distributed) {
    const VectorType old_ghosted = problem_->ghosted(problem_->solution());
    parallel::distributed::SolutionTransfer<dim, VectorType> transfer(
        problem_->dof_handler());
    transfer.prepare_for_coarsening_and_refinement(old_ghosted);
    tria.execute_coarsening_and_refinement();
    problem_->setup_system();
    transfer.interpolate(problem_->solution());  // owned entries
  } else {
    SolutionTransfer<dim, VectorType> transfer(problem_->dof_handler());
    const VectorType old_solution = problem_->solution();
    tria.prepare_coarsening_and_refinement();
    transfer.prepare_for_coarsening_and_refinement(old_solution);
    tria.execute_coarsening_and_refinement();
    problem_->setup_system();
    transfer.interpolate(old_solution, problem_->solution());
  }
  problem_->nonzero_constraints().distribute(problem_->solution());
}

// ---- nested iteration: level l is the mesh of refinement l (every cell of level l - 1
// refined once: the same cells as IntruderMesh(l)); the interpolated solution of level l - 1
// is close to the converged one of level l, so the final stage alone converges in a few
// Newton steps where the continuation from the far field takes tens (docs/performance.md).
void CylinderProblem::solve_next_level(int level) {
  for (const auto& cell : mesh_->tria().active_cell_iterators())
    if (cell->is_locally_owned()) cell->set_refine_flag();
  refine_flagged_cells();
  {
    std::ostringstream os;
    os << "continuum: nested level " << level << " of " << config_.refinement << ": "
       << mesh_->tria().n_global_active_cells() << " cells, "
       << problem_->dof_handler().n_dofs() << " dofs, from the interpolated level "
       << level - 1;
    say(os.str());
  }
  done_delta_ = -1;  // no split of the final stage: the fallback below instead
  // (measured on the demo at refinement 2: the last one or two stages before the final, or
  // 2-5 Picard steps first, take as many or more steps: 15-19 against 15)
  todo_.push_back({config_.rheology.delta, true});
  solve_with_continuation();
  if (problem_->report().converged) return;
  say("continuum: the interpolated level did not converge; the whole continuation on this "
      "mesh from the far field");
  problem_->interpolate_initial_guess();  // done_delta_ is still -1: splits from the first stage
  for (const double delta : schedule_) todo_.push_back({delta, false});
  todo_.push_back({config_.rheology.delta, true});
  solve_with_continuation();
}

/// Forces and work of the level just solved (out_.levels); with linearised gravity the
/// forces include the level's own first-order correction.
void CylinderProblem::record_level(int level,
                                   std::chrono::steady_clock::time_point started) {
  LevelResult lr;
  lr.refinement = level;
  lr.cells = static_cast<int>(mesh_->tria().n_global_active_cells());
  lr.dofs = static_cast<int>(problem_->dof_handler().n_dofs());
  lr.converged = problem_->report().converged;
  const int steps = problem_->report().picard_steps + problem_->report().newton_steps;
  lr.nonlinear_steps = steps - steps_recorded_;
  steps_recorded_ = steps;
  // the requested level without adaptive cycles: its forces come from run() (no second
  // post-processing of the same state)
  if (lr.converged && (level < config_.refinement || config_.adaptive_cycles > 0)) {
    if (linearised_) correct_for_gravity();
    compute_boundary_outputs();
    lr.fx = out_.fx;
    lr.fy = out_.fy;
    lr.torque = out_.torque;
  }
  lr.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  out_.levels.push_back(lr);
}

void CylinderProblem::schedule_after_refinement() {
  // the transferred state is not a converged state of the finer mesh: approach it again
  // through the last two intermediate stages (the final delta directly can stall; so did
  // the last stage alone: its 20 steps do not converge from the transferred state, the
  // final stage then has no converged state to split from, and refinement 1 + 2 cycles
  // did not converge on reduced_phi080 nor on the Guillard study case)
  for (std::size_t i = schedule_.size() > 2 ? schedule_.size() - 2 : 0; i < schedule_.size(); ++i)
    todo_.push_back({schedule_[i], false});
  if (!schedule_.empty()) done_delta_ = -1;
  todo_.push_back({config_.rheology.delta, true});
}

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
  const auto share = problem_->ill_posed_share();
  out_.sheared_share = share[0];
  out_.ill_posed_share = share[1];
  if (out_.ill_posed_share > 0.05) {
    const InertialRange w = well_posed_range(config_.rheology);
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
  if (!config_.vtu_directory.empty()) post().output_results(config_.vtu_directory, "continuum");
}

}  // namespace grainlift::continuum::internal
