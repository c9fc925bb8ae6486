// Glue between the case file / shared schema and the continuum engine (conversion only).
#include "grainlift/continuum/continuum_solver.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <initializer_list>
#include <stdexcept>
#include <utility>
#include <vector>

#include "continuum_box.h"
#include "grainlift/continuum/errors.h"
#include "grainlift/continuum/fem_module.h"
#include "grainlift/continuum/solver.h"
#include "grainlift/shared/run/interrupt.h"
#include "grainlift/shared/case/case_geometry.h"
#include "grainlift/shared/errors.h"
#include "grainlift/shared/statistics/force_statistics.h"
#include "grainlift/shared/surface/surface_smoothing.h"
#include "grainlift/shared/surface/surface_stress.h"

namespace grainlift::continuum {

namespace {
/// Samples of the continuum's trace per cell of the M-grid for the kernel average: the trace
/// is continuous with kinks at the face vertices, so its modes fall like 1/k^2 and those near
/// the sampling number fold back undamped (surface_smoothing.h). On cases/demo (M = 64,
/// s = 8 deg) the smoothed traces from 1, 4, 8, 16 samples per cell differ from those from 32
/// by 1.4e-2, 8.2e-4, 2.0e-4, 3.9e-5 of the sigma_t range (sigma_n: 2.2e-3 ... 6.3e-6),
/// falling like 1/oversample^2.
constexpr int kSurfaceOversample = 8;

/// The angles (from V) at which the engine samples the trace: the M-grid theta_m (the
/// pointwise trace), then the grid of kSurfaceOversample * M angles (the smoothed trace).
std::vector<double> surface_trace_angles(int M) {
  std::vector<double> t = surface_angle_grid(M);
  const std::vector<double> fine = surface_angle_grid(kSurfaceOversample * M);
  t.insert(t.end(), fine.begin(), fine.end());
  return t;
}

/// The engine's value for a case's choice; the loader accepts only the registry's choices, so
/// a name missing here is a bug, not bad input.
template <class T>
T choice(const std::string& name, std::initializer_list<std::pair<const char*, T>> table) {
  for (const auto& [key, value] : table)
    if (name == key) return value;
  throw std::logic_error("continuum: choice \"" + name +
                         "\" passed the loader but has no engine value");
}

/// continuum.dilatancy = "phi_i": the calibrated Phi(I) (rheology file or cache), floored at
/// its value at the top of the calibrated range; "auto": the same where the law is calibrated,
/// the model local and gravity full (the combinations "phi_i" is refused with), else none.
void set_dilatancy(const Case& c, ContinuumConfig& f) {
  const ContinuumSection& cn = c.continuum;
  if (cn.dilatancy == "none") return;
  if (cn.dilatancy == "auto" &&
      (!(cn.phi_max > 0) || f.model != ContinuumModel::local || f.linearised_gravity))
    return;
  if (!(cn.phi_max > 0))
    throw InputError(fmt::format(
        "{}: continuum.dilatancy = \"phi_i\" needs a calibrated Phi(I), and no rheology file "
        "was read (continuum.rheology_file, or `grainlift calibrate {}` for the cache); set "
        "continuum.dilatancy = \"none\" to run incompressible",
        c.source.path, c.source.path));
  f.dilatancy.enabled = true;
  f.dilatancy.phi_max = cn.phi_max;
  f.dilatancy.a = cn.phi_a;
  f.dilatancy.phi_min = std::max(cn.phi_max - cn.phi_a * cn.phi_I_max, 1e-3);
}
}  // namespace

ContinuumConfig make_continuum_config(const Case& c, const std::string& out_dir) {
  ContinuumConfig f;
  f.intruder_diameter = c.intruder.diameter;
  set_box(c, f);
  f.intruder_velocity = c.intruder.velocity;
  f.intruder_omega = c.intruder.omega;
  f.gravity = c.scene.gravity;
  f.bulk_density = c.bulk_density();
  f.ambient_pressure = c.continuum_pressure();
  if (!(f.ambient_pressure > 0))
    throw InputError(fmt::format(
        "{}: the mu(I) rheology needs a confining pressure, and this case gives none: no lid "
        "(domain.lid_pressure), no gravity with the intruder below the top of the bed, no "
        "continuum.ambient_pressure. A DEM bed without them is volume-controlled: its own "
        "pressure is measured (dem.h5 /far_field), but a continuum comparison needs the same "
        "pressure on both sides: add a lid or gravity",
        c.source.path));
  auto& rh = f.rheology;
  rh.mu_s = c.continuum.mu_s;
  rh.mu_2 = c.continuum.mu_2;
  rh.I0 = c.continuum.I0;
  rh.grain_diameter = c.grains.diameter;
  rh.solid_density = c.grains.density;
  rh.regularisation = choice<Regularisation>(
      c.continuum.regularisation, {{"barker_gray", Regularisation::barker_gray},
                                   {"chauchat_medale", Regularisation::chauchat_medale}});
  rh.delta = c.continuum.delta;
  rh.barker_gray_IN = c.continuum.barker_gray_IN;
  rh.eta_max = c.continuum.eta_max;
  rh.pressure_smoothing = c.continuum.pressure_smoothing * f.ambient_pressure;
  f.linearised_gravity = choice<bool>(c.continuum.gravity_treatment,
                                      {{"full", false}, {"linearised", true}});
  f.wall = choice<WallCondition>(
      c.continuum.wall, {{"no_slip", WallCondition::no_slip}, {"coulomb", WallCondition::coulomb}});
  f.wall_friction = c.continuum.wall_friction;
  f.wall_mu_a = c.continuum.wall_mu_a;
  f.wall_mu_b = c.continuum.wall_mu_b;
  f.wall_v0 = c.continuum.wall_v0;
  f.inertia = choice<InertiaMode>(c.continuum.inertia, {{"on", InertiaMode::on},
                                                        {"off", InertiaMode::off},
                                                        {"auto", InertiaMode::automatic}});
  f.refinement = c.continuum.refinement;
  f.adaptive_cycles = c.continuum.adaptive_cycles;
  f.wall_layers = c.continuum.wall_layers;
  f.nested = c.continuum.nested;
  f.nonlinear_tolerance = c.continuum.tolerance;
  f.max_nonlinear_iterations = c.continuum.max_iterations;
  f.picard_iterations = c.continuum.picard_iterations;
  f.linear_solver = choice<LinearSolver>(
      c.continuum.linear_solver, {{"direct", LinearSolver::direct}, {"amg", LinearSolver::amg}});
  f.model = choice<ContinuumModel>(c.continuum.model,
                                   {{"local", ContinuumModel::local},
                                    {"nonlocal_fluidity", ContinuumModel::nonlocal_fluidity}});
  f.target_error = c.continuum.target_error;
  f.nonlocal.amplitude = c.continuum.nonlocal_amplitude;
  f.nonlocal.max_iterations = c.continuum.nonlocal_iterations;
  f.nonlocal.relaxation = c.continuum.nonlocal_relaxation;
  f.nonlocal.tolerance = c.continuum.nonlocal_tolerance;
  set_dilatancy(c, f);  // after the model and the gravity treatment
  // Surface angles: the shared grid (the pointwise trace), then the oversampled grid the
  // smoothed trace is computed from (surface_trace_angles), measured from V as the engine
  // takes them (it turns them into lab angles itself).
  f.surface_theta = surface_trace_angles(c.output.angles);
  const FieldGridLayout grid = field_grid_layout(c);
  f.fields.enabled = grid.enabled;
  f.fields.x0 = grid.x0;
  f.fields.y0 = grid.y0;
  f.fields.spacing = grid.spacing;
  f.fields.nx = grid.nx;
  f.fields.ny = grid.ny;
  if (c.output.vtu) f.vtu_directory = out_dir + "/fem_vtu";
  return f;
}

namespace {

/// Where P0 comes from: "lid", "continuum.ambient_pressure" (not a pressure of the DEM bed),
/// "lithostatic", or a sum of them.
std::string pressure_source(const Case& c) {
  std::string s;
  if (c.domain.lid_pressure > 0) s = "lid";
  if (c.continuum.ambient_pressure > 0) s = "continuum.ambient_pressure";
  if (c.lithostatic_pressure() > 0) s += s.empty() ? "lithostatic" : " + lithostatic";
  return s;
}

/// The forces of the next coarser level (refinement - 1), when they were solved.
struct CoarserLevel {
  int refinement = -1;
  double drag = 0, lift = 0, torque = 0;
};

/// /surface: the kernel average of Guillard eq. (A4) that the DEM writes, from the fine
/// samples; the pointwise trace at theta_m beside it (surface_trace_angles gives the order).
SurfaceDistribution surface_result(const Case& c, const ContinuumOutput& out) {
  const int M = c.output.angles;
  const std::vector<double> fine_theta = surface_angle_grid(kSurfaceOversample * M);
  const auto fine = [&](const std::vector<double>& v) {
    return std::vector<double>(v.begin() + M, v.end());
  };
  SurfaceDistribution s;
  s.theta = surface_angle_grid(M);
  s.sigma_n = smooth_onto_grid(fine_theta, fine(out.sigma_n), M, c.output.kernel_width_deg);
  s.sigma_t = smooth_onto_grid(fine_theta, fine(out.sigma_t), M, c.output.kernel_width_deg);
  s.kernel_width_deg = c.output.kernel_width_deg;
  s.sigma_n_pointwise = std::vector<double>(out.sigma_n.begin(), out.sigma_n.begin() + M);
  s.sigma_t_pointwise = std::vector<double>(out.sigma_t.begin(), out.sigma_t.begin() + M);
  return s;
}

/// /fields: velocity, pressure and stress at the centres of the case's field grid.
FieldGrid field_result(const Case& c, const ContinuumOutput& out) {
  FieldGrid g;
  const FieldGridLayout layout = field_grid_layout(c);
  g.x = layout.x_centres();
  g.y = layout.y_centres();
  g.velocity_x = out.vx;
  g.velocity_y = out.vy;
  if (!out.pressure.empty()) g.pressure = out.pressure;
  if (!out.sxx.empty()) {
    g.stress_xx = out.sxx;
    g.stress_xy = out.sxy;
    g.stress_yy = out.syy;
  }
  return g;
}

/// The case's geometry with the FE box as the domain (lab frame) and P0 as pressure scale.
Geometry result_geometry(const Case& c, const ContinuumConfig& cfg) {
  Geometry q = case_geometry(c);
  const std::array<double, 4> e = box_edges(cfg);
  q.domain_xmin = c.intruder.position[0] + e[0];
  q.domain_xmax = c.intruder.position[0] + e[1];
  q.domain_ymin = c.intruder.position[1] + e[2];
  q.domain_ymax = c.intruder.position[1] + e[3];
  q.pressure_scale = cfg.ambient_pressure;
  return q;
}

/// The mesh-error estimate of the forces @p m: their change from the next coarser level (an
/// upper bound of the fine level's error when the forces converge with order >= 1 at a rate
/// better than 1/2 per level, as the refinement studies of the docs show).
void add_mesh_error(const MeanForces& m, const CoarserLevel& coarser, Diagnostics& d) {
  d.counts["coarser_refinement"] = coarser.refinement;
  d.values["drag_coarser"] = coarser.drag;
  d.values["lift_coarser"] = coarser.lift;
  d.values["torque_coarser"] = coarser.torque;
  d.values["drag_mesh_error"] = std::abs(m.drag - coarser.drag);
  d.values["lift_mesh_error"] = std::abs(m.lift - coarser.lift);
  d.values["torque_mesh_error"] = std::abs(m.torque - coarser.torque);
}

/// The nested levels (coarsest first) as series: mesh, forces, work.
void add_level_series(const Case& c, const ContinuumOutput& out, Diagnostics& d) {
  auto& lv = d.series;
  for (const LevelResult& l : out.levels) {
    const DragLift dl =
        project_drag_lift(l.fx, l.fy, c.intruder.velocity[0], c.intruder.velocity[1]);
    lv["level_refinement"].push_back(l.refinement);
    lv["level_dofs"].push_back(l.dofs);
    lv["level_drag"].push_back(dl.drag);
    lv["level_lift"].push_back(dl.lift);
    lv["level_torque"].push_back(l.torque);
    lv["level_nonlinear_steps"].push_back(l.nonlinear_steps);
    lv["level_seconds"].push_back(l.seconds);
    lv["level_approach"].push_back(l.approach);
    lv["level_adaptive_cycle"].push_back(l.adaptive_cycle);
  }
}

/// /diagnostics: the solve's counts and residuals, the surface integral, the choices made,
/// the mesh-error estimate against @p coarser, the nested levels and the residual history.
Diagnostics result_diagnostics(const Case& c, const ContinuumConfig& cfg,
                               const ContinuumOutput& out, const MeanForces& m,
                               const std::optional<CoarserLevel>& coarser) {
  Diagnostics d;
  d.counts = {{"converged", out.converged ? 1 : 0},
              {"cells", out.cells},
              {"dofs", out.dofs},
              {"nonlinear_iterations", out.nonlinear_iterations},
              {"picard_steps", out.picard_steps},
              {"newton_steps", out.newton_steps},
              {"linear_solves", out.linear_iterations},
              {"krylov_iterations", out.krylov_iterations},
              {"continuation_splits", out.continuation_splits},
              {"inertia_used", out.inertia_used ? 1 : 0}};
  d.values = {{"initial_residual", out.initial_residual},
              {"final_relative_residual", out.final_residual},
              {"worst_direct_residual", out.worst_direct_residual},
              {"sheared_share", out.sheared_share},
              {"ill_posed_share", out.ill_posed_share},
              {"ill_posed_wall_share", out.ill_posed_wall_share},
              {"surface_integral_fx", out.force_fx_surface},
              {"surface_integral_fy", out.force_fy_surface},
              {"surface_integral_torque", out.torque_surface}};
  if (cfg.linearised_gravity) d.values["correction_seconds"] = out.correction_seconds;
  d.texts = {{"far_field", far_field_name(cfg.far_field)},
             {"box", box_statement(c, cfg)},
             {"linear_solver", c.continuum.linear_solver},
             {"law", c.continuum.regularisation},
             {"pressure_source", pressure_source(c)},
             {"rheology_source", c.continuum.law_source}};
  if (!c.continuum.rheology_file.empty()) d.texts["rheology_file"] = c.continuum.rheology_file;
  if (c.continuum.wall_law == "measured")  // absent otherwise: today's files unchanged
    d.texts["wall_law"] = fmt::format("measured: friction {} of the [wall] table of {}",
                                      c.continuum.wall_friction, c.continuum.rheology_file);
  if (c.continuum.wall_law == "measured_slip")
    d.texts["wall_law"] = fmt::format(
        "measured_slip: mu_w(s) = {} + ({} - {}) |s| / (|s| + {} m/s), [wall] of {}",
        c.continuum.wall_mu_a, c.continuum.wall_mu_b, c.continuum.wall_mu_a,
        c.continuum.wall_v0, c.continuum.rheology_file);
  if (cfg.model == ContinuumModel::nonlocal_fluidity) {  // absent otherwise
    d.texts["continuum_model"] = fmt::format(
        "nonlocal_fluidity: A = {} ({}), xi capped at {} m, g_loc from Jop's mu(I) inverted",
        cfg.nonlocal.amplitude, c.continuum.nonlocal_amplitude_source,
        cfg.nonlocal.xi_max > 0 ? cfg.nonlocal.xi_max : cfg.intruder_diameter);
    d.counts["nonlocal_iterations"] = out.nonlocal_iterations;
    d.values["nonlocal_change"] = out.nonlocal_change;
    d.values["nonlocal_force_change"] = out.nonlocal_force_change;
  }
  if (cfg.dilatancy.enabled)  // absent otherwise
    d.texts["dilatancy"] = fmt::format(
        "phi_i (continuum.dilatancy = \"{}\"): Phi(I) = {:.4f} - {:.4f} I of {}, floored at "
        "{:.4f}; div(Phi u) = 0, weight rho Phi / phi_max g",
        c.continuum.dilatancy, cfg.dilatancy.phi_max, cfg.dilatancy.a, c.continuum.rheology_file,
        cfg.dilatancy.phi_min);
  if (cfg.target_error > 0) {  // absent otherwise
    d.values["target_error"] = cfg.target_error;
    d.values["estimated_error"] = out.estimated_error;
    d.counts["target_met"] = out.target_met ? 1 : 0;
    d.counts["stopped_at_refinement"] = out.levels.empty() ? 0 : out.levels.back().refinement;
    if (cfg.adaptive_cycles > 0)
      d.counts["stopped_at_adaptive_cycle"] =
          out.levels.empty() ? 0 : out.levels.back().adaptive_cycle;
  }
  if (coarser) add_mesh_error(m, *coarser, d);
  if (!out.levels.empty()) add_level_series(c, out, d);
  d.series["residual_history"] = out.residual_history;
  d.series["residual_stage"].assign(out.residual_stage.begin(), out.residual_stage.end());
  return d;
}

/// The run's result in the shared schema: forces, their drag and lift, /surface, /fields,
/// geometry, notes and /diagnostics.
RunResult to_result(const Case& c, const ContinuumConfig& cfg, const ContinuumOutput& out,
                    const std::optional<CoarserLevel>& coarser) {
  RunResult r;
  const double vx = c.intruder.velocity[0], vy = c.intruder.velocity[1];
  ForceSeries f;
  f.time = {0.0};
  f.fx = {out.fx};
  f.fy = {out.fy};
  f.torque = {out.torque};
  r.forces = f;
  const DragLift dl = project_drag_lift(out.fx, out.fy, vx, vy);
  MeanForces m;
  m.drag = dl.drag;
  m.lift = dl.lift;
  m.torque = out.torque;
  m.samples = 1;
  m.blocks = 0;
  r.means = m;
  if (!out.sigma_n.empty()) r.surface = surface_result(c, out);
  if (cfg.fields.enabled && !out.vx.empty()) r.fields = field_result(c, out);
  r.geometry = result_geometry(c, cfg);
  r.meta.notes = fmt::format("{} cells, {} unknowns, {} nonlinear steps, final relative residual "
                             "{:.3g}, ill-posed share {:.3g} (all in /diagnostics)",
                             out.cells, out.dofs, out.nonlinear_iterations, out.final_residual,
                             out.ill_posed_share);
  r.diagnostics = result_diagnostics(c, cfg, out, m, coarser);
  return r;
}

/// The sentence of a solve that ran out of memory (or would have): the need and the limit,
/// what was kept, and the ways out.
std::string out_of_memory_sentence(const std::string& what, const ContinuumConfig& cfg,
                                   const std::string& saved_level, int fits,
                                   const std::string& out_dir) {
  return fmt::format(
      "the continuum ran out of memory: {}. {}. Ways out: {}continuum.refinement = {} or "
      "lower, or more machines (mpirun -n N across hosts)",
      what,
      saved_level.empty() ? "No level had converged"
                          : fmt::format("{}/fem.h5 holds {} (marked partial)", out_dir,
                                        saved_level),
      cfg.linear_solver == LinearSolver::direct
          ? "continuum.linear_solver = \"amg\" (iterative: a fraction of the memory), "
          : "",
      std::max(fits, 0));
}

}  // namespace

SolverEntry solver_entry() {
  SolverEntry e;
  e.name = "fem";
  e.description = kFemSolverDescription;
  e.run = [](const Case& c, const RunOptions& opt, ProgressReporter& progress) {
    ContinuumConfig cfg = make_continuum_config(c, opt.out_dir);
    // Ctrl-C / SIGTERM (interrupt.h): no further refinement; the last converged mesh is the
    // result, marked partial
    cfg.stop_refining = [] { return interrupt_signal() != 0; };
    // each converged mesh is written (partial) before it is refined: a killed study keeps it.
    // Every MPI rank post-processes the level (collective), the writer alone writes it.
    std::string saved_level;  // the converged mesh last written as a partial result
    int saved_refinement = -1;  // its nested level (-1: none, or an adaptive cycle)
    if (cfg.nested || cfg.adaptive_cycles > 0) {
      cfg.level_converged = [&](const ContinuumOutput& level) {
        if (!opt.save_partial) return;
        saved_level = fmt::format("the converged mesh of {} cells", level.cells);
        if (!level.levels.empty() && level.levels.back().adaptive_cycle == 0)
          saved_refinement = level.levels.back().refinement;
        RunResult r = to_result(c, cfg, level, std::nullopt);
        r.meta.partial = true;
        r.meta.notes += fmt::format(
            "; PARTIAL: the converged mesh of {} cells before refining it further (refinement "
            "{} asked for{}); the run that wrote it did not finish",
            level.cells, cfg.refinement,
            cfg.adaptive_cycles > 0 ? fmt::format(", then {} adaptive cycles", cfg.adaptive_cycles)
                                    : std::string());
        opt.save_partial(std::move(r));
      };
    }
    progress.message(box_statement(c, cfg));
    if (!c.pressure_matched())
      progress.message(fmt::format(
          "warning: P0 = {:g} Pa includes continuum.ambient_pressure = {:g} Pa, which the "
          "DEM bed of this case does not have (only a lid or gravity confine it; it carries its "
          "own pressure, dem.h5 /far_field): DEM and FEM are not at the same pressure here",
          cfg.ambient_pressure, c.continuum.ambient_pressure));
    ContinuumOutput out;
    std::optional<CoarserLevel> coarser;
    try {
      // (the nonlocal model: from its nested levels, which it solves each; without them its
      // coarser level would be a second whole splitting)
      const bool estimate = c.continuum.mesh_error_estimate && cfg.refinement >= 1 &&
                            cfg.adaptive_cycles == 0 &&
                            (cfg.model == ContinuumModel::local || cfg.nested);
      if (estimate && !cfg.nested) {
        // an independent solve of the coarser mesh (the requested level does not start from
        // it, so its result is the same with and without the estimate)
        ContinuumConfig coarse = cfg;
        coarse.refinement = cfg.refinement - 1;
        coarse.fields.enabled = false;
        coarse.vtu_directory.clear();
        progress.message(fmt::format("mesh-error estimate: refinement {} first",
                                     coarse.refinement));
        const ContinuumOutput co =
            solve_flow(coarse, [&](const std::string& line) { progress.message(line); });
        if (co.converged) {
          const DragLift dl =
              project_drag_lift(co.fx, co.fy, c.intruder.velocity[0], c.intruder.velocity[1]);
          coarser = CoarserLevel{coarse.refinement, dl.drag, dl.lift, co.torque};
        } else {
          progress.message(fmt::format("mesh-error estimate: refinement {} did not converge "
                                       "({}); no estimate",
                                       coarse.refinement, co.message));
        }
      }
      out = solve_flow(cfg, [&](const std::string& line) { progress.message(line); });
      if (estimate && cfg.nested && !out.interrupted && out.levels.size() >= 2) {
        // the nested level below the requested one was solved on the way
        const LevelResult& lv = out.levels[out.levels.size() - 2];
        const DragLift dl =
            project_drag_lift(lv.fx, lv.fy, c.intruder.velocity[0], c.intruder.velocity[1]);
        coarser = CoarserLevel{lv.refinement, dl.drag, dl.lift, lv.torque};
      }
    } catch (const ConfigError& e) {
      throw InputError(fmt::format("{}: {}", c.source.path, e.what()));
    } catch (const OutOfMemory& e) {
      throw RunError(out_of_memory_sentence(
          e.what(), cfg, saved_level,
          saved_refinement >= 0 ? saved_refinement : cfg.refinement - 1, opt.out_dir));
    } catch (const SolverError& e) {  // an error in the solve, not a non-convergence: exit 1
      throw RunError(fmt::format("{} (an error, not a non-convergence)", e.what()));
    }
    if (!out.converged)
      throw RunError(fmt::format("the continuum solve did not converge: {}", out.message));
    RunResult r = to_result(c, cfg, out, coarser);
    if (out.interrupted) {
      const int reached = out.levels.empty() ? 0 : out.levels.back().refinement;
      r.meta.partial = true;
      r.meta.notes += fmt::format(
          "; PARTIAL: interrupted by a signal; the result is the last converged mesh, "
          "refinement {} of the {} asked for", reached, cfg.refinement);
      progress.message(fmt::format("interrupted: writing the converged refinement {} (of {})",
                                   reached, cfg.refinement));
    }
    return r;
  };
  return e;
}

}  // namespace grainlift::continuum
