// solve_flow(): the cylinder problem (geometry, boundary conditions, outputs) on top of the
// FlowProblem engine. Conventions: docs/continuum-model.md (theta from V, counter-clockwise).
#include "grainlift/continuum/solver.h"

#include <deal.II/base/mpi.h>
#include <deal.II/distributed/grid_refinement.h>
#include <deal.II/distributed/solution_transfer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/fe/fe_values_extractors.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_refinement.h>
#include <deal.II/numerics/error_estimator.h>
#include <deal.II/numerics/solution_transfer.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/grid/manifold_lib.h>
#include <deal.II/grid/tria.h>

#include <chrono>
#include <deque>
#include <map>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <memory>
#include <set>
#include <sstream>
#include <stdexcept>

#include "flow_problem.h"
#include "grainlift/continuum/errors.h"
#include "grainlift/continuum/mpi_session.h"
#include "grainlift/continuum/mu_i_rheology.h"

namespace grainlift::continuum {

using namespace dealii;
using internal::FlowProblem;
using internal::Point2;
using internal::ProblemSetup;
using internal::Vec2;

namespace {

// Boundary ids of GridGenerator::plate_with_a_hole(colorize = true).
constexpr types::boundary_id kLeft = 0, kRight = 1, kBottom = 2, kTop = 3, kHole = 4;

void require(bool ok, const std::string& what) {
  if (!ok) throw ConfigError("continuum: " + what);
}

bool finite(double x) { return std::isfinite(x); }

/// Sizes of the padding cells between the central block (half-size b) and the box edge
/// (distance pad): the first is b, each next 1.4 times larger, scaled to fit exactly.
std::vector<double> padding_steps(double b, double pad) {
  std::vector<double> steps;
  if (pad <= 1e-12 * b) return steps;
  double sum = 0, s = b;
  while (sum < pad * (1 - 1e-9)) {
    steps.push_back(s);
    sum += s;
    s *= 1.4;
  }
  for (double& x : steps) x *= pad / sum;
  return steps;
}

/// Box [-W, W] x [-H, H] with a hole of radius R at the origin. A square block of half-size
/// b = 2R around the hole (8 cells, polar manifold on the hole, transfinite interpolation inside)
/// is merged into a tensor grid whose cells grow geometrically (ratio 1.4) away from the block.
/// Boundary ids: 0 x = -W, 1 x = W, 2 y = -H, 3 y = H, 4 the hole. After @p refinement global
/// refinements the block is refined once more (the mesh is finest at the intruder).
///
/// One MPI rank: a serial Triangulation. Several: a parallel::distributed::Triangulation (p4est)
/// made from the vertices and cells of the same coarse mesh; the ids and the manifolds are then
/// set on the distributed mesh itself, whose coarse mesh every rank holds whole, so the
/// transfinite interpolation is initialised on exactly the serial coarse cells. (Copying the
/// decorated serial mesh with copy_triangulation instead made TransfiniteInterpolationManifold::
/// initialize() throw ExcTransformationFailed in an earlier attempt.) The refinement is the
/// same on both; a rank flags only its own cells. The serial mesh limits the level jump to one
/// across vertices too (limit_level_difference_at_vertices), as p4est's 2:1 balance does: the
/// adaptive cycles then refine the same cells on one and on N ranks (with faces only, a cell
/// touching a block corner two levels finer would stay coarse on one process and be refined by
/// p4est). Uniform meshes never have such a jump: the rule changes nothing there.
class IntruderMesh {
 public:
  IntruderMesh(double R, double W, double H, int refinement) : R_(R), W_(W), H_(H) {
    b_ = std::min(2 * R, 0.5 * (R + std::min(W, H)));
    if (MpiSession::size() == 1) {  // (MPI may not even be initialised)
      tria_ = std::make_unique<Triangulation<2>>(
          Triangulation<2>::limit_level_difference_at_vertices);
      make_coarse(*tria_);
    } else {
      Triangulation<2> coarse;
      make_coarse(coarse);
      std::vector<CellData<2>> cells(coarse.n_cells(0));
      for (const auto& cell : coarse.cell_iterators_on_level(0))
        for (const unsigned int v : cell->vertex_indices())
          cells[cell->index()].vertices[v] = cell->vertex_index(v);
      tria_ = std::make_unique<parallel::distributed::Triangulation<2>>(MPI_COMM_WORLD);
      tria_->create_triangulation(coarse.get_vertices(), cells, SubCellData());
    }
    decorate(*tria_);
    tria_->refine_global(refinement);
    for (const auto& cell : tria_->active_cell_iterators())
      if (cell->is_locally_owned() && in_block(cell->center())) cell->set_refine_flag();
    tria_->execute_coarsening_and_refinement();
  }
  Triangulation<2>& tria() { return *tria_; }

 private:
  bool in_block(const Point2& x) const { return std::abs(x[0]) < b_ && std::abs(x[1]) < b_; }

  void make_coarse(Triangulation<2>& tria) const {
    const double W = W_, H = H_;
    const double b = b_;
    const auto steps_along = [b](double half) {
      const std::vector<double> pad = padding_steps(b, half - b);
      std::vector<double> steps(pad.rbegin(), pad.rend());
      steps.push_back(b);
      steps.push_back(b);
      steps.insert(steps.end(), pad.begin(), pad.end());
      return steps;
    };
    Triangulation<2> outer, outer_holed, block;
    GridGenerator::subdivided_hyper_rectangle(outer, {steps_along(W), steps_along(H)},
                                              Point2(-W, -H), Point2(W, H), false);
    std::set<Triangulation<2>::active_cell_iterator> central;
    for (const auto& cell : outer.active_cell_iterators())
      if (in_block(cell->center())) central.insert(cell);
    GridGenerator::create_triangulation_with_removed_cells(outer, central, outer_holed);
    GridGenerator::hyper_cube_with_cylindrical_hole(block, R_, b, 1.0, 1, false);
    GridGenerator::merge_triangulations(outer_holed, block, tria, 1e-9 * R_);
  }

  /// Boundary and manifold ids, the polar and transfinite-interpolation manifolds.
  void decorate(Triangulation<2>& tria) const {
    tria.reset_all_manifolds();
    tria.set_all_manifold_ids(numbers::flat_manifold_id);
    const double tol = 1e-6 * R_;
    for (const auto& cell : tria.active_cell_iterators())
      if (in_block(cell->center())) cell->set_all_manifold_ids(1);
    for (const auto& cell : tria.active_cell_iterators())
      for (const auto& face : cell->face_iterators()) {
        if (!face->at_boundary()) continue;
        const Point2 c = face->center();
        if (std::abs(face->vertex(0).norm() - R_) < tol && std::abs(face->vertex(1).norm() - R_) < tol) {
          face->set_boundary_id(kHole);
          face->set_manifold_id(0);
        } else if (std::abs(c[0] + W_) < tol) face->set_boundary_id(kLeft);
        else if (std::abs(c[0] - W_) < tol) face->set_boundary_id(kRight);
        else if (std::abs(c[1] + H_) < tol) face->set_boundary_id(kBottom);
        else face->set_boundary_id(kTop);
      }
    tria.set_manifold(0, PolarManifold<2>(Point2()));
    TransfiniteInterpolationManifold<2> tfi;
    tfi.initialize(tria);
    tria.set_manifold(1, tfi);
  }

  double R_, W_, H_, b_ = 0;
  std::unique_ptr<Triangulation<2>> tria_;
};

}  // namespace

void validate_config(const ContinuumConfig& c) {
  require(finite(c.intruder_diameter) && c.intruder_diameter > 0, "intruder_diameter must be > 0");
  require(finite(c.half_width) && c.half_width > c.intruder_diameter,
          "half_width must be > intruder_diameter");
  require(finite(c.half_height) && c.half_height > c.intruder_diameter,
          "half_height must be > intruder_diameter");
  require(finite(c.intruder_velocity[0]) && finite(c.intruder_velocity[1]), "intruder_velocity must be finite");
  require(finite(c.intruder_omega), "intruder_omega must be finite");
  require(finite(c.gravity[0]) && finite(c.gravity[1]), "gravity must be finite");
  require(finite(c.bulk_density) && c.bulk_density > 0, "bulk_density must be > 0");
  require(finite(c.ambient_pressure) && c.ambient_pressure > 0, "ambient_pressure must be > 0");
  // the lithostatic pressure P0 + rho g.x must not be negative on the box (0 is allowed: a
  // box whose top is the free surface)
  for (const double sx : {-1.0, 1.0})
    for (const double sy : {-1.0, 1.0}) {
      const double p = c.ambient_pressure + c.bulk_density * (c.gravity[0] * sx * c.half_width +
                                                              c.gravity[1] * sy * c.half_height);
      require(p >= -1e-9 * c.ambient_pressure,
              "ambient_pressure too small: the lithostatic pressure P0 + rho g.x is negative in a "
              "corner of the box (the box reaches above the free surface)");
    }
  const RheologyParams& r = c.rheology;
  require(r.mu_s >= 0 && r.mu_2 > r.mu_s, "rheology needs 0 <= mu_s < mu_2");
  require(r.I0 > 0, "rheology I0 must be > 0");
  require(r.grain_diameter > 0, "rheology grain_diameter must be > 0");
  require(r.solid_density > 0, "rheology solid_density must be > 0");
  require(r.delta >= 0, "rheology delta must be >= 0");
  require(r.regularisation != Regularisation::chauchat_medale || r.delta > 0 || r.eta_max < HUGE_VAL,
          "chauchat_medale needs delta > 0 or a finite eta_max");
  require(r.eta_min >= 0 && r.eta_max > r.eta_min, "rheology needs 0 <= eta_min < eta_max");
  if (r.regularisation == Regularisation::barker_gray) {
    // the low-I branch is well posed only when it joins mu(I) where mu(I) itself is
    const InertialRange w = well_posed_range(r);
    require(!w.empty(), "barker_gray needs mu_s, mu_2, I0 for which mu(I) is well posed in some "
                        "range of I (Barker et al. 2015); these give none");
    std::ostringstream range;
    range << "(" << w.low << ", " << w.high << ")";
    require(r.barker_gray_IN == 0 || (r.barker_gray_IN > w.low && r.barker_gray_IN < w.high),
            "barker_gray_IN must be 0 (automatic) or inside the well-posed range " + range.str() +
                " of mu(I)");
  }
  require(c.wall_friction >= 0, "wall_friction must be >= 0");
  require(c.wall_slip_regularisation >= 0, "wall_slip_regularisation must be >= 0");
  require(c.inertia_threshold >= 0, "inertia_threshold must be >= 0");
  require(c.refinement >= 0 && c.refinement <= 7, "refinement must be in [0, 7]");
  require(c.adaptive_cycles >= 0 && c.adaptive_cycles <= 5, "adaptive_cycles must be in [0, 5]");
  require(c.nonlinear_tolerance > 0 && c.nonlinear_tolerance < 1, "nonlinear_tolerance must be in (0, 1)");
  require(c.max_nonlinear_iterations >= 1, "max_nonlinear_iterations must be >= 1");
  require(c.picard_iterations >= 0, "picard_iterations must be >= 0");
  for (const double t : c.surface_theta) require(finite(t), "surface_theta values must be finite");
  if (c.fields.enabled)
    require(c.fields.spacing > 0 && c.fields.nx > 0 && c.fields.ny > 0,
            "fields need spacing > 0, nx > 0 and ny > 0");
}

ContinuumOutput solve_flow(const ContinuumConfig& c,
                           const std::function<void(const std::string&)>& log) {
  validate_config(c);
  const auto say = [&log](const std::string& s) { if (log) log(s); };
  ContinuumOutput out;
  try {
    const double R = 0.5 * c.intruder_diameter, W = c.half_width, H = c.half_height;
    const Vec2 V({c.intruder_velocity[0], c.intruder_velocity[1]});
    const Vec2 g({c.gravity[0], c.gravity[1]});
    const double omega = c.intruder_omega, rho = c.bulk_density, P0 = c.ambient_pressure;
    const double speed = V.norm();
    const double vref = std::max(speed, std::abs(omega) * R);

    // ---- mesh (see IntruderMesh)
    IntruderMesh mesh(R, W, H, c.refinement);
    Triangulation<internal::dim>& tria = mesh.tria();

    // ---- physics
    MuIRheology rheology(c.rheology);
    // The problem with gravity g_used: body force rho g, far field at P0 + rho g.x.
    const auto make_setup = [&](const Vec2& g_used) {
      const auto p_lith = [=](const Point2& x) { return P0 + rho * (g_used * x); };
      ProblemSetup setup;
      setup.viscosity = &rheology;
      setup.log = log;
      setup.linear_solver = c.linear_solver;
      setup.schur_approximation = c.schur_approximation;
      if (g_used.norm() > 0) setup.body_force = [=](const Point2&) { return Vec2(rho * g_used); };
      // far field: Dirichlet u = -V where the flow enters or slides along the box, the
      // lithostatic traction -p_lith n where it leaves (or everywhere if V = 0).
      const auto far_velocity = [=](const Point2&) { return Vec2(-V); };
      const auto lithostatic = [=](const Point2& x, const Vec2& n) { return Vec2(-p_lith(x) * n); };
      const std::pair<types::boundary_id, Vec2> sides[] = {{kLeft, Vec2({-1, 0})},
                                                           {kRight, Vec2({1, 0})},
                                                           {kBottom, Vec2({0, -1})},
                                                           {kTop, Vec2({0, 1})}};
      for (const auto& [id, n] : sides) {
        if (speed == 0 || (-V) * n > 1e-12 * speed)
          setup.bc.traction[id] = lithostatic;
        else
          setup.bc.dirichlet[id] = far_velocity;
      }
      const auto wall_velocity = [omega](const Point2& x) { return Vec2({-omega * x[1], omega * x[0]}); };
      if (c.wall == WallCondition::no_slip) {
        setup.bc.dirichlet[kHole] = wall_velocity;
      } else {
        internal::FrictionWall w;
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
    };
    // linearised gravity: the nonlinear solve is the base state without gravity
    const bool linearised = c.linearised_gravity && g.norm() > 0;
    const ProblemSetup setup = make_setup(linearised ? Vec2() : g);
    out.inertia_used = setup.inertia_density > 0;

    // ---- continuation: the target problem is approached through stages of the case's friction
    // law (Jop's mu(I), or Barker-Gray's) with the strain-rate regularisation delta_k = 0.1
    // gamma_ref, 0.01 gamma_ref, ... (> 2 delta, > 1e-6 gamma_ref), gamma_ref = v_ref / R,
    // without inertia, each solved to 1e-3 |R_0|; the last stage is the requested rheology and
    // inertia, solved to nonlinear_tolerance |R_0|. A stage that does not converge is retried
    // from the last converged state after an intermediate stage at the geometric mean of the
    // two deltas (at most kMaxSplits times in a run): a factor of 10 in delta is too large a
    // step for some problems (e.g. low P0 with an opening behind the intruder at refinement 2).
    const double gamma_ref = std::max(vref, 1e-12) / R;
    struct Stage { double delta; bool final; };
    std::vector<double> schedule;  // the intermediate deltas
    for (double delta = 0.1 * gamma_ref;
         c.continuation && delta > 2 * c.rheology.delta && delta > 1e-6 * gamma_ref; delta *= 0.1)
      schedule.push_back(delta);
    std::deque<Stage> todo;
    for (const double delta : schedule) todo.push_back({delta, false});
    todo.push_back({c.rheology.delta, true});
    constexpr int kMaxSplits = 6, kStageIterations = 20;
    int splits = 0, stage_number = 0;
    double done_delta = -1;  // delta of the last converged stage; < 0: none yet
    std::vector<std::unique_ptr<MuIRheology>> stage_rheology;  // outlive the solves
    const double rho_inertia = setup.inertia_density;
    FlowProblem problem(tria, setup);
    problem.setup_system();
    problem.interpolate_initial_guess();
    // runs the stages in todo, splitting those that fail
    const auto run_stages = [&]() {
      while (!todo.empty()) {
        const Stage st = todo.front();
        internal::NonlinearSettings nl = setup.nonlinear;
        nl.picard_iterations = stage_number == 0 ? c.picard_iterations : 0;
        std::ostringstream os;
        if (st.final) {
          problem.set_viscosity(&rheology);
          problem.set_inertia_density(rho_inertia);
          os << "continuum: final stage";
        } else {
          RheologyParams prm = c.rheology;
          prm.delta = st.delta;
          stage_rheology.push_back(std::make_unique<MuIRheology>(prm));
          problem.set_viscosity(stage_rheology.back().get());
          problem.set_inertia_density(0);
          nl.relative_tolerance = std::max(1e-3, c.nonlinear_tolerance);
          // a stage that needs more than 20 steps is better split than pushed
          nl.max_iterations = std::min(nl.max_iterations, kStageIterations);
          os << "continuum: continuation stage " << stage_number + 1 << ", delta = " << st.delta
             << " 1/s";
        }
        say(os.str());
        const internal::VectorType saved = problem.solution();
        problem.solve_nonlinear(nl);
        ++stage_number;
        if (!problem.report().converged && done_delta > 0 && splits < kMaxSplits) {
          // back to the last converged state, through an intermediate delta
          problem.solution() = saved;
          const double mid = std::sqrt(done_delta * st.delta);
          todo.push_front({mid, false});
          ++splits;
          std::ostringstream msg;
          msg << "continuum: stage did not converge; retrying through delta = " << mid << " 1/s";
          say(msg.str());
          continue;
        }
        if (problem.report().converged) done_delta = st.delta;
        todo.pop_front();
      }
    };
    // Test hook (FemMpi.FailureOnOneRankEndsEveryRank): GRAINLIFT_TEST_FAIL_ON_RANK=R makes
    // rank R alone throw here, as a bad_alloc or a failed factorisation on one rank would.
    if (const char* fail_on = std::getenv("GRAINLIFT_TEST_FAIL_ON_RANK");
        fail_on && std::string(fail_on) == std::to_string(MpiSession::rank()))
      throw std::runtime_error("GRAINLIFT_TEST_FAIL_ON_RANK=" + std::string(fail_on) +
                               ": test failure before the nonlinear solve");
    run_stages();

    // ---- adaptive refinement: Kelly's indicator (jump of the velocity gradient across faces,
    // weighted by the face size) marks the 30% of the cells with the largest values; the
    // solution is carried over to the refined mesh and the problem solved again from it.
    // Distributed mesh: each rank estimates its own cells (the ghosted solution gives the
    // neighbours across the partition), the 30% are counted over all ranks, and the old solution
    // travels with the cells (parallel::distributed::SolutionTransfer, from a ghosted vector).
    // The marked cells are those of one process, and both meshes limit level jumps across
    // vertices (see IntruderMesh): the refined mesh is the one-process mesh.
    auto* const distributed =
        dynamic_cast<parallel::distributed::Triangulation<internal::dim>*>(&tria);
    for (int cycle = 0; cycle < c.adaptive_cycles && problem.report().converged; ++cycle) {
      Vector<float> indicator(tria.n_active_cells());  // distributed: 0 on the others' cells
      const FEValuesExtractors::Vector velocity(0);
      const internal::VectorType old_ghosted = problem.ghosted(problem.solution());
      KellyErrorEstimator<internal::dim>::estimate(
          problem.mapping(), problem.dof_handler(), QGauss<internal::dim - 1>(3), {}, old_ghosted,
          indicator, problem.dof_handler().get_fe().component_mask(velocity));
      if (distributed) {
        parallel::distributed::GridRefinement::refine_and_coarsen_fixed_number(
            *distributed, indicator, 0.3, 0.0);
        parallel::distributed::SolutionTransfer<internal::dim, internal::VectorType> transfer(
            problem.dof_handler());
        transfer.prepare_for_coarsening_and_refinement(old_ghosted);
        tria.execute_coarsening_and_refinement();
        problem.setup_system();
        transfer.interpolate(problem.solution());  // owned entries
      } else {
        GridRefinement::refine_and_coarsen_fixed_number(tria, indicator, 0.3, 0.0);
        SolutionTransfer<internal::dim, internal::VectorType> transfer(problem.dof_handler());
        const internal::VectorType old_solution = problem.solution();
        tria.prepare_coarsening_and_refinement();
        transfer.prepare_for_coarsening_and_refinement(old_solution);
        tria.execute_coarsening_and_refinement();
        problem.setup_system();
        transfer.interpolate(old_solution, problem.solution());
      }
      problem.nonzero_constraints().distribute(problem.solution());
      std::ostringstream os;
      os << "continuum: adaptive cycle " << cycle + 1 << " of " << c.adaptive_cycles << ": "
         << tria.n_global_active_cells() << " cells, " << problem.dof_handler().n_dofs() << " dofs";
      say(os.str());
      // the transferred state is not a converged state of the finer mesh: approach it again
      // through the last two intermediate stages (the final delta directly can stall; so did
      // the last stage alone: its 20 steps do not converge from the transferred state, the
      // final stage then has no converged state to split from, and refinement 1 + 2 cycles
      // did not converge on reduced_phi080 nor on the Guillard study case)
      for (std::size_t i = schedule.size() > 2 ? schedule.size() - 2 : 0; i < schedule.size(); ++i)
        todo.push_back({schedule[i], false});
      if (!schedule.empty()) done_delta = -1;
      todo.push_back({c.rheology.delta, true});
      run_stages();
    }
    out.continuation_splits = splits;
    // ---- linearised gravity: one Newton step from the base state of the problem with gravity
    std::unique_ptr<FlowProblem> corrected;
    internal::VectorType du;  // the first-order correction (linearised gravity)
    if (linearised) {
      say("continuum: first-order gravity correction (one linear solve at the base state)");
      const auto t0 = std::chrono::steady_clock::now();
      corrected = std::make_unique<FlowProblem>(tria, make_setup(g));
      corrected->set_viscosity(&rheology);
      corrected->setup_system();
      corrected->solution() = problem.solution();
      internal::VectorType residual;
      corrected->assemble_system(corrected->solution(), true, true, residual);
      corrected->solve(residual, du);
      std::ostringstream os;
      out.correction_seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      os << "continuum: gravity correction: |R_g(u_0)| = " << residual.l2_norm() << ", "
         << out.correction_seconds << " s";
      say(os.str());
    }
    FlowProblem& post = corrected ? *corrected : problem;
    const auto& rep = problem.report();
    out.converged = rep.converged;
    out.message = rep.message;
    out.picard_steps = rep.picard_steps;
    out.newton_steps = rep.newton_steps;
    out.nonlinear_iterations = rep.picard_steps + rep.newton_steps;
    out.linear_iterations = rep.linear_solves;
    out.krylov_iterations = rep.krylov_iterations;
    out.initial_residual = rep.initial_residual;
    out.final_residual = rep.initial_residual > 0 ? rep.final_residual / rep.initial_residual : 0;
    // where the law is ill posed the solution depends on the mesh: say so
    const auto share = problem.ill_posed_share();
    out.sheared_share = share[0];
    out.ill_posed_share = share[1];
    if (out.ill_posed_share > 0.05) {
      const InertialRange w = well_posed_range(c.rheology);
      std::ostringstream os;
      os << "continuum: warning: in " << std::lround(100 * out.ill_posed_share)
         << "% of the sheared medium (" << std::lround(100 * out.sheared_share)
         << "% of the area) mu(I) is ill posed at the local I (Barker et al. 2015; Jop's law "
            "with these parameters only for "
         << w.low << " < I < " << w.high << "): the solution will change with the mesh. ";
      if (c.rheology.regularisation == Regularisation::barker_gray)
        os << "Barker-Gray's branch removes the ill-posedness at low I only; here the flow is "
              "too fast (I > " << w.high
           << "): raise the confining pressure or lower the speeds (docs/continuum-model.md)";
      else
        os << "continuum.regularisation = \"barker_gray\" is well posed at low I "
              "(docs/continuum-model.md)";
      say(os.str());
    }
    out.cells = static_cast<int>(tria.n_global_active_cells());
    out.dofs = static_cast<int>(problem.dof_handler().n_dofs());

    // ---- forces (consistent reaction on the hole; surface integral as a diagnostic) and the
    // surface stresses at theta measured from V counter-clockwise, from the consistent traction
    // (the reaction forces spread by the boundary mass matrix), which converges like the
    // forces; sigma(grad u_h).n at the wall converges at rate < 2
    const double phi0 = speed > 0 ? std::atan2(V[1], V[0]) : 0.0;
    // every output of a state in one vector: the reaction (fx, fy, torque), the surface
    // integral (fx, fy, torque), then sigma_n and sigma_t at the surface angles
    const std::size_t n_angles = c.surface_theta.size();
    const auto collect = [&](const FlowProblem& fp) {
      const auto reac = fp.reaction(kHole, Point2());
      const auto surf = fp.surface_integral(kHole, Point2());
      std::vector<double> v = {reac.fx, reac.fy, reac.torque, surf.fx, surf.fy, surf.torque};
      v.resize(6 + 2 * n_angles);
      for (std::size_t k = 0; k < n_angles; ++k) {
        const double phi = phi0 + c.surface_theta[k];
        const Vec2 n_body({std::cos(phi), std::sin(phi)});  // outward normal of the intruder
        const Vec2 t = fp.consistent_traction(kHole, Point2(), phi);  // medium on intruder
        const Vec2 e_phi({-n_body[1], n_body[0]});           // counter-clockwise tangent
        v[6 + k] = -(t * n_body);           // sigma_n > 0 compressive
        v[6 + n_angles + k] = t * e_phi;    // sigma_t > 0 pulls the surface counter-clockwise
      }
      return v;
    };
    std::vector<double> v;
    if (!corrected) {
      v = collect(problem);
    } else {
      // First order throughout: the outputs are linear functionals of the residual, so they
      // are taken as S(u_0; g) + dS/du . du, the derivative by a central difference along du
      // (exact for the linear gravity terms; O(h^2) for the rheology, h = 1e-4).
      const internal::VectorType u0 = problem.solution();
      constexpr double h = 1e-4;
      const auto at = [&](double t) {
        corrected->solution() = u0;
        corrected->solution().add(t, du);
        return collect(*corrected);
      };
      v = at(0);
      const std::vector<double> vp = at(h), vm = at(-h);
      for (std::size_t k = 0; k < v.size(); ++k) v[k] += (vp[k] - vm[k]) / (2 * h);
      corrected->solution() = u0;  // fields and VTU: the corrected state u_0 + du
      corrected->solution() += du;
    }
    out.fx = v[0];
    out.fy = v[1];
    out.torque = v[2];
    out.force_fx_surface = v[3];
    out.force_fy_surface = v[4];
    out.torque_surface = v[5];
    out.sigma_n.assign(v.begin() + 6, v.begin() + 6 + n_angles);
    out.sigma_t.assign(v.begin() + 6 + n_angles, v.end());
    {
      std::ostringstream os;
      os << "continuum: force (" << out.fx << ", " << out.fy << ") N/m, torque " << out.torque
         << " N [surface integral (" << out.force_fx_surface << ", " << out.force_fy_surface
         << "), " << out.torque_surface << "]";
      say(os.str());
    }

    // ---- fields on the grid (intruder frame, lab axes)
    if (c.fields.enabled) {
      const std::size_t n = static_cast<std::size_t>(c.fields.nx) * c.fields.ny;
      const double nan = std::numeric_limits<double>::quiet_NaN();
      for (auto* v : {&out.vx, &out.vy, &out.pressure, &out.sxx, &out.sxy, &out.syy}) v->assign(n, nan);
      // bin (i, j) has its lower-left corner at (x0 + i h, y0 + j h), as in the DEM; the
      // fields are the point values at the bin centres (evaluated together: one reduction)
      std::vector<Point2> points;
      std::vector<std::size_t> where;
      for (int j = 0; j < c.fields.ny; ++j)
        for (int i = 0; i < c.fields.nx; ++i) {
          const Point2 x(c.fields.x0 + (i + 0.5) * c.fields.spacing,
                         c.fields.y0 + (j + 0.5) * c.fields.spacing);
          if (x.norm() < R) continue;
          points.push_back(x);
          where.push_back(static_cast<std::size_t>(j) * c.fields.nx + i);
        }
      std::vector<char> found;
      const auto states = post.point_states(points, found);
      for (std::size_t m = 0; m < points.size(); ++m) {
        if (!found[m]) continue;
        const internal::PointState& st = states[m];
        const std::size_t k = where[m];
        out.vx[k] = st.velocity[0];
        out.vy[k] = st.velocity[1];
        out.pressure[k] = st.pressure;
        out.sxx[k] = st.stress[0][0];
        out.sxy[k] = st.stress[0][1];
        out.syy[k] = st.stress[1][1];
      }
    }
    if (!c.vtu_directory.empty()) post.output_results(c.vtu_directory, "continuum");
  } catch (const ConfigError&) {
    throw;
  } catch (const std::exception& e) {
    out.converged = false;
    out.message = std::string("continuum solver failed: ") + e.what();
    // on several ranks, a failure of this rank alone ends the run here (the others would wait
    // for it in their next collective call); one of all ranks together is reported as usual
    MpiSession::all_ranks_failed(MpiSession::FailureSite::continuum_solve, out.message, 1);
  }
  return out;
}

}  // namespace grainlift::continuum
