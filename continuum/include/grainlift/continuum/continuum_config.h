// Plain-data description of one continuum (mu(I)) run, filled from the case file by the
// glue in continuum/glue/continuum_solver.cc. No deal.II types here: files that include
// this header compile fast.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace grainlift::continuum {

enum class Regularisation {
  chauchat_medale,  ///< eta = mu(I) p / (2 sqrt(|D|^2 + delta^2)), capped at eta_max (Chauchat &
                    ///< Medale, JCP 2014)
  barker_gray       ///< partial regularisation of Barker & Gray (JFM 2017) for low I
};
enum class WallCondition { no_slip, coulomb };
/// The ends of the FE box and how its edges meet the far field.
enum class FarField {
  /// [-half_width, half_width] x [-half_height, half_height] about the intruder: u = -V on
  /// every side the medium enters or slides along, the lithostatic traction where it leaves
  symmetric_box,
  /// the box's x ends identified (period box_right - box_left); bottom and top by their edges
  periodic,
  /// u = -V where the medium enters at an x end, the lithostatic traction where it leaves;
  /// bottom and top by their edges
  open
};
/// The top edge of a periodic or open box: a wall, lid or far-field edge (u = -V; in a
/// periodic box with a wall below, the pressure level is set by the mean pressure on it, the
/// lithostatic pressure there), or a free surface (the lithostatic traction: zero where P0 is
/// the weight of the bed above the intruder).
enum class TopEdge { wall, free_surface };
enum class InertiaMode { off, on, automatic };
/// direct: MUMPS (Trilinos Amesos) on the whole saddle-point matrix. amg: FGMRES with a block
/// upper-triangular preconditioner (Trilinos AMG on the velocity block, 1/eta-weighted pressure
/// mass matrix).
enum class LinearSolver { direct, amg };
/// local: the mu(I) law of RheologyParams; nonlocal_fluidity: Kamrin & Koval's nonlocal
/// granular fluidity (NonlocalParams), solved from the local solution by splitting
enum class ContinuumModel { local, nonlocal_fluidity };

/// The nonlocal granular fluidity model (Kamrin & Koval, PRL 108, 178301, 2012; Henann &
/// Kamrin, PNAS 110, 6730, 2013): eta = p / g, g - xi^2 Laplacian(g) = g_loc(mu, p),
/// xi = A d / sqrt|mu - mu_s| (capped at xi_max), g_loc from the inverse of Jop's mu(I).
struct NonlocalParams {
  double amplitude = 0.5;    ///< A (dimensionless); Kamrin & Koval's glass beads: 0.48
  double xi_max = 0;         ///< m, the cap of xi; 0 = the intruder diameter
  int max_iterations = 60;   ///< splitting iterations (fluidity solve, then flow solve)
  /// stop when the force and the torque move by less than this (relative) in two iterations
  double tolerance = 2e-3;
  double relaxation = 1.0;   ///< w of the Anderson mixing of log g (nonlocal_coupling.cc)
};

/// Dilatancy (continuum.dilatancy = "phi_i"): the packing fraction follows the calibrated
/// Phi(I) = phi_max - a I, floored at phi_min (the calibrated range's end, not extrapolated);
/// the medium keeps the mass of its grains, div(Phi u) = 0 (steady in the intruder's frame),
/// and weighs rho (Phi / phi_max) g, rho the case's bulk density. docs/continuum-model.md.
struct DilatancyParams {
  bool enabled = false;
  double phi_max = 0, a = 0, phi_min = 0;
};
/// Schur complement approximation S ~ B A^{-1} B^T of the amg preconditioner.
enum class SchurApproximation {
  diagonal_a,     ///< B diag(A)^{-1} B^T, one AMG V-cycle (default: robust to the eta_min/eta_max
                  ///< contrast)
  viscosity_mass  ///< pressure mass matrix weighted by 1/eta, lumped (fails when eta spans many
                  ///< decades)
};

struct RheologyParams {
  double mu_s = 0.38, mu_2 = 0.64, I0 = 0.279;  ///< Jop, Forterre & Pouliquen 2006 (glass beads)
  double grain_diameter = 1.5e-3;   ///< m
  double solid_density = 2500;      ///< kg/m^3 (rho_s); I = 2|D| d / sqrt(p / rho_s)
  Regularisation regularisation = Regularisation::barker_gray;
  double delta = 1e-3;              ///< 1/s, strain-rate regularisation
  double eta_max = 1e4;             ///< Pa s, viscosity cap
  // ---- added by the continuum engine (defaults keep the previous behaviour)
  double eta_min = 1e-6;  ///< Pa s, viscosity floor (where p <= 0 the mu(I) viscosity vanishes)
  /// I_N of Barker & Gray 2017: below it mu(I) = sqrt(alpha / ln(A / I)), with alpha and A set so
  /// that mu and dmu/dI are continuous at I_N. Used only with Regularisation::barker_gray.
  /// Must lie inside the range where Jop's mu(I) is well posed (well_posed_range()); 0 picks
  /// 1.5 times its lower end (see MuIRheology::barker_gray_IN()).
  double barker_gray_IN = 0;
  /// Pa, p_eps: with p_eps > 0 the rheology sees p+ = (p + sqrt(p^2 + p_eps^2)) / 2 instead of
  /// max(p, 0), so that d eta / d p is continuous where the pressure vanishes (0 = hard clamp).
  double pressure_smoothing = 0;
};

/// Regular grid in the intruder frame on which fields are sampled (same meaning as the DEM's).
struct FieldGridSpec {
  bool enabled = false;
  double x0 = 0, y0 = 0, spacing = 0;
  int nx = 0, ny = 0;
};

struct ContinuumOutput;

struct ContinuumConfig {
  // ---- geometry (intruder frame: intruder centred at the origin)
  double intruder_diameter = 0.1;   ///< m
  double half_width = 1.0;  ///< m, box is [-half_width, half_width] x [-half_height, half_height]
  double half_height = 1.0;         ///< m
  FarField far_field = FarField::symmetric_box;
  /// periodic and open boxes: the edges relative to the intruder's centre (m), box_left < -R,
  /// box_right > R, box_bottom < -R, box_top > R; the bottom is a wall (u = -V)
  double box_left = -1, box_right = 1, box_bottom = -1, box_top = 1;
  TopEdge top = TopEdge::wall;
  // ---- kinematics (lab frame)
  std::array<double, 2> intruder_velocity{1,
                                          0};  ///< m/s; far field moves at -V in the intruder frame
  double intruder_omega = 0;                      ///< rad/s, counter-clockwise positive
  // ---- body force and pressure
  std::array<double, 2> gravity{0, 0};  ///< m/s^2
  double bulk_density = 1500;           ///< kg/m^3, rho = Phi rho_s
  double ambient_pressure = 1000;       ///< Pa, P0 at the intruder centre
  RheologyParams rheology;
  WallCondition wall = WallCondition::no_slip;
  double wall_friction = 0.5;           ///< mu_w for the Coulomb wall condition
  /// A slip law in place of wall_friction when wall_v0 > 0: mu_w(s) = wall_mu_a + (wall_mu_b -
  /// wall_mu_a) |s| / (|s| + wall_v0), s the local slip (m/s), the grains' measured law.
  double wall_mu_a = 0, wall_mu_b = 0, wall_v0 = 0;
  InertiaMode inertia = InertiaMode::automatic;
  // ---- added by the continuum engine
  /// InertiaMode::automatic keeps rho (u.grad)u only when rho |V|^2 / P0 >= this value.
  double inertia_threshold = 1e-2;
  /// m/s, slip velocity of the regularised Coulomb wall: |tau| = mu_w p s / sqrt(s^2 + eps^2);
  /// 0 = automatic, 1e-3 * max(|V|, |omega| R).
  double wall_slip_regularisation = 0;
  /// Approach the requested problem through Chauchat-Medale stages with
  /// delta = 0.1, 0.01, ... x max(|V|, |omega| R) / R (> 2 delta), without inertia.
  bool continuation = true;
  /// Gravity as a perturbation (Guillard 2014 appendix B): solve the base state without gravity
  /// (uniform far-field pressure P0), then add the first-order correction from one linear solve
  /// with the Newton Jacobian at the base state, J du = -R_g(u_0), R_g the residual with gravity.
  bool linearised_gravity = false;
  ContinuumModel model = ContinuumModel::local;
  NonlocalParams nonlocal;
  DilatancyParams dilatancy;
  // ---- numerics
  int refinement = 2;                   ///< global refinement level of the base mesh
  int adaptive_cycles = 0;
  /// Rings of cells at the intruder, each twice as thick as the one inside it (IntruderMesh);
  /// 0: the plain block.
  int wall_layers = 0;
  /// Nested iteration: the continuation runs on refinement 0, each finer level up to
  /// `refinement` starts from the interpolated coarser solution and solves the final stage
  /// only (a level where that fails is solved again through the whole continuation from the
  /// far field); false: the whole continuation on the requested mesh.
  bool nested = true;
  /// > 0: the nested levels stop at the first level L >= 2 whose estimated force error is at or
  /// below it; `refinement` is then the finest level allowed. The estimate, from the changes
  /// d_L = |F_L - F_(L-1)| and their ratio r = d_L / d_(L-1): d_L max(1, r / (1 - r)) / |F_L|
  /// (the changes still to come if they keep shrinking by r, never less than the last one);
  /// r >= 1: no estimate (1). 0: every level up to `refinement`.
  double target_error = 0;
  double nonlinear_tolerance = 1e-8;    ///< relative residual
  int max_nonlinear_iterations = 50;
  int picard_iterations = 5;
  LinearSolver linear_solver = LinearSolver::direct;
  /// added by the continuum engine (no case key): the Schur approximation of LinearSolver::amg
  SchurApproximation schur_approximation = SchurApproximation::diagonal_a;
  // ---- output
  /// rad, angles at which sigma_n, sigma_t are sampled, measured from the direction of V,
  /// counter-clockwise (docs/conventions.md)
  std::vector<double> surface_theta;
  FieldGridSpec fields;
  std::string vtu_directory;            ///< "" = no VTU output
  // ---- control
  /// Asked before every refinement (nested levels, adaptive cycles): true stops refining; the
  /// run ends on the last mesh solved, its converged state post-processed as usual
  /// (ContinuumOutput::interrupted). Empty: never asked.
  std::function<bool()> stop_refining;
  /// Called before every refinement (nested levels, adaptive cycles) with the converged state
  /// of the mesh about to be refined, post-processed as a final result would be (forces,
  /// surface stresses, fields; not the VTU): a study killed during the next level keeps what
  /// it had. Empty: not called (no post-processing of the intermediate meshes).
  std::function<void(const ContinuumOutput&)> level_converged;
};

/// The FE box's edges {x0, x1, y0, y1} relative to the intruder's centre (m): the symmetric
/// box's half sizes, or box_left ... box_top.
inline std::array<double, 4> box_edges(const ContinuumConfig& c) {
  if (c.far_field == FarField::symmetric_box)
    return {-c.half_width, c.half_width, -c.half_height, c.half_height};
  return {c.box_left, c.box_right, c.box_bottom, c.box_top};
}

/// One level of the nested iteration (ContinuumConfig::nested): its mesh, forces and work.
struct LevelResult {
  int refinement = 0, cells = 0, dofs = 0;
  double fx = 0, fy = 0, torque = 0;  ///< N/m, N
  int nonlinear_steps = 0;            ///< Picard and Newton steps spent on this level
  double seconds = 0;                 ///< wall time of this level (refinement, set-up, solves)
  bool converged = false;
  /// how it was reached: 0 the final stage from the interpolated coarser level, 1 from it
  /// through the last two continuation stages, 2 the whole continuation from the far field
  /// (level 0, and a level neither of the others converged on)
  int approach = 0;
  /// 0: a nested level (every cell refined); k >= 1: adaptive cycle k on top of the finest
  /// nested level (Kelly's 30%)
  int adaptive_cycle = 0;
};

struct ContinuumOutput {
  double fx = 0, fy = 0, torque = 0;  ///< N/m, N: force and torque of the medium on the intruder
  std::vector<double> sigma_n,
      sigma_t;  ///< Pa at surface_theta; sigma_n > 0 compressive, sigma_t > 0 ccw
  // fields on the grid, row-major [j * nx + i]; NaN inside the intruder or outside the mesh
  std::vector<double> vx, vy, pressure, sxx, sxy, syy;
  int nonlinear_iterations = 0;
  int linear_iterations = 0;              ///< linear solves (one per nonlinear step and retry)
  int cells = 0, dofs = 0;
  double final_residual = 0;
  bool converged = false;
  // ---- added by the continuum engine
  int picard_steps = 0, newton_steps = 0;  ///< split of nonlinear_iterations
  double initial_residual = 0;            ///< |R_0| (final_residual is |R_k| / |R_0|)
  long krylov_iterations = 0;  ///< FGMRES iterations over all linear solves (amg; 0 for direct)
  /// direct solves: the largest relative linear residual |A x - b| / |b| left (0 for amg)
  double worst_direct_residual = 0;
  bool inertia_used = false;              ///< whether rho (u.grad)u was included
  double correction_seconds =
      0;  ///< linearised gravity: time of the correction (setup + one solve)
  int continuation_splits = 0;            ///< intermediate stages inserted after a failed stage
  /// share of the medium's area sheared beyond the regularisation (|D| > 5 delta), and the part
  /// of it where mu(I) is ill posed at the local I (Barker et al. 2015): there the solution
  /// depends on the mesh (docs/continuum-model.md)
  double sheared_share = 0, ill_posed_share = 0;
  /// share of the layer a quarter of the intruder's radius deep around it that is sheared at
  /// an I above the high end of mu(I)'s well-posed range: where a slip line forms at the wall
  /// and the forces may have no mesh limit (docs/continuum-model.md); a run that misses its
  /// target_error names it
  double ill_posed_wall_share = 0;
  double force_fx_surface = 0, force_fy_surface = 0,
         torque_surface = 0;  ///< same by integrating sigma.n (diagnostic)
  /// |R_k| / |R_0| after each nonlinear step, all continuation stages and adaptive cycles
  /// concatenated in order (|R_0| the residual of the initial guess)
  std::vector<double> residual_history;
  /// the continuation stage (0, 1, 2, ... in the order they ran, counting the retries of split
  /// stages and the stages of each adaptive cycle) of each entry of residual_history
  std::vector<int> residual_stage;
  std::string message;                    ///< why it failed when !converged
  /// ContinuumModel::nonlocal_fluidity: splitting iterations run, and the last relative change
  /// of g (|g_k - g_(k-1)| / |g_k|, below NonlocalParams::tolerance when it converged)
  /// ContinuumConfig::target_error > 0: the estimated relative force error of the level the
  /// run stopped at (see target_error; -1 when fewer than three levels were solved), and
  /// whether it met the target
  double estimated_error = -1;
  bool target_met = false;
  int nonlocal_iterations = 0;
  double nonlocal_change = 0;
  /// the largest relative change of |F| and |T| in the last iteration; settled: it stayed
  /// below NonlocalParams::tolerance in two iterations running
  double nonlocal_force_change = 0;
  bool nonlocal_settled = false;
  bool interrupted = false;               ///< stop_refining() ended it before the requested mesh
  /// nested iteration: every level solved, coarsest first (the last is the requested one,
  /// before any adaptive cycle); empty without nesting
  std::vector<LevelResult> levels;
};

}  // namespace grainlift::continuum
