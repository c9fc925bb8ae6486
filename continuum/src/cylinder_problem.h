// Internal: the cylinder problem (geometry, boundary conditions, continuation, adaptive
// refinement, outputs) on top of the FlowProblem engine; solve_flow() runs it. Includes
// deal.II: never include it from a public header.
#pragma once

#include <array>
#include <chrono>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "flow_problem.h"
#include "grainlift/continuum/continuum_config.h"
#include "grainlift/continuum/mu_i_rheology.h"
#include "fluidity/fluidity_problem.h"
#include "fluidity/fluidity_viscosity.h"
#include "intruder_mesh.h"

namespace grainlift::continuum::internal {

/// @brief Steady mu(I) flow around a translating, spinning cylinder in the intruder frame, in
/// the shape of the deal.II tutorials (step-57): run() makes the mesh, sets up the problem,
/// solves it through a continuation in the regularisation, refines adaptively, applies the
/// linearised gravity correction, post-processes (forces, surface stresses, fields) and
/// writes the VTU output. Conventions: docs/continuum-model.md (theta from V,
/// counter-clockwise). The configuration must have passed validate_config().
class CylinderProblem {
 public:
  /// @param config  the case (SI units); must outlive the object
  /// @param log     optional sink for one-line progress messages
  CylinderProblem(const ContinuumConfig& config, std::function<void(const std::string&)> log);
  ~CylinderProblem();

  /// @brief Solve and post-process. Collective on several MPI ranks.
  /// @return the outputs; converged = false with a message when the nonlinear solve did not
  ///         converge. Exceptions (failures that are not a non-convergence) propagate.
  ContinuumOutput run();

 private:
  /// One solve of the continuation: the regularisation delta (1/s) of an intermediate stage,
  /// or the requested rheology and inertia (final).
  struct Stage {
    double delta;
    bool final;
  };

  void make_mesh(int refinement);
  /// The problem with gravity @p g_used: body force rho g, far field at P0 + rho g.x.
  ProblemSetup make_setup(const Vec2& g_used) const;
  void setup_system();
  void schedule_continuation();
  void solve_with_continuation();
  void refine_mesh(int cycle);
  void refine_flagged_cells();
  void solve_next_level(int level);
  void record_level(int level, std::chrono::steady_clock::time_point started);
  void schedule_after_refinement();
  /// Every stage of schedule_, then the final one (the continuation from the far field).
  void schedule_whole_continuation();
  /// The problem on a refined mesh from the state carried over to it, by the first approach
  /// that converges: 0 the final stage (only with @p final_first), 1 the last two stages and
  /// the final one, 2 the whole continuation from the far field; returns it
  /// (cylinder_refinement.cc).
  int solve_from_carried(bool final_first);
  void correct_for_gravity();
  void report_convergence();
  void check_well_posedness();
  /// With continuum.target_error: when the levels ran out before the estimate met it, says so
  /// (and names a slip line at the wall, ContinuumOutput::ill_posed_wall_share).
  void report_missed_target() const;
  void compute_boundary_outputs();
  /// The reaction (fx, fy, torque), the surface integral (fx, fy, torque), then sigma_n and
  /// sigma_t at the surface angles, of the state of @p fp.
  std::vector<double> boundary_outputs(const FlowProblem& fp) const;
  void sample_fields();
  void output_results() const;
  void hand_out_converged_level();
  /// With ContinuumConfig::target_error: the estimated error of the mesh just recorded (a
  /// nested level >= 2 or an adaptive cycle: its forces against the two meshes before it, in
  /// out_.estimated_error) and whether it meets the target (cylinder_refinement.cc).
  bool target_met();
  /// The nonlocal fluidity model from the converged local state: fluidity and flow solved in
  /// turn until g settles (fluidity/nonlocal_coupling.cc).
  void solve_nonlocal_fluidity();
  /// The splitting's flow step @p k with the previous flow's g_loc at the fluidity's points
  /// (FluidityViscosity::set_local_fluidity), its outputs and its line; false when the flow
  /// did not converge.
  bool nonlocal_flow_step(int k, bool with_picard, std::vector<double> g_loc);
  /// The flow step @p k again from @p flow_before with the fluidity's step halved (g halfway
  /// back to @p g_before), up to four times; false when none converged.
  bool nonlocal_flow_step_halved(int k, bool with_picard, const std::vector<double>& g_loc,
                                 const dealii::Vector<double>& g_before,
                                 const VectorType& flow_before);
  /// Whether the force and torque of out_ moved by less than the splitting's tolerance since
  /// @p last (updated; out_.nonlocal_force_change set).
  bool nonlocal_forces_still(std::array<double, 3>& last);
  /// fluidity_table_ at the fluidity's quadrature points of every active cell
  std::vector<double> carried_table() const;
  /// The problem whose state is post-processed: the gravity-corrected one when there is one.
  const FlowProblem& post() const { return corrected_ ? *corrected_ : *problem_; }
  void say(const std::string& s) const;

  const ContinuumConfig& config_;
  std::function<void(const std::string&)> log_;
  // the case in the intruder frame
  double R_;
  Vec2 V_, g_;
  double omega_, rho_, P0_, speed_, vref_;
  bool linearised_;  ///< linearised gravity: the nonlinear solve is the base state without it
  MuIRheology rheology_;

  std::unique_ptr<IntruderMesh> mesh_;  ///< declared before the problems, which use its mesh
  ProblemSetup setup_;
  std::unique_ptr<FlowProblem> problem_;

  // continuation (see schedule_continuation())
  std::vector<double> schedule_;  ///< the intermediate deltas
  std::deque<Stage> todo_;
  int splits_ = 0, stage_number_ = 0;
  int steps_recorded_ = 0;  ///< nonlinear steps counted in out_.levels so far
  int outputs_stage_ = -1;  ///< stage_number_ of the state whose forces are in out_
  double done_delta_ = -1;  ///< delta of the last converged stage; < 0: none yet
  /// > 0 (solve_next_level()'s approaches from an interpolated level): every stage's
  /// NonlinearSettings::stall_window, and the approach ends at its first failed stage
  int stall_window_ = 0;
  /// NonlinearSettings::tangent_floor of the intermediate stages: > 0 only in
  /// solve_from_carried()'s last approach (the whole continuation on a refined mesh)
  double tangent_floor_ = 0;
  /// how the level just solved was reached (solve_from_carried(); 2 for level 0: the whole
  /// continuation from the far field), for LevelResult::approach
  int level_approach_ = 2;
  std::vector<std::unique_ptr<MuIRheology>> stage_rheology_;  ///< outlive the solves

  // linearised gravity: the problem with gravity and the first-order correction
  std::unique_ptr<FlowProblem> corrected_;
  VectorType du_;
  VectorType corrected_base_;  ///< the base state in the problem with gravity (its pressure level)

  // nonlocal fluidity (solve_nonlocal_fluidity()): the g problem, its field, the viscosity
  std::unique_ptr<fluidity::internal::FluidityProblem> fluidity_;
  dealii::Vector<double> fluidity_g_;
  /// the last flow step's g_loc table projected on g's space: carried with g to the next
  /// nested level (refine_flagged_cells()), where carried_table() gives it at the points
  dealii::Vector<double> fluidity_table_;
  std::unique_ptr<FluidityViscosity> fluidity_viscosity_;

  ContinuumOutput out_;
};

}  // namespace grainlift::continuum::internal
