// Verification drivers of the fluidity equation: problems with known solutions run through
// FluidityProblem (see fluidity_verification.h).
#include "grainlift/continuum/fluidity/fluidity_verification.h"

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>

#include <cmath>
#include <utility>

#include "fluidity_problem.h"

namespace grainlift::continuum::fluidity::verification {

using namespace dealii;
using internal::dim;
using internal::FluidityProblem;
using internal::FluiditySetup;
using internal::GradientField;
using internal::Point2;
using internal::ScalarField;
using internal::Vec2;

namespace {
/// Solve with @p setup on @p tria and measure against @p g, @p grad_g.
FluidityErrors solve_and_measure(const Triangulation<dim>& tria, int degree,
                                 FluiditySetup setup, const ScalarField& g,
                                 const GradientField& grad_g, double h) {
  FluidityProblem problem(tria, static_cast<unsigned int>(degree), std::move(setup));
  problem.run();
  const auto e = problem.errors(g, grad_g);
  FluidityErrors r;
  r.h = h;
  r.l2 = e[0];
  r.h1 = e[1];
  r.max_nodal = problem.max_nodal_error(g);
  r.cells = static_cast<int>(tria.n_active_cells());
  r.dofs = static_cast<int>(problem.dof_handler().n_dofs());
  return r;
}
}  // namespace

double planar_shear_profile(const PlanarShear& p, double y) {
  return p.g_loc + (p.g_wall - p.g_loc) * std::cosh((y - p.height / 2) / p.xi) /
                       std::cosh(p.height / (2 * p.xi));
}

FluidityErrors planar_shear_fluidity(const PlanarShear& p, int refinement, int degree) {
  Triangulation<dim> tria;
  // colorized ids: 0 x = 0, 1 x = H/4 (zero flux), 2 y = 0, 3 y = H (walls, g = g_w)
  GridGenerator::subdivided_hyper_rectangle(tria, {1, 4}, Point2(0, 0),
                                            Point2(p.height / 4, p.height), true);
  tria.refine_global(static_cast<unsigned int>(refinement));
  FluiditySetup setup;
  setup.coefficients = internal::pointwise_coefficients(
      [xi = p.xi](const Point2&) { return xi; }, [g = p.g_loc](const Point2&) { return g; });
  setup.dirichlet[2] = [g = p.g_wall](const Point2&) { return g; };
  setup.dirichlet[3] = setup.dirichlet[2];
  const auto g = [p](const Point2& x) { return planar_shear_profile(p, x[1]); };
  const auto grad_g = [p](const Point2& x) {
    const double dg = (p.g_wall - p.g_loc) * std::sinh((x[1] - p.height / 2) / p.xi) /
                      (p.xi * std::cosh(p.height / (2 * p.xi)));
    return Vec2({0.0, dg});
  };
  return solve_and_measure(tria, degree, std::move(setup), g, grad_g,
                           p.height / 4 / std::pow(2.0, refinement));
}

FluidityErrors uniform_zero_flux_fluidity(int refinement, int degree) {
  constexpr double g_loc = 1.5;
  Triangulation<dim> tria;
  // ids: 0 the outer square, 1 the hole (both zero flux: no Dirichlet entry)
  GridGenerator::hyper_cube_with_cylindrical_hole(tria, 0.25, 1.0);
  tria.refine_global(static_cast<unsigned int>(refinement));
  FluiditySetup setup;
  setup.coefficients = internal::pointwise_coefficients(
      [](const Point2& x) { return 0.05 * (1 + x.norm_square()); },
      [](const Point2&) { return g_loc; });
  return solve_and_measure(
      tria, degree, std::move(setup), [](const Point2&) { return g_loc; },
      [](const Point2&) { return Vec2(); }, 2.0 / std::pow(2.0, refinement + 1));
}

FluidityErrors manufactured_fluidity(int refinement, int degree) {
  constexpr double a = M_PI / 2;
  const auto g = [](const Point2& x) { return 2 + std::sin(a * x[0]) * std::cos(M_PI * x[1]); };
  const auto grad_g = [](const Point2& x) {
    return Vec2({a * std::cos(a * x[0]) * std::cos(M_PI * x[1]),
                 -M_PI * std::sin(a * x[0]) * std::sin(M_PI * x[1])});
  };
  const auto xi = [](const Point2& x) { return 0.2 * (1 + 0.5 * x[0] * x[1]); };
  // g_loc = g - xi^2 Laplacian(g)
  const auto g_loc = [=](const Point2& x) {
    const double laplacian = -(a * a + M_PI * M_PI) * std::sin(a * x[0]) * std::cos(M_PI * x[1]);
    return g(x) - xi(x) * xi(x) * laplacian;
  };
  Triangulation<dim> tria;
  GridGenerator::hyper_cube(tria, 0, 1, true);  // ids: 0 x = 0, 1 x = 1, 2 y = 0, 3 y = 1
  tria.refine_global(static_cast<unsigned int>(refinement));
  FluiditySetup setup;
  setup.coefficients = internal::pointwise_coefficients(xi, g_loc);
  setup.dirichlet[0] = g;
  setup.dirichlet[2] = g;
  return solve_and_measure(tria, degree, std::move(setup), g, grad_g,
                           1.0 / std::pow(2.0, refinement));
}

}  // namespace grainlift::continuum::fluidity::verification
