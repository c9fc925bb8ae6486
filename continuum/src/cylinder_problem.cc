// CylinderProblem: the cylinder problem (geometry, boundary conditions, continuation, adaptive
// refinement, outputs) on top of the FlowProblem engine (cylinder_problem.h). This file: the
// run loop, the set-up and the continuation; the boundary conditions are in cylinder_setup.cc,
// the refinement in cylinder_refinement.cc, the post-processing in cylinder_postprocess.cc.
// Conventions: docs/continuum-model.md (theta from V, counter-clockwise).
#include "cylinder_problem.h"

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <chrono>
#include <cmath>
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
  // the nonlocal fluidity on every nested level, each from the coarser one's (g, flow)
  const bool nonlocal = config_.model == ContinuumModel::nonlocal_fluidity;
  const bool nonlocal_nested = nonlocal && nested && config_.adaptive_cycles == 0;
  if (nonlocal_nested && problem_->report().converged) solve_nonlocal_fluidity();
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
    if (target_met()) break;
  }
  // adaptive cycles, with a target error each a step of the same estimate (target_met())
  for (int cycle = 0; cycle < config_.adaptive_cycles && problem_->report().converged &&
                      !out_.target_met;
       ++cycle) {
    if (stop()) break;
    level_start = std::chrono::steady_clock::now();
    refine_mesh(cycle);
    level_approach_ = solve_from_carried(false);
    if (!nested) continue;
    record_level(config_.refinement, level_start);
    out_.levels.back().adaptive_cycle = cycle + 1;
    if (target_met()) break;
  }
  if (nonlocal && !nonlocal_nested && problem_->report().converged && !out_.interrupted)
    solve_nonlocal_fluidity();
  out_.continuation_splits = splits_;
  if (linearised_) correct_for_gravity();
  report_convergence();
  if (nonlocal && out_.converged && !out_.interrupted && !out_.nonlocal_settled) {
    std::ostringstream os;
    os << "the nonlocal fluidity did not settle in " << out_.nonlocal_iterations
       << " iterations (the forces still move by " << out_.nonlocal_force_change
       << " of their size, tolerance " << config_.nonlocal.tolerance << "; |dg|/|g| = "
       << out_.nonlocal_change << ")";
    out_.converged = false;
    out_.message = os.str();
  }
  check_well_posedness();
  report_missed_target();
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
                                         config_.far_field == FarField::periodic,
                                         config_.wall_layers);
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
  schedule_whole_continuation();
}

void CylinderProblem::schedule_whole_continuation() {
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
    nl.stall_window = stall_window_;
    // the final stage from a converged neighbour: the exact Jacobian's quadratic convergence
    // (with the floor the low-pressure opening's final stage crept at 0.86 per step)
    nl.tangent_floor = st.final ? 0.0 : tangent_floor_;
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
    // a guarded approach (solve_from_carried()) gives up at its first failed stage
    if (!problem_->report().converged && stall_window_ > 0) todo_.clear();
  }
}

}  // namespace grainlift::continuum::internal
