// Verification drivers of the fluidity equation g - xi^2 Laplacian(g) = g_loc (the building
// block of the nonlocal granular fluidity model): problems with known solutions run through
// the same finite-element solver (continuum/src/fluidity/). deal.II-free; used by
// tests/continuum/test_fluidity.cc and to re-measure the rates in docs/continuum-model.md.
#pragma once

namespace grainlift::continuum::fluidity::verification {

/// Errors of one run.
struct FluidityErrors {
  double h = 0;           ///< m, cell size (the finest direction)
  double l2 = 0;          ///< L2 norm of g_h - g (1/s m)
  double h1 = 0;          ///< H1 seminorm of g_h - g (1/s)
  double max_nodal = 0;   ///< 1/s, max over the support points of |g_h - g|
  int cells = 0, dofs = 0;
};

/// A planar shear layer 0 < y < H with uniform g_loc and xi and g = g_w at both walls.
struct PlanarShear {
  double height = 1.0;  ///< m, H
  double xi = 0.1;      ///< m
  double g_loc = 2.0;   ///< 1/s
  double g_wall = 0.5;  ///< 1/s
};

/// @brief The exact profile g(y) = g_loc + (g_w - g_loc) cosh((y - H/2)/xi) / cosh(H/(2 xi))
/// (1/s) at height @p y (m): a boundary layer of thickness xi at each wall.
double planar_shear_profile(const PlanarShear& p, double y);

/// @brief The layer @p p on a strip of width H/4 (zero flux on its sides x = 0 and x = H/4),
/// 1 x 4 cells refined @p refinement times, Q@p degree elements (1 or 2).
FluidityErrors planar_shear_fluidity(const PlanarShear& p, int refinement, int degree);

/// @brief Uniform g_loc = 1.5 1/s, zero flux on every boundary (the box and a circular hole,
/// as around the intruder) and a variable xi = 0.05 (1 + x^2 + y^2) m: the exact solution is
/// g = g_loc, whatever xi. Square [-1, 1]^2 with a hole of radius 0.25, refined @p refinement
/// times, Q@p degree; the errors are against g_loc.
FluidityErrors uniform_zero_flux_fluidity(int refinement, int degree);

/// @brief Manufactured solution on [0, 1]^2: g = 2 + sin(pi x / 2) cos(pi y) (1/s),
/// xi = 0.2 (1 + 0.5 x y) (m), g_loc = g - xi^2 Laplacian(g); g imposed on x = 0 and y = 0,
/// zero flux on x = 1 and y = 1 (where dg/dn = 0 exactly). 2^@p refinement cells per side,
/// Q@p degree.
FluidityErrors manufactured_fluidity(int refinement, int degree);

}  // namespace grainlift::continuum::fluidity::verification
