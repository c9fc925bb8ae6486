// Internal: the deal.II finite-element engine shared by solve_flow() and the verification
// drivers. Steady incompressible generalised-Newtonian flow, Taylor-Hood Q2-Q1, Picard then
// Newton with a backtracking line search; linear solves direct (MUMPS) or FGMRES with a block
// preconditioner (Trilinos AMG on the velocity block, 1/eta-weighted pressure mass matrix).
// The linear algebra is Trilinos' (MPI block vectors and matrices, velocity then pressure), so
// the same code runs on a serial Triangulation (one rank) and on a distributed one (each rank
// assembles its locally owned cells; the post-processing reduces over the ranks).
// This header includes deal.II: never include it from a public header.
#pragma once

#include <deal.II/base/function.h>
#include <deal.II/base/point.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q_cache.h>
#include <deal.II/grid/grid_tools_cache.h>
#include <deal.II/grid/tria.h>
#include <deal.II/base/index_set.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_block_sparse_matrix.h>
#include <deal.II/lac/trilinos_parallel_block_vector.h>
#include <deal.II/lac/vector.h>

#include <mpi.h>

#include <algorithm>
#include <array>
#include <deque>
#include <functional>
#include <memory>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "grainlift/continuum/continuum_config.h"
#include "grainlift/continuum/mu_i_rheology.h"
#include "grainlift/shared/machine/memory.h"

namespace grainlift::continuum::internal {

constexpr int dim = 2;
using Point2 = dealii::Point<dim>;
using Vec2 = dealii::Tensor<1, dim>;
using VectorField = std::function<Vec2(const Point2&)>;
using ScalarField = std::function<double(const Point2&)>;
/// Solution, residual and update: block 0 the velocity, block 1 the pressure dofs (owned
/// entries only; evaluations use a ghosted copy, see FlowProblem::ghosted()).
using VectorType = dealii::TrilinosWrappers::MPI::BlockVector;
using MatrixType = dealii::TrilinosWrappers::BlockSparseMatrix;

/// Regularised Coulomb wall: u.n = 0 strongly, tangential traction on the medium
/// -mu_w p+ s / sqrt(s^2 + eps^2) along the tangent, s the slip (u - u_wall).t.
struct FrictionWall {
  dealii::types::boundary_id id = 0;
  VectorField wall_velocity;  ///< m/s, tangential velocity of the wall
  double mu_w = 0.5;
  double slip_scale = 1e-3;   ///< m/s, eps
  /// With v0 > 0, mu_w is the slip law mu_a + (mu_b - mu_a) |s| / (|s| + v0) (m/s) instead.
  double mu_a = 0, mu_b = 0, v0 = 0;
};

/// The pressure level of a problem with no traction boundary: the mean pressure over the
/// boundary @p id equals @p value (Pa). One linear constraint on the pressure dofs of that
/// boundary (FlowProblem::make_constraints), on any number of MPI ranks.
struct MeanPressure {
  dealii::types::boundary_id id = 0;
  double value = 0;
};

struct BoundarySpec {
  std::map<dealii::types::boundary_id, VectorField> dirichlet;  ///< imposed velocity
  /// imposed traction sigma.n (n the outward normal of the medium), given x and n
  std::map<dealii::types::boundary_id, std::function<Vec2(const Point2&, const Vec2&)>> traction;
  std::optional<FrictionWall> friction;
  /// pairs of boundary ids identified by periodicity along x
  std::vector<std::pair<dealii::types::boundary_id, dealii::types::boundary_id>> periodic_x;
  std::optional<MeanPressure> mean_pressure;
  bool pin_pressure = false;  ///< fix one pressure dof (all-Dirichlet problems) to initial_pressure
};

/// A dilatant medium's relative density deficit delta(I) = (phi_max - Phi(I)) / phi_max =
/// min(a I, phi_max - phi_min) / phi_max: the continuity equation is div((1 - delta) u) = 0
/// and the body force (1 - delta) f, delta at the I of the state being assembled (Newton's
/// matrix differentiates it through I(|D|^2, p); Picard's holds it fixed). The min is rounded
/// over x = a I / phi_max within w = max_deficit / 10 of the floor, x - (x - m + w)^2 / (4 w),
/// so that delta is C1 (Newton cycled on the kink where the wake's I crosses the floor).
struct DilatancyLaw {
  double a_rel = 0;        ///< a / phi_max
  double max_deficit = 0;  ///< (phi_max - phi_min) / phi_max
  double deficit(double inertial_number) const {
    const double x = a_rel * inertial_number, m = max_deficit, w = 0.1 * m;
    if (x <= m - w) return x;
    if (x >= m + w) return m;
    return x - (x - m + w) * (x - m + w) / (4 * w);
  }
  /// d delta / dI
  double slope(double inertial_number) const {
    const double x = a_rel * inertial_number, m = max_deficit, w = 0.1 * m;
    if (x <= m - w) return a_rel;
    if (x >= m + w) return 0.0;
    return a_rel * (1 - (x - m + w) / (2 * w));
  }
};

struct NonlinearSettings {
  double relative_tolerance = 1e-8;  ///< ||R_k|| <= tol ||R_0||
  double absolute_tolerance = 1e-300;
  int max_iterations = 50;
  int picard_iterations = 5;
  /// > 0: Newton's matrix keeps the tangent of the stress along the strain rate at least
  /// tangent_floor times the secant viscosity's (the viscosity's derivative scaled down where
  /// it would go lower): a saturating mu(I) makes that tangent 5-10% of the secant in the
  /// flowing medium and nearly 0 near yield and at high I, which spoils the Newton direction
  /// on fine meshes (docs/continuum-model.md, "Newton's tangent floor"). The
  /// matrix is then not the exact Jacobian where the floor acts. 0: the exact Jacobian.
  double tangent_floor = 0;
  /// > 0: give up (not converged, "stalled") once the last stall_window Newton steps' lengths
  /// have a geometric mean at or below stall_step (a Newton step redone as Picard counts as
  /// the line search's shortest, 1/1024): the line search keeps cutting the steps, and a
  /// caller with a better start (more regularisation) can take over. 0: never.
  int stall_window = 0;
  double stall_step = 1.0 / 16;
};

struct ProblemSetup {
  VectorField body_force;                 ///< N/m^3 (e.g. rho g); empty = none
  std::optional<DilatancyLaw> dilatancy;  ///< empty: incompressible
  /// s in div((1 - delta) u) = s (manufactured solutions); empty = 0
  ScalarField continuity_source;
  BoundarySpec bc;
  const ViscosityModel* viscosity = nullptr;
  double inertia_density = 0;             ///< kg/m^3; 0 = Stokes (no rho (u.grad)u)
  NonlinearSettings nonlinear;
  VectorField initial_velocity;           ///< empty = 0
  ScalarField initial_pressure;           ///< empty = 0
  std::function<void(const std::string&)> log;
  LinearSolver linear_solver = LinearSolver::direct;
  SchurApproximation schur_approximation = SchurApproximation::diagonal_a;
};

struct NonlinearReport {
  int picard_steps = 0, newton_steps = 0, linear_solves = 0;
  long krylov_iterations = 0;  ///< FGMRES iterations summed over the linear solves (amg only)
  /// direct solves: the largest relative linear residual |A x - b| / |b| left
  double worst_direct_residual = 0;
  double initial_residual = 0, final_residual = 0;
  /// |R_k| / |R_0| after each nonlinear step, over all calls of solve_nonlinear() in order
  /// (|R_0| the residual of the initial guess of the first call)
  std::vector<double> residual_history;
  bool converged = false;
  std::string message;
};

struct ForceTorque { double fx = 0, fy = 0, torque = 0; };

/// Stress state evaluated at one point.
struct PointState {
  Vec2 velocity;
  double pressure = 0, viscosity = 0, inertial_number = 0;
  dealii::SymmetricTensor<2, dim> stress;  ///< sigma = -p I + 2 eta D
};

class FlowProblem {
 public:
  FlowProblem(dealii::Triangulation<dim>& tria, const ProblemSetup& setup);

  /// setup_system(), initial guess, then the nonlinear iterations (solve_nonlinear()).
  void run();
  /// Picard then Newton iterations from the current solution with @p settings; the counts in
  /// report() accumulate over calls (continuation stages).
  void solve_nonlinear(const NonlinearSettings& settings);
  /// Change the viscosity model or the inertia between continuation stages.
  void set_viscosity(const ViscosityModel* viscosity) { setup_.viscosity = viscosity; }
  void set_inertia_density(double rho) { setup_.inertia_density = rho; }

  void setup_system();
  /// Assemble the residual R(state) (constrained rows zero) and, if @p matrix, the Jacobian
  /// (@p newton) or the Picard matrix (eta frozen) into system_matrix.
  double assemble_system(const VectorType& state, bool matrix, bool newton, VectorType& residual);
  /// Solve system_matrix * update = -residual; update satisfies zero constraints. Direct
  /// (MUMPS through Trilinos Amesos on the whole matrix, any number of ranks), or FGMRES to
  /// |K update + residual| <= @p relative_tolerance |residual| (amg).
  /// Returns the number of Krylov iterations (0 for the direct solver).
  int solve(const VectorType& residual, VectorType& update, double relative_tolerance = 1e-12);
  /// <directory>/<basename>.vtu (one file; written with MPI I/O by all ranks together when
  /// distributed). Collective.
  void output_results(const std::string& directory, const std::string& basename) const;

  // ---- post-processing
  // All of these are collective (every rank calls them, every rank gets the global value).
  /// Force and torque (about @p centre) of the medium on the boundary @p id from the
  /// consistent reaction (unconstrained volume residual tested with rigid motions).
  ForceTorque reaction(dealii::types::boundary_id id, const Point2& centre) const;
  /// Same by integration of sigma.n over the boundary faces (diagnostic).
  ForceTorque surface_integral(dealii::types::boundary_id id, const Point2& centre) const;
  /// State at a boundary point of @p id closest in angle to @p angle about @p centre.
  PointState boundary_state(dealii::types::boundary_id id, const Point2& centre, double angle,
                            Vec2& normal_out_of_medium, Point2& where) const;
  /// Consistent traction of the medium on the boundary @p id: the nodal reaction forces turned
  /// into a traction field t_h in the trace of the velocity space, M_Gamma t_h = -R (M_Gamma the
  /// boundary mass matrix). Converges like the reaction, faster than sigma(grad u_h).n.
  /// Returns t_h at the boundary point closest in angle to @p angle about @p centre.
  Vec2 consistent_traction(dealii::types::boundary_id id, const Point2& centre, double angle) const;
  /// Area fractions of the medium: [0] where it is sheared beyond the viscosity model's
  /// regularisation (|D| > regularised_strain_rate()), [1] the part of that where the model is
  /// ill posed at the local I (ViscosityModel::well_posedness() > 0), [2] the part of the
  /// layer @p r0 <= |x - @p centre| < @p r1 (the medium next to an intruder of radius r0) that
  /// is sheared with I above @p high_i (where mu(I) is ill posed at high I). Collective.
  std::array<double, 3> ill_posed_share(const Point2& centre, double r0, double r1,
                                        double high_i) const;
  /// State at an arbitrary point; false when the point is not in the mesh.
  bool point_state(const Point2& x, PointState& out) const;
  /// States at many points with one reduction: each point is evaluated by the lowest rank that
  /// owns a cell containing it; found[k] = 0 when no cell contains points[k].
  std::vector<PointState> point_states(const std::vector<Point2>& points,
                                       std::vector<char>& found) const;
  /// L2 velocity, H1-seminorm velocity and L2 pressure errors against exact fields
  /// (pressure compared after removing the mean difference when @p remove_mean_pressure).
  std::array<double, 3> errors(
      const VectorField& u, const std::function<dealii::Tensor<2, dim>(const Point2&)>& grad_u,
      const ScalarField& p, bool remove_mean_pressure) const;

  // ---- access
  const dealii::DoFHandler<dim>& dof_handler() const { return dof_handler_; }
  const VectorType& solution() const { return solution_; }
  /// Write access to the state; drops the cached consistent traction.
  VectorType& solution() { traction_id_ = -1; return solution_; }
  /// A zero vector with the layout of the solution (owned entries).
  VectorType make_vector() const;
  /// A copy of @p v with the ghost entries of this rank (for evaluations on its cells).
  VectorType ghosted(const VectorType& v) const;
  const MatrixType& system_matrix() const { return system_matrix_; }
  const dealii::AffineConstraints<double>& zero_constraints() const { return zero_constraints_; }
  const dealii::AffineConstraints<double>& nonzero_constraints() const {
    return nonzero_constraints_;
  }
  const NonlinearReport& report() const { return report_; }
  const dealii::Mapping<dim>& mapping() const { return mapping_; }
  MPI_Comm communicator() const { return comm_; }
  unsigned int n_ranks() const;
  void interpolate_initial_guess();

 private:
  /// Calls @p visit with face values at the boundary point of boundary @p id seen at
  /// @p angle (rad) from @p centre, on this rank's cells: once, or twice when the angle falls
  /// on a vertex shared by two faces (possibly of two ranks). Returns the number of visits on
  /// this rank (the callers sum over the ranks); throws on every rank when there is none on
  /// any (@p who names the caller in the message). Collective.
  int visit_boundary_at_angle(
      dealii::types::boundary_id id, const Point2& centre, double angle,
      dealii::UpdateFlags flags, const char* who,
      const std::function<void(const dealii::FEFaceValues<dim>&)>& visit) const;

  void make_constraints(dealii::AffineConstraints<double>& c, bool homogeneous) const;
  /// The line of BoundarySpec::mean_pressure in @p c (after the other constraints).
  void add_mean_pressure_constraint(dealii::AffineConstraints<double>& c, bool homogeneous) const;
  /// Residual (and matrix when @p matrix != nullptr) at @p state. With @p reaction_mode, only
  /// the volume terms, added without constraints (for the reaction forces).
  /// With @p schur_mass, also the pressure mass matrix weighted by 1/eta (the Schur
  /// complement approximation of the block preconditioner).
  /// @p state must be ghosted (see ghosted()); @p residual is reinitialised (owned entries).
  double assemble_impl(const VectorType& state, MatrixType* matrix, bool newton,
                       VectorType& residual, bool reaction_mode,
                       MatrixType* schur_mass = nullptr) const;
  /// Work arrays of one cell's assembly (assembly.cc).
  struct AssemblyScratch;
  /// The volume terms of the residual (and matrices) on the cell of @p s, into its local ones.
  void assemble_cell_volume(AssemblyScratch& s, const VectorType& state, bool matrix, bool newton,
                            bool schur) const;
  /// The traction and wall-friction terms on the boundary faces of @p cell, into @p s.
  void assemble_cell_boundary(AssemblyScratch& s,
                              const dealii::DoFHandler<dim>::active_cell_iterator& cell,
                              const VectorType& state, bool matrix, bool newton) const;
  /// The wall-friction terms of the face of @p s (FrictionWall), into its local ones.
  void add_friction_terms(AssemblyScratch& s, const VectorType& state, bool matrix,
                          bool newton) const;
  /// The dilatant continuity's boundary flux on @p face of @p cell (DilatancyLaw), into @p s.
  void add_dilatancy_flux(AssemblyScratch& s,
                          const dealii::DoFHandler<dim>::active_cell_iterator& cell,
                          const dealii::DoFHandler<dim>::face_iterator& face,
                          const VectorType& state, bool matrix, bool newton) const;
  /// The local residual and matrices of @p s into the global ones (local-to-global).
  void distribute_cell(const AssemblyScratch& s, MatrixType* matrix, VectorType& residual,
                       bool reaction_mode, MatrixType* schur_mass) const;
  /// Vectors and outcome of one nonlinear step (nonlinear_solver.cc).
  struct NonlinearWork;
  struct NonlinearStep;
  /// One Newton (with line search) or Picard step from solution_ at |R| = @p r.
  NonlinearStep nonlinear_step(NonlinearWork& w, bool newton, bool nonlinear, double r,
                               double r_ref);
  /// Whether the Newton steps have stalled (NonlinearSettings::stall_window), @p log_steps
  /// the log2 of the last steps' lengths (updated).
  bool stalled(const NonlinearSettings& nl, bool newton_phase, const NonlinearStep& step,
               std::deque<double>& log_steps) const;
  /// The merit's weights: the inverse |diagonal| of the velocity block, 1 on the pressure rows.
  void jacobi_weights(VectorType& weight) const;
  /// The line-search merit of the residual @p v (weighted or plain norm). Collective.
  double merit(const VectorType& v, const VectorType& weight, bool scaled) const;
  /// Backtracking along the update from solution_; true when a step was accepted.
  bool line_search(NonlinearWork& w, double m0, bool scaled, double r, bool nonlinear,
                   NonlinearStep& step);
  /// The progress lines of solve_nonlinear(): its start, then one per step.
  void log_nonlinear_start(double r0) const;
  void log_nonlinear_step(const NonlinearStep& step, int it, double relative,
                          bool iterative) const;
  /// The message of a solve that did not converge, with its residual history.
  void report_nonconvergence(double relative);
  /// MUMPS on the whole matrix, its linear residual checked (linear_solver.cc).
  void solve_direct(const VectorType& residual, VectorType& update);
  /// Before MUMPS's first analysis on a mesh: the measured rule for its memory; throws
  /// OutOfMemory when it cannot fit (direct_solver.cc).
  void screen_direct_memory();
  /// After that analysis: MUMPS's own estimate (its INFOG array); throws OutOfMemory when the
  /// factorisation cannot fit, logs the estimate otherwise.
  void check_direct_memory(const int* infog);
  /// Throws OutOfMemory: the unknowns, @p need bytes, the room left, where @p source comes from.
  [[noreturn]] void refuse_direct_solve(double need, const grainlift::MemoryRoom& room,
                                        bool short_here, const char* source) const;
  /// FGMRES with the block upper-triangular preconditioner (see flow_problem.cc).
  int solve_iterative(const VectorType& rhs, VectorType& x, double relative_tolerance);
  /// Locally owned entries of the reaction -R (unconstrained volume residual) on the velocity
  /// dofs of boundary @p id, gathered on every rank.
  std::map<dealii::types::global_dof_index, double> boundary_reaction(
      dealii::types::boundary_id id) const;
  /// The state from D, p and u at the point @p unit (reference coordinates) of @p cell: a
  /// FieldViscosity (the nonlocal model's) reads its field there.
  PointState make_state(const dealii::SymmetricTensor<2, dim>& D, double p, const Vec2& u,
                        const dealii::Triangulation<dim>::cell_iterator& cell,
                        const Point2& unit) const;
  /// make_state() at the point @p q of the face values @p ffv.
  PointState make_state(const dealii::SymmetricTensor<2, dim>& D, double p, const Vec2& u,
                        const dealii::FEFaceValues<dim>& ffv, unsigned int q) const;
  void log(const std::string& s) const { if (setup_.log) setup_.log(s); }

  int mpi_ready_;  ///< MPI is initialised before any Trilinos member is built
  dealii::Triangulation<dim>& tria_;
  MPI_Comm comm_;
  ProblemSetup setup_;
  dealii::FESystem<dim> fe_;
  dealii::MappingQCache<dim> mapping_;  ///< Q2 isoparametric, support points cached once
  dealii::DoFHandler<dim> dof_handler_;
  dealii::AffineConstraints<double> zero_constraints_, nonzero_constraints_;
  // dofs numbered velocity first (n_u_ of them), then pressure: two blocks
  dealii::types::global_dof_index n_u_ = 0;
  std::vector<dealii::IndexSet> owned_, relevant_;  ///< per block
  /// the dofs of BoundarySpec::mean_pressure's line (empty without it), set by make_constraints
  mutable dealii::IndexSet mean_pressure_rows_;
  MatrixType system_matrix_;
  VectorType solution_;
  // ---- direct solver: MUMPS on the whole matrix (the blocks copied into it)
  dealii::TrilinosWrappers::SparseMatrix direct_matrix_;
  /// MUMPS with its analysis of this mesh's matrix, kept between solves (direct_solver.cc);
  /// none until the mesh's first direct solve, which checks the memory
  struct DirectFactorization;
  struct DirectFactorizationDeleter {
    void operator()(DirectFactorization* d) const;
  };
  std::unique_ptr<DirectFactorization, DirectFactorizationDeleter> direct_;
  /// DirectFactorization::destination for this mesh's blocks (direct_solver.cc)
  void map_blocks_into_direct_matrix();
  /// MUMPS's analysis of @p d's matrix; the memory checked after the mesh's first.
  void analyse(DirectFactorization& d);
  /// Factorisation and solve on @p d's analysis: |A x - b| / |b|, or infinity where the
  /// factorisation on a @p kept analysis failed (the caller analyses again).
  double factorise_and_solve(DirectFactorization& d, bool kept);
  // ---- block preconditioner (LinearSolver::amg)
  MatrixType schur_mass_;  ///< only the (p,p) block is used
  std::vector<std::vector<bool>> velocity_constant_modes_;
  NonlinearReport report_;
  double tangent_floor_ = 0;  ///< NonlinearSettings::tangent_floor of the current solve
  mutable std::unique_ptr<dealii::GridTools::Cache<dim>> cache_;
  /// nodal consistent traction on the boundary traction_id_ (velocity dofs of all ranks)
  mutable std::map<dealii::types::global_dof_index, double> traction_;
  mutable int traction_id_ = -1;
};

}  // namespace grainlift::continuum::internal
