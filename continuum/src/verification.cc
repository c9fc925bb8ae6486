// Verification drivers: problems with known solutions run through FlowProblem.
#include "grainlift/continuum/verification.h"

#include <deal.II/base/function.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/vector_tools.h>

#include <cmath>
#include <optional>
#include <vector>

#include "flow_problem.h"
#include "manufactured_forcing.h"
#include "fluidity/fluidity_viscosity.h"
#include "grainlift/continuum/mu_i_rheology.h"

namespace grainlift::continuum::verification {

using namespace dealii;
using internal::dim;
using internal::FlowProblem;
using internal::Point2;
using internal::ProblemSetup;
using internal::Vec2;
using Grad = Tensor<2, dim>;

namespace {
/// The layer problems' solver settings: to 1e-10 of the initial residual, three Picard steps
/// first (their initial guesses are far from the solution).
void use_tight_nonlinear_settings(ProblemSetup& setup) {
  setup.nonlinear.relative_tolerance = 1e-10;
  setup.nonlinear.max_iterations = 60;
  setup.nonlinear.picard_iterations = 3;
}
}  // namespace

CouetteResult rotating_cylinder_couette(double R1, double R2, double eta, double omega,
                                        int refinement, LinearSolver solver) {
  Triangulation<dim> tria;
  GridGenerator::hyper_shell(tria, Point2(), R1, R2, 8, true);  // ids: 0 inner, 1 outer
  tria.refine_global(refinement);
  NewtonianViscosity visc(eta);
  ProblemSetup setup;
  setup.viscosity = &visc;
  setup.bc.dirichlet[0] = [omega](const Point2& x) { return Vec2({-omega * x[1], omega * x[0]}); };
  setup.bc.dirichlet[1] = [](const Point2&) { return Vec2(); };
  setup.bc.pin_pressure = true;
  setup.linear_solver = solver;
  FlowProblem problem(tria, setup);
  problem.run();

  CouetteResult r;
  const auto reac = problem.reaction(0, Point2());
  const auto surf = problem.surface_integral(0, Point2());
  r.torque_reaction = reac.torque;
  r.torque_surface = surf.torque;
  r.fx = reac.fx;
  r.fy = reac.fy;
  r.torque_exact = -4 * M_PI * eta * omega * R1 * R1 * R2 * R2 / (R2 * R2 - R1 * R1);
  // u_theta = A r + B / r
  const double A = -omega * R1 * R1 / (R2 * R2 - R1 * R1);
  const double B = omega * R1 * R1 * R2 * R2 / (R2 * R2 - R1 * R1);
  const auto u = [A, B](const Point2& x) {
    const double r2 = x.norm_square(), ut_over_r = A + B / r2;
    return Vec2({-ut_over_r * x[1], ut_over_r * x[0]});
  };
  const auto grad = [A, B](const Point2& x) {
    // u = (A + B/r^2) (-y, x)
    const double r2 = x.norm_square(), f = A + B / r2;
    const double fx = -2 * B * x[0] / (r2 * r2), fy = -2 * B * x[1] / (r2 * r2);
    Grad g;
    g[0][0] = -fx * x[1];
    g[0][1] = -fy * x[1] - f;
    g[1][0] = fx * x[0] + f;
    g[1][1] = fy * x[0];
    return g;
  };
  r.velocity_l2_error = problem.errors(u, grad, [](const Point2&) { return 0.0; }, true)[0];
  // wall shear stress of the fluid on the cylinder, t.e_theta = sigma_r_theta = -2 eta B / R1^2
  const double tau = -2 * eta * B / (R1 * R1);
  for (int k = 0; k < 16; ++k) {
    const double angle = 2 * M_PI * (k + 0.3) / 16;
    const Vec2 e_theta({-std::sin(angle), std::cos(angle)});
    const Vec2 tc = problem.consistent_traction(0, Point2(), angle);
    Vec2 n_medium;
    Point2 where;
    const auto st = problem.boundary_state(0, Point2(), angle, n_medium, where);
    const Vec2 tg = st.stress * Vec2(-n_medium);
    r.shear_error_consistent =
        std::max(r.shear_error_consistent, std::abs(tc * e_theta - tau) / std::abs(tau));
    r.shear_error_gradient =
        std::max(r.shear_error_gradient, std::abs(tg * e_theta - tau) / std::abs(tau));
  }
  r.cells = static_cast<int>(tria.n_active_cells());
  r.dofs = static_cast<int>(problem.dof_handler().n_dofs());
  r.krylov_iterations = problem.report().krylov_iterations;
  return r;
}

namespace {

// Divergence-free manufactured velocity and its gradient.
Vec2 mms_u(const Point2& x) {
  const double sx = std::sin(M_PI * x[0]), sy = std::sin(M_PI * x[1]);
  return Vec2(
      {M_PI * sx * sx * std::sin(2 * M_PI * x[1]), -M_PI * std::sin(2 * M_PI * x[0]) * sy * sy});
}
Grad mms_grad(const Point2& x) {
  const double pi2 = M_PI * M_PI;
  const double sx = std::sin(M_PI * x[0]), sy = std::sin(M_PI * x[1]);
  Grad g;
  g[0][0] = pi2 * std::sin(2 * M_PI * x[0]) * std::sin(2 * M_PI * x[1]);
  g[0][1] = 2 * pi2 * sx * sx * std::cos(2 * M_PI * x[1]);
  g[1][0] = -2 * pi2 * std::cos(2 * M_PI * x[0]) * sy * sy;
  g[1][1] = -g[0][0];
  return g;
}

/// The viscosity model's outputs at the exact fields at @p x (D their strain rate).
RheologyOutputs exact_rheology(const ViscosityModel& visc, const Point2& x, double p, Grad& D) {
  const Grad g = mms_grad(x);
  D = 0.5 * (g + transpose(g));
  RheologyInputs in;
  in.resize(1);
  RheologyOutputs out;
  out.resize(1);
  in.strain_rate_sq[0] = 0.5 * scalar_product(D, D);
  in.pressure[0] = p;
  visc.evaluate(in, out);
  return out;
}

/// sigma = -p I + 2 eta(|D|^2, p) D of exact fields.
Grad exact_stress(const ViscosityModel& visc, const Point2& x,
                  const std::function<double(const Point2&)>& p) {
  Grad D;
  const double px = p(x);
  Grad s = 2 * exact_rheology(visc, x, px, D).viscosity[0] * D;
  s[0][0] -= px;
  s[1][1] -= px;
  return s;
}

/// delta(I) of @p law at the exact fields' I (mu(I) viscosities only).
double exact_deficit(const ViscosityModel& visc, const internal::DilatancyLaw& law,
                     const Point2& x, const std::function<double(const Point2&)>& p) {
  Grad D;
  return law.deficit(exact_rheology(visc, x, p(x), D).inertial_number[0]);
}

/// The manufactured solution on @p refinement; with @p dilatancy the medium is dilatant
/// (ProblemSetup::dilatancy): the body force is -div sigma / (1 - delta) and the continuity
/// source div((1 - delta) u) = -u.grad delta of the exact fields (central differences).
ManufacturedResult run_manufactured(int refinement, const ViscosityModel& visc,
                                    const std::function<double(const Point2&)>& p_exact,
                                    LinearSolver solver = LinearSolver::direct,
                                    SchurApproximation schur = SchurApproximation::diagonal_a,
                                    std::optional<internal::DilatancyLaw> dilatancy = {}) {
  Triangulation<dim> tria;
  GridGenerator::hyper_cube(tria, 0, 1, true);  // ids 0: x=0, 1: x=1, 2: y=0, 3: y=1
  tria.refine_global(refinement);
  ProblemSetup setup;
  setup.viscosity = &visc;
  for (const types::boundary_id id : {0, 2, 3}) setup.bc.dirichlet[id] = mms_u;
  setup.bc.traction[1] = [&visc, p_exact](const Point2& x, const Vec2& n) {
    return Vec2(exact_stress(visc, x, p_exact) * n);
  };
  // f = -div sigma by central differences of the exact stress (error ~1e-10)
  setup.body_force = [&visc, p_exact](const Point2& x) {
    return internal::minus_divergence(
        [&](const Point2& y) { return exact_stress(visc, y, p_exact); }, x);
  };
  if (dilatancy) {
    const internal::DilatancyLaw law = *dilatancy;
    setup.dilatancy = law;
    const auto delta = [&visc, law, p_exact](const Point2& x) {
      return exact_deficit(visc, law, x, p_exact);
    };
    setup.body_force = [f = setup.body_force, delta](const Point2& x) {
      return Vec2(f(x) / (1 - delta(x)));
    };
    setup.continuity_source = [delta](const Point2& x) {
      const double h = 1e-5;
      const Vec2 grad({(delta(Point2(x[0] + h, x[1])) - delta(Point2(x[0] - h, x[1]))) / (2 * h),
                       (delta(Point2(x[0], x[1] + h)) - delta(Point2(x[0], x[1] - h))) / (2 * h)});
      return -(mms_u(x) * grad);
    };
  }
  // start from rest at the mean pressure (not from the answer)
  const double p_mean = p_exact(Point2(0.5, 0.5));
  setup.initial_pressure = [p_mean](const Point2&) { return p_mean; };
  setup.nonlinear.relative_tolerance = 1e-12;
  setup.nonlinear.max_iterations = 40;
  setup.nonlinear.picard_iterations = 3;
  setup.linear_solver = solver;
  setup.schur_approximation = schur;
  FlowProblem problem(tria, setup);
  problem.run();
  const auto e = problem.errors(mms_u, mms_grad, p_exact, false);
  ManufacturedResult r;
  r.h = 1.0 / (1 << refinement);
  r.velocity_l2 = e[0];
  r.velocity_h1 = e[1];
  r.pressure_l2 = e[2];
  r.dofs = static_cast<int>(problem.dof_handler().n_dofs());
  r.krylov_iterations = problem.report().krylov_iterations;
  r.nonlinear_iterations = problem.report().picard_steps + problem.report().newton_steps;
  r.converged = problem.report().converged;
  return r;
}

}  // namespace

ManufacturedResult manufactured_stokes(int refinement, LinearSolver solver,
                                       SchurApproximation schur) {
  NewtonianViscosity visc(1.0);
  return run_manufactured(
      refinement, visc,
      [](const Point2& x) { return std::cos(M_PI * x[0]) * std::cos(M_PI * x[1]); }, solver, schur);
}

ManufacturedResult manufactured_mu_i(int refinement, const RheologyParams& params,
                                     double dilatancy_a) {
  MuIRheology visc(params);
  std::optional<internal::DilatancyLaw> law;
  if (dilatancy_a > 0) law = internal::DilatancyLaw{dilatancy_a, 0.9};
  return run_manufactured(
      refinement, visc,
      [](const Point2& x) { return 2 + std::cos(M_PI * x[0]) * std::cos(M_PI * x[1]); },
      LinearSolver::direct, SchurApproximation::diagonal_a, law);
}

namespace {

/// J(x) d against the central difference of R on @p tria (the unit square refined twice) with
/// the viscosity @p visc: the body of check_jacobian and check_jacobian_fluidity.
JacobianCheck jacobian_on(Triangulation<dim>& tria, const ViscosityModel& visc,
                          bool inertia, bool friction_wall, double dilatancy_a = 0) {
  ProblemSetup setup;
  setup.viscosity = &visc;
  if (dilatancy_a > 0) setup.dilatancy = internal::DilatancyLaw{dilatancy_a, 0.9};
  setup.bc.dirichlet[0] = mms_u;
  setup.bc.dirichlet[3] = mms_u;
  setup.bc.traction[1] = [](const Point2& x, const Vec2& n) { return Vec2(-(2 + x[1]) * n); };
  if (friction_wall) {
    internal::FrictionWall w;
    w.id = 2;
    w.wall_velocity = [](const Point2&) { return Vec2({0.3, 0}); };
    w.mu_w = 0.4;
    w.slip_scale = 0.2;
    setup.bc.friction = w;
  } else {
    setup.bc.dirichlet[2] = mms_u;
  }
  setup.inertia_density = inertia ? 0.7 : 0.0;
  setup.body_force = [](const Point2& x) { return Vec2({1 + x[1], -2.0}); };
  // smooth state with p > 0 and a velocity that does not vanish on the friction wall
  setup.initial_velocity = [](const Point2& x) {
    return Vec2(mms_u(x) + Vec2({0.5 + 0.2 * x[0] * x[1], 0.1 * x[0]}));
  };
  setup.initial_pressure = [](const Point2& x) {
    return 2 + std::cos(M_PI * x[0]) * std::cos(M_PI * x[1]);
  };
  FlowProblem problem(tria, setup);
  problem.setup_system();
  problem.interpolate_initial_guess();
  const internal::VectorType x0 = problem.solution();
  const auto n = x0.size();
  // deterministic pseudo-random direction satisfying the homogeneous constraints
  internal::VectorType dir = problem.make_vector();
  unsigned long long seed = 12345;
  for (unsigned int i = 0; i < n; ++i) {
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    dir(i) = 2.0 * static_cast<double>(seed >> 11) / 9007199254740992.0 - 1.0;
  }
  problem.zero_constraints().distribute(dir);

  internal::VectorType r = problem.make_vector(), rp = r, rm = r, jd = r, xs = r;
  problem.assemble_system(x0, true, true, r);
  problem.system_matrix().vmult(jd, dir);
  const double h = 1e-6;
  xs = x0;
  xs.add(h, dir);
  problem.assemble_system(xs, false, false, rp);
  xs = x0;
  xs.add(-h, dir);
  problem.assemble_system(xs, false, false, rm);
  JacobianCheck c;
  for (unsigned int i = 0; i < n; ++i) {
    if (problem.zero_constraints().is_constrained(i)) continue;
    const double fd = (rp(i) - rm(i)) / (2 * h);
    c.max_abs_difference = std::max(c.max_abs_difference, std::abs(fd - jd(i)));
    c.max_abs_reference = std::max(c.max_abs_reference, std::abs(fd));
  }
  return c;
}

}  // namespace

JacobianCheck check_jacobian(const RheologyParams& params, bool inertia, bool friction_wall,
                             double dilatancy_a) {
  Triangulation<dim> tria;
  GridGenerator::hyper_cube(tria, 0, 1, true);
  tria.refine_global(2);
  const MuIRheology visc(params);
  return jacobian_on(tria, visc, inertia, friction_wall, dilatancy_a);
}

JacobianCheck check_jacobian_fluidity(const RheologyParams& params, bool friction_wall,
                                      bool local_implicit) {
  Triangulation<dim> tria;
  GridGenerator::hyper_cube(tria, 0, 1, true);
  tria.refine_global(2);
  // a smooth fluidity field, Q2 on the flow's mesh as the splitting's: g = 1 + x + y / 2 (1/s)
  const FE_Q<dim> fe(2);
  DoFHandler<dim> g_dofs(tria);
  g_dofs.distribute_dofs(fe);
  Vector<double> g(g_dofs.n_dofs());
  VectorTools::interpolate(g_dofs, ScalarFunctionFromFunctionObject<dim>([](const Point2& x) {
                             return 1 + x[0] + 0.5 * x[1];
                           }),
                           g);
  internal::FluidityViscosity visc(params, g_dofs, g);
  if (local_implicit) {
    const QGauss<dim> quad(3);  // the assembly's
    FEValues<dim> fev(fe, quad, update_quadrature_points);
    std::vector<double> g_loc(tria.n_active_cells() * quad.size());
    for (const auto& cell : g_dofs.active_cell_iterators()) {
      fev.reinit(cell);
      for (unsigned int q = 0; q < quad.size(); ++q) {
        const Point2& x = fev.quadrature_point(q);
        g_loc[cell->active_cell_index() * quad.size() + q] =
            1.2 + 0.6 * std::cos(2 * M_PI * x[0]) * std::sin(M_PI * x[1]);
      }
    }
    visc.set_local_fluidity(quad, std::move(g_loc));
  }
  return jacobian_on(tria, visc, false, friction_wall);
}

InclineResult incline_layer(const InclineSpec& s) {
  const double h = s.depth, dx = h / s.cells_across;
  Triangulation<dim> tria;
  GridGenerator::subdivided_hyper_rectangle(tria, {2u, static_cast<unsigned int>(s.cells_across)},
                                            Point2(0, 0), Point2(2 * dx, h), true);
  MuIRheology visc(s.rheology);
  const double rho = s.bulk_density, g = s.gravity, th = s.slope;
  const double G = rho * g * std::cos(th), Ptop = s.overburden;
  const double Ibeta = visc.inertial_number_for_friction(std::tan(th));
  const double d = s.rheology.grain_diameter, rho_s = s.rheology.solid_density;
  const double coef = 2 * Ibeta / (3 * d * std::sqrt(rho_s) * G);
  const auto u_exact = [=](double z) {
    return coef * (std::pow(Ptop + G * h, 1.5) - std::pow(Ptop + G * (h - z), 1.5));
  };
  ProblemSetup setup;
  setup.viscosity = &visc;
  setup.bc.periodic_x.push_back({0, 1});
  setup.bc.dirichlet[2] = [](const Point2&) { return Vec2(); };
  setup.bc.traction[3] = [=](const Point2&, const Vec2&) {
    return Vec2({Ptop * std::tan(th), -Ptop});
  };
  setup.body_force = [=](const Point2&) {
    return Vec2({rho * g * std::sin(th), -rho * g * std::cos(th)});
  };
  // initial guess: a parabolic profile at half the exact surface speed, lithostatic pressure
  const double us = u_exact(h);
  setup.initial_velocity = [=](const Point2& x) {
    const double e = 1 - x[1] / h;
    return Vec2({0.5 * us * (1 - e * e), 0});
  };
  setup.initial_pressure = [=](const Point2& x) { return Ptop + G * (h - x[1]); };
  use_tight_nonlinear_settings(setup);
  setup.nonlinear.tangent_floor = s.tangent_floor;
  FlowProblem problem(tria, setup);
  problem.run();

  InclineResult r;
  r.converged = problem.report().converged;
  r.picard_steps = problem.report().picard_steps;
  r.newton_steps = problem.report().newton_steps;
  r.surface_velocity_exact = us;
  internal::PointState st;
  for (int k = 0; k <= 100; ++k) {
    const double z = h * k / 100.0;
    if (!problem.point_state(Point2(dx, z), st)) continue;
    if (k == 100) r.surface_velocity = st.velocity[0];
    r.max_relative_error =
        std::max(r.max_relative_error, std::abs(st.velocity[0] - u_exact(z)) / us);
  }
  return r;
}

LidBoxResult lid_box(const LidBoxSpec& s) {
  Triangulation<dim> tria;
  GridGenerator::subdivided_hyper_rectangle(
      tria, {static_cast<unsigned int>(s.cells_x), static_cast<unsigned int>(s.cells_y)},
      Point2(0, 0), Point2(s.width, s.height), true);  // ids: 0 left, 1 right, 2 bottom, 3 top
  MuIRheology visc(s.rheology);
  const double rho = s.bulk_density, g = s.gravity, H = s.height, U = s.lid_speed;
  const double P = s.lid_pressure;
  ProblemSetup setup;
  setup.viscosity = &visc;
  setup.bc.periodic_x.push_back({0, 1});
  setup.bc.dirichlet[2] = [](const Point2&) { return Vec2(); };
  setup.bc.dirichlet[3] = [U](const Point2&) { return Vec2({U, 0}); };
  setup.bc.mean_pressure = internal::MeanPressure{3, P};
  if (g > 0) setup.body_force = [=](const Point2&) { return Vec2({0, -rho * g}); };
  if (s.dilatancy_a > 0) setup.dilatancy = internal::DilatancyLaw{s.dilatancy_a, 0.9};
  // initial guess: the lid's pressure everywhere, the medium at rest (the solver must find
  // the gradient and the profile)
  setup.initial_pressure = [P](const Point2&) { return P; };
  use_tight_nonlinear_settings(setup);
  FlowProblem problem(tria, setup);
  problem.run();

  LidBoxResult r;
  r.converged = problem.report().converged;
  internal::PointState st;
  // the weight above each of the grid's heights: rho g int_y^H (1 - delta) (trapezoids on 256
  // intervals, delta from the solution's I on the column x = width / 2; delta = 0 when the
  // medium is incompressible)
  const int n = 256;
  std::vector<double> weight(n + 1, 0.0), kept(n + 1, 1.0);
  for (int k = 0; k <= n && s.dilatancy_a > 0; ++k)
    if (problem.point_state(Point2(s.width / 2, H * k / n), st))
      kept[k] = 1 - setup.dilatancy->deficit(st.inertial_number);
  for (int k = n - 1; k >= 0; --k)
    weight[k] = weight[k + 1] + rho * g * 0.5 * (kept[k] + kept[k + 1]) * H / n;
  r.weight_deficit = (rho * g * H - weight[0]) / P;
  for (int i = 0; i <= 8; ++i)
    for (int j = 0; j <= 8; ++j) {
      const Point2 x(s.width * i / 8.0, H * j / 8.0);
      if (!problem.point_state(x, st)) continue;
      const double p = P + weight[j * n / 8];
      r.max_pressure_error = std::max(r.max_pressure_error, std::abs(st.pressure - p) / P);
      if (U != 0)
        r.max_velocity_error =
            std::max(r.max_velocity_error, (st.velocity - Vec2({U * x[1] / H, 0})).norm() / U);
    }
  const auto lid = problem.surface_integral(3, Point2());
  r.lid_shear_stress = -lid.fx / s.width;
  // the mean pressure on the lid, from the same surface integral's normal force
  r.lid_mean_pressure = lid.fy / s.width;
  const double I = (U / H) * s.rheology.grain_diameter / std::sqrt(P / s.rheology.solid_density);
  r.shear_stress_exact = visc.friction(I) * P;
  return r;
}

}  // namespace grainlift::continuum::verification
