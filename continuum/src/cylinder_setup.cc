// CylinderProblem's problem set-up (cylinder_problem.h): body force, far-field and wall
// boundary conditions, initial guess, nonlinear settings and inertia of the FlowProblem.
#include "cylinder_problem.h"

#include <algorithm>

namespace grainlift::continuum::internal {

using namespace dealii;

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
  if (c.dilatancy.enabled) {
    const DilatancyParams& d = c.dilatancy;
    setup.dilatancy = DilatancyLaw{d.a / d.phi_max, (d.phi_max - d.phi_min) / d.phi_max};
  }
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
            kTop,
            P0 + rho * (g_used[0] * 0.5 * (c.box_left + c.box_right) + g_used[1] * c.box_top)};
    }
  }
  const auto wall_velocity = [omega](const Point2& x) {
    return Vec2({-omega * x[1], omega * x[0]});
  };
  if (c.wall == WallCondition::no_slip) {
    setup.bc.dirichlet[kHole] = wall_velocity;
  } else {
    FrictionWall w;
    w.id = kHole;
    w.wall_velocity = wall_velocity;
    w.mu_w = c.wall_friction;
    w.mu_a = c.wall_mu_a;
    w.mu_b = c.wall_mu_b;
    w.v0 = c.wall_v0;
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

}  // namespace grainlift::continuum::internal
