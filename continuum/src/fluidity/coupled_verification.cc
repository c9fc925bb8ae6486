// manufactured_coupled_fluidity(): the nonlocal fluidity model's coupled system (flow with
// eta = p+ / g, fluidity with xi(mu) and g_loc(mu, p) of that flow) with known fields, solved by
// alternating its two solves, the flow step with the local part of g implicit as the
// cylinder's splitting (verification.h). Plain alternation (eta = p+ / g_h held) diverged here:
// g -> g_loc(mu(g)) has a gain of about 10 at these grains' dg_loc / dmu.
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/vector.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "flow_problem.h"
#include "manufactured_forcing.h"
#include "fluidity/fluidity_problem.h"
#include "fluidity/fluidity_viscosity.h"
#include "grainlift/continuum/verification.h"
#include "grainlift/shared/rheology/fluidity_law.h"
#include "quadrature_rheology.h"

namespace grainlift::continuum::verification {

using namespace dealii;
using internal::dim;
using internal::Point2;
using internal::Vec2;
using Grad = Tensor<2, dim>;

namespace {

// The exact fields: a uniform shear S y plus a Taylor-Green cell of amplitude U (divergence
// free; D12 = S / 2 everywhere, so |D| >= S / 2 and mu = 2 |D| / g stays within (mu_s, mu_cap)),
// p between 1.5 and 2.5, g between 1.1 and 1.9 (1/s).
constexpr double kS = 0.5, kU = 0.1, kA = 0.5, kXiMax = 0.5;
Vec2 exact_u(const Point2& x) {
  const double a = M_PI * x[0], b = M_PI * x[1];
  return Vec2({kS * x[1] + kU * std::sin(a) * std::cos(b), -kU * std::cos(a) * std::sin(b)});
}
Grad exact_grad_u(const Point2& x) {
  const double a = M_PI * x[0], b = M_PI * x[1], k = kU * M_PI;
  Grad g;
  g[0][0] = k * std::cos(a) * std::cos(b);
  g[0][1] = kS - k * std::sin(a) * std::sin(b);
  g[1][0] = k * std::sin(a) * std::sin(b);
  g[1][1] = -g[0][0];
  return g;
}
double exact_p(const Point2& x) { return 2 + 0.5 * std::cos(M_PI * x[0]) * std::cos(M_PI * x[1]); }
double exact_g(const Point2& x) {
  return 1.5 + 0.4 * std::sin(M_PI * x[0]) * std::cos(0.5 * M_PI * x[1]);
}
Vec2 exact_grad_g(const Point2& x) {
  return Vec2({0.4 * M_PI * std::cos(M_PI * x[0]) * std::cos(0.5 * M_PI * x[1]),
               -0.2 * M_PI * std::sin(M_PI * x[0]) * std::sin(0.5 * M_PI * x[1])});
}
double exact_laplacian_g(const Point2& x) { return -1.25 * M_PI * M_PI * (exact_g(x) - 1.5); }

/// sigma = -p I + 2 (p / g) D of the exact fields.
Grad exact_stress(const Point2& x) {
  const Grad g = exact_grad_u(x);
  Grad s = (exact_p(x) / exact_g(x)) * (g + transpose(g));
  s[0][0] -= exact_p(x);
  s[1][1] -= exact_p(x);
  return s;
}

/// mu = 2 |D| / g of the exact fields.
double exact_mu(const Point2& x) {
  const Grad g = exact_grad_u(x);
  const Grad D = 0.5 * (g + transpose(g));
  return 2 * std::sqrt(0.5 * scalar_product(D, D)) / exact_g(x);
}

}  // namespace

CoupledManufacturedResult manufactured_coupled_fluidity(int refinement,
                                                        const RheologyParams& params) {
  Triangulation<dim> tria;
  GridGenerator::hyper_cube(tria, 0, 1, true);  // ids 0: x=0, 1: x=1, 2: y=0, 3: y=1
  tria.refine_global(refinement);
  const FluidityMaterial m{params.mu_s, params.mu_2, params.I0, params.solid_density,
                           params.grain_diameter};
  const auto xi = [&](double mu) {
    return cooperativity_length(mu, params.mu_s, kA, params.grain_diameter, kXiMax);
  };
  // the fluidity's source: g - xi^2 Laplacian(g) - g_loc(mu, p) of the exact fields
  const auto source = [&](const Point2& x) {
    const double mu = exact_mu(x), l = xi(mu);
    return exact_g(x) - l * l * exact_laplacian_g(x) - local_fluidity(mu, exact_p(x), m);
  };
  // the flow's state at the fluidity's points (set after each flow solve)
  std::unique_ptr<internal::FlowProblem> flow;
  std::unique_ptr<FEValues<dim>> flow_values;
  std::unique_ptr<internal::QuadratureRheology> qr;
  internal::VectorType state;
  const ViscosityModel* model = nullptr;
  std::vector<double> g_loc_points;
  fluidity::internal::FluiditySetup fs;
  fs.coefficients = [&](const fluidity::internal::CellIterator& cell,
                        const std::vector<Point2>& points,
                        fluidity::internal::CellCoefficients& c) {
    const DoFHandler<dim>::active_cell_iterator fc(&tria, cell->level(), cell->index(),
                                                   &flow->dof_handler());
    flow_values->reinit(fc);
    qr->evaluate(*flow_values, state, *model);
    for (unsigned int q = 0; q < points.size(); ++q) {
      const double p = qr->pressure[q];
      const double rate = std::sqrt(std::max(qr->in.strain_rate_sq[q], 0.0));
      const double mu = p > 0 ? 2 * qr->out.viscosity[q] * rate / p : 0;
      c.xi[q] = xi(mu);
      c.g_loc[q] = local_fluidity(mu, p, m) + source(points[q]);
      // the flow step's table (FluidityViscosity's implicit form, as the cylinder's splitting)
      g_loc_points[cell->active_cell_index() * points.size() + q] =
          local_fluidity(qr->out.friction[q], p, m);
    }
  };
  for (const types::boundary_id id : {0, 1, 2, 3}) fs.dirichlet[id] = exact_g;
  fluidity::internal::FluidityProblem fluidity(tria, 2, fs);
  fluidity.setup_system();
  Vector<double> g(fluidity.dof_handler().n_dofs());
  g = 1.5;  // the mean, not the answer
  internal::FluidityViscosity visc(params, fluidity.dof_handler(), g);
  model = &visc;
  internal::ProblemSetup setup;
  setup.viscosity = &visc;
  for (const types::boundary_id id : {0, 2, 3}) setup.bc.dirichlet[id] = exact_u;
  setup.bc.traction[1] = [](const Point2& x, const Vec2& n) { return Vec2(exact_stress(x) * n); };
  setup.body_force = [](const Point2& x) {  // -div sigma by central differences (~1e-10)
    return internal::minus_divergence(exact_stress, x);
  };
  setup.initial_pressure = [](const Point2&) { return 2.0; };
  setup.nonlinear.relative_tolerance = 1e-12;
  setup.nonlinear.max_iterations = 40;
  flow = std::make_unique<internal::FlowProblem>(tria, setup);
  flow->setup_system();
  flow->interpolate_initial_guess();
  flow_values = std::make_unique<FEValues<dim>>(flow->mapping(), flow->dof_handler().get_fe(),
                                                fluidity.quadrature(),
                                                update_values | update_gradients);
  qr = std::make_unique<internal::QuadratureRheology>(fluidity.quadrature().size());
  g_loc_points.assign(tria.n_active_cells() * fluidity.quadrature().size(), 0.0);
  CoupledManufacturedResult r;
  // the alternation contracts by about 0.82 per step here: stopped at |dg| <= 1e-8 |g|, the
  // iteration's error is below 1e-7 |g|, far below the discretisation's (2e-5 at h = 1/16)
  for (r.iterations = 1; r.iterations <= 200; ++r.iterations) {
    flow->solve_nonlinear(setup.nonlinear);
    if (!flow->report().converged) break;
    state = flow->ghosted(flow->solution());
    fluidity.assemble_system();
    fluidity.solve();
    Vector<double> change = fluidity.solution();
    change -= g;
    g = fluidity.solution();
    visc.set_local_fluidity(fluidity.quadrature(), g_loc_points);
    if (change.l2_norm() <= 1e-8 * g.l2_norm()) {
      r.converged = true;
      break;
    }
  }
  const auto ef = flow->errors(exact_u, exact_grad_u, exact_p, false);
  const auto eg = fluidity.errors(exact_g, exact_grad_g);
  r.h = 1.0 / (1 << refinement);
  r.velocity_l2 = ef[0];
  r.pressure_l2 = ef[2];
  r.fluidity_l2 = eg[0];
  r.fluidity_h1 = eg[1];
  return r;
}

}  // namespace grainlift::continuum::verification
