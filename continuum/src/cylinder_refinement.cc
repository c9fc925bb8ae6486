// CylinderProblem's mesh refinement (cylinder_problem.h): adaptive cycles with Kelly's
// estimate, nested iteration over uniformly refined levels, the solution carried to the new
// mesh, and the forces and work recorded per level.
#include "cylinder_problem.h"

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/grid_refinement.h>
#include <deal.II/distributed/solution_transfer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/fe/fe_values_extractors.h>
#include <deal.II/grid/grid_refinement.h>
#include <deal.II/numerics/error_estimator.h>
#include <deal.II/numerics/solution_transfer.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <utility>
#include <sstream>

#include "fault_injection.h"

namespace grainlift::continuum::internal {

using namespace dealii;

namespace {
/// Newton steps over which the final stage of an interpolated level may average a length of
/// 1/16 or less before it counts as stalled (NonlinearSettings::stall_window). The demo's
/// levels converge with windows averaging 1/6-1/8; Kumar's dilute case stalls at 1/32-1/64.
constexpr int kStallWindow = 8;
/// NonlinearSettings::tangent_floor of the intermediate stages of the whole continuation on a
/// refined mesh. Kumar's dilute case, Kelly's cycle 4 from refinement 1: 0.05 converges (0.01
/// does not); on every approach it slows the demo's levels 93 -> 132 steps, so only in the
/// last approach (docs/continuum-model.md, "Newton's tangent floor").
constexpr double kTangentFloor = 0.05;
}  // namespace

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
    // the nonlocal fluidity's g (one rank only) goes with the flow: the next level starts
    // from the coarser one's converged pair (solve_nonlocal_fluidity())
    const bool with_g = fluidity_ && fluidity_g_.size() == fluidity_->dof_handler().n_dofs() &&
                        fluidity_table_.size() == fluidity_g_.size();
    std::unique_ptr<SolutionTransfer<dim, Vector<double>>> g_transfer;
    const std::vector<Vector<double>> g_old =
        with_g ? std::vector<Vector<double>>{fluidity_g_, fluidity_table_}
               : std::vector<Vector<double>>();
    if (with_g) {
      g_transfer = std::make_unique<SolutionTransfer<dim, Vector<double>>>(
          fluidity_->dof_handler());
      g_transfer->prepare_for_coarsening_and_refinement(g_old);
    }
    tria.execute_coarsening_and_refinement();
    problem_->setup_system();
    transfer.interpolate(old_solution, problem_->solution());
    if (with_g) {
      fluidity_->setup_system();
      std::vector<Vector<double>> carried(2, Vector<double>(fluidity_->dof_handler().n_dofs()));
      g_transfer->interpolate(g_old, carried);
      fluidity_g_ = std::move(carried[0]);
      fluidity_table_ = std::move(carried[1]);
    }
  }
  problem_->nonzero_constraints().distribute(problem_->solution());
}

// ---- nested iteration: level l is the mesh of refinement l (every cell of level l - 1
// refined once: the same cells as IntruderMesh(l)); the interpolated solution of level l - 1
// is close to the converged one of level l, so the final stage alone converges in a few
// Newton steps where the continuation from the far field takes tens (docs/performance.md).
void CylinderProblem::solve_next_level(int level) {
  bad_alloc_here_if_requested(level);  // test hook (fault_injection.h)
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
  // the nonlocal fluidity from the coarser level's g and flow: no local solve between
  if (config_.model == ContinuumModel::nonlocal_fluidity && fluidity_) {
    solve_nonlocal_fluidity();
    return;
  }
  level_approach_ = solve_from_carried(true);
}

// ---- a refined mesh from the state carried over to it (nested levels and adaptive cycles).
// The carried state is not a converged state of the finer mesh. In turn, each given up at
// its first failed stage or stalled Newton steps (kStallWindow):
//  0. the final stage directly (nested levels only: the demo's levels converge in 13-17 steps,
//     where the last one or two stages before it, or 2-5 Picard steps first, took 15-19);
//  1. the last two intermediate stages, then the final one: their larger delta smooths the
//     nearly rigid zones that the final stage's Newton steps stall on (Kumar's dilute case at
//     refinements 2 and 3: 13-50 steps of length 1/16-1/1024 from the interpolated level,
//     then 16 + 4 + 10 steps this way);
//  2. the whole continuation on this mesh from the far field (splits allowed).
int CylinderProblem::solve_from_carried(bool final_first) {
  const VectorType carried = problem_->solution();
  stall_window_ = kStallWindow;
  int approach = -1;
  if (final_first) {
    done_delta_ = -1;  // no split of the final stage: the next approach instead
    todo_.push_back({config_.rheology.delta, true});
    solve_with_continuation();
    if (problem_->report().converged) approach = 0;
  }
  // (without intermediate stages approach 1 would be approach 0 again)
  if (approach < 0 && !(final_first && schedule_.empty())) {
    if (final_first) {
      say("continuum: the final stage did not converge from the carried state; again from it "
          "through the last two stages");
      problem_->solution() = carried;
    }
    schedule_after_refinement();
    solve_with_continuation();
    if (problem_->report().converged) approach = 1;
  }
  stall_window_ = 0;
  if (approach >= 0) return approach;
  say("continuum: the carried state did not converge; the whole continuation on this mesh "
      "from the far field");
  problem_->interpolate_initial_guess();
  done_delta_ = -1;  // splits from the first stage on
  schedule_whole_continuation();
  tangent_floor_ = kTangentFloor;
  solve_with_continuation();
  tangent_floor_ = 0;
  return 2;
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
  lr.approach = level_approach_;
  const int steps = problem_->report().picard_steps + problem_->report().newton_steps;
  lr.nonlinear_steps = steps - steps_recorded_;
  steps_recorded_ = steps;
  // the requested level without adaptive cycles: its forces come from run() (no second
  // post-processing of the same state)
  if (lr.converged && (level < config_.refinement || config_.adaptive_cycles > 0 ||
                       config_.target_error > 0)) {
    if (linearised_) correct_for_gravity();
    compute_boundary_outputs();
    lr.fx = out_.fx;
    lr.fy = out_.fy;
    lr.torque = out_.torque;
  }
  lr.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  out_.levels.push_back(lr);
}

bool CylinderProblem::target_met() {
  const std::size_t n = out_.levels.size();
  if (!(config_.target_error > 0) || n < 3 || !problem_->report().converged) return false;
  // the changes of the force between the last three levels, and their ratio r
  auto change = [&](std::size_t a, std::size_t b) {
    return std::hypot(out_.levels[a].fx - out_.levels[b].fx,
                      out_.levels[a].fy - out_.levels[b].fy);
  };
  const double d_fine = change(n - 1, n - 2), d_coarse = change(n - 2, n - 3);
  const double F = std::hypot(out_.levels.back().fx, out_.levels.back().fy);
  const double r = d_coarse > 0 ? d_fine / d_coarse : 0.0;
  // the change still to come if the changes keep shrinking by r (d r / (1 - r)), never less
  // than the last change itself; not converging (r >= 1): no estimate
  out_.estimated_error = r < 1 && F > 0 ? d_fine * std::max(1.0, r / (1 - r)) / F : 1.0;
  out_.target_met = out_.estimated_error <= config_.target_error;
  std::ostringstream os;
  const LevelResult& last = out_.levels.back();
  os << "continuum: " << (last.adaptive_cycle > 0 ? "adaptive cycle " : "level ")
     << (last.adaptive_cycle > 0 ? last.adaptive_cycle : last.refinement)
     << ": estimated force error " << out_.estimated_error
     << " (change " << d_fine / std::max(F, 1e-300) << ", ratio " << r << "), target "
     << config_.target_error;
  say(os.str());
  return out_.target_met;
}

void CylinderProblem::report_missed_target() const {
  if (!(config_.target_error > 0) || out_.target_met || !out_.converged || out_.interrupted ||
      out_.levels.empty())
    return;
  // the levels ran out before the estimate reached the target: the forces are the finest
  // level's, their error larger than asked
  std::ostringstream os;
  os << "continuum: warning: the target error " << config_.target_error << " was not met: ";
  if (out_.estimated_error >= 0)
    os << "the estimate at the finest level is " << out_.estimated_error;
  else
    os << "fewer than three levels give no estimate";
  os << " (continuum.refinement = " << config_.refinement
     << " caps the levels; /diagnostics level_drag, level_lift)";
  if (out_.ill_posed_wall_share > 0 && config_.model == ContinuumModel::local) {
    // the slip line of docs/continuum-model.md, "What sits at the wall with the glass-bead
    // law": one cell thick, its I growing with each level, the lift with no mesh limit in
    // sight
    os.precision(3);
    os << ". Next to the intruder " << 100 * out_.ill_posed_wall_share
       << "% of a layer R/4 deep is sheared where mu(I) is ill posed (I above "
       << well_posed_range(config_.rheology).high
       << "): a slip line at the wall, whose forces may have no mesh limit. A higher "
          "confining pressure or lower speeds leave that range; continuum.model = "
          "\"nonlocal_fluidity\" gives the layer a thickness (docs/continuum-model.md)";
  }
  say(os.str());
}

void CylinderProblem::schedule_after_refinement() {
  // the last two intermediate stages, then the final one (solve_from_carried()'s approach 1;
  // the last stage alone: its 20 steps did not converge from the transferred state after
  // adaptive cycles on reduced_phi080 nor on the Guillard study case)
  for (std::size_t i = schedule_.size() > 2 ? schedule_.size() - 2 : 0; i < schedule_.size(); ++i)
    todo_.push_back({schedule_[i], false});
  if (!schedule_.empty()) done_delta_ = -1;
  todo_.push_back({config_.rheology.delta, true});
}

}  // namespace grainlift::continuum::internal
