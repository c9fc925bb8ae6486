// Verification drivers of the continuum engine: small problems with known solutions, run
// through the same finite-element engine as solve_flow(). deal.II-free; used by the tests in
// tests/continuum and by anyone who wants to re-measure the numbers in docs/continuum-model.md.
#pragma once

#include "grainlift/continuum/continuum_config.h"

namespace grainlift::continuum::verification {

/// Result of the rotating cylinder in a Newtonian annulus (circular Couette flow).
struct CouetteResult {
  double torque_reaction =
      0;  ///< N, torque of the fluid on the inner cylinder (consistent reaction)
  double torque_surface = 0;   ///< N, same by integrating sigma.n over the cylinder
  double torque_exact = 0;     ///< N, -4 pi eta omega R1^2 R2^2 / (R2^2 - R1^2)
  double fx = 0, fy = 0;       ///< N/m, net force on the inner cylinder (exactly 0)
  double velocity_l2_error = 0;
  /// max over 16 angles of |t.e_theta - tau_exact| / |tau_exact|, tau_exact = -2 eta B / R1^2
  /// the exact wall shear stress: from the consistent traction and from sigma(grad u_h).n
  double shear_error_consistent = 0, shear_error_gradient = 0;
  int cells = 0, dofs = 0;
  long krylov_iterations = 0;  ///< FGMRES iterations (LinearSolver::amg)
};

/// @brief Inner cylinder (radius @p R1, m) spinning at @p omega (rad/s) inside a fixed outer one
/// (radius @p R2) filled with a fluid of viscosity @p eta (Pa s); @p refinement global refinements.
CouetteResult rotating_cylinder_couette(double R1, double R2, double eta, double omega,
                                        int refinement,
                                        LinearSolver solver = LinearSolver::direct);

/// Errors of one manufactured-solution run on the unit square.
struct ManufacturedResult {
  double h = 0;               ///< m, cell size
  double velocity_l2 = 0;     ///< m^3/s... (L2 norm of u_h - u)
  double velocity_h1 = 0;     ///< H1 seminorm of u_h - u
  double pressure_l2 = 0;     ///< L2 norm of p_h - p
  int dofs = 0, nonlinear_iterations = 0;
  long krylov_iterations = 0;  ///< FGMRES iterations (LinearSolver::amg)
  bool converged = false;
};

/// @brief Newtonian Stokes (eta = 1) on [0,1]^2 with u = (pi sin^2(pi x) sin(2 pi y),
/// -pi sin(2 pi x) sin^2(pi y)), p = cos(pi x) cos(pi y); Dirichlet on three sides, the exact
/// traction on x = 1 (which fixes the pressure level); 2^refinement cells per side.
ManufacturedResult manufactured_stokes(int refinement, LinearSolver solver = LinearSolver::direct,
                                       SchurApproximation schur = SchurApproximation::diagonal_a);

/// @brief Same velocity with p = 2 + cos(pi x) cos(pi y) and the regularised mu(I) viscosity
/// of @p params; the body force is -div sigma of the exact fields (central differences). With
/// @p dilatancy_a > 0 the medium is dilatant with delta(I) = min(dilatancy_a I, 0.9)
/// (continuum.dilatancy's law): the body force is -div sigma / (1 - delta) and the continuity
/// div((1 - delta) u) = -u.grad delta of the exact fields.
ManufacturedResult manufactured_mu_i(int refinement, const RheologyParams& params,
                                     double dilatancy_a = 0);

/// Finite-difference check of the Newton Jacobian.
struct JacobianCheck {
  double max_abs_difference = 0;  ///< max_i |(J d)_i - FD_i| over unconstrained rows
  double max_abs_reference = 0;   ///< max_i |FD_i|
  double relative_error() const { return max_abs_difference / max_abs_reference; }
};

/// @brief Compare J(x) d with (R(x + h d) - R(x - h d)) / 2h at a smooth state x (mu(I) with
/// @p params, p > 0) on a small unit-square mesh with a Dirichlet side, a traction side and,
/// when @p friction_wall, a regularised Coulomb wall; @p inertia adds rho (u.grad)u;
/// @p dilatancy_a > 0 a dilatant medium, delta(I) = min(dilatancy_a I, 0.9).
JacobianCheck check_jacobian(const RheologyParams& params, bool inertia, bool friction_wall,
                             double dilatancy_a = 0);

/// @brief The same check for the flow step of the nonlocal fluidity's splitting: eta = p+ / g
/// (FluidityViscosity) with a fixed smooth fluidity g = 1 + x + y / 2 (1/s, Q2 on the mesh),
/// so d eta / dp = 1 / g and d eta / d|D|^2 = 0; no inertia, a Coulomb wall when
/// @p friction_wall. @p params: delta below mu_s / 2 (so g stays above g_min = 2 delta / mu_s).
/// With @p local_implicit the previous g_loc is set too (1.2 + 0.6 cos(2 pi x) sin(pi y) at the
/// assembly's points, an excess g - g_loc of either sign) and the step solves gamma_dot =
/// mu (g_loc(mu, p) + excess) for mu: eta depends on |D|^2 and p through mu.
JacobianCheck check_jacobian_fluidity(const RheologyParams& params, bool friction_wall,
                                      bool local_implicit = false);

/// Errors of the nonlocal fluidity's coupled manufactured solution on the unit square.
struct CoupledManufacturedResult {
  double h = 0;                         ///< cell size
  double velocity_l2 = 0, pressure_l2 = 0;
  double fluidity_l2 = 0, fluidity_h1 = 0;
  int iterations = 0;                   ///< alternations of flow and fluidity solves
  bool converged = false;               ///< |dg| <= 1e-8 |g| between two alternations
};

/// @brief The coupled system of the nonlocal fluidity model with known fields: u a uniform
/// shear plus a Taylor-Green cell, p = 2 + cos(pi x) cos(pi y) / 2, g = 1.5 + 0.4 sin(pi x)
/// cos(pi y / 2); the flow with eta = p+ / g_h (FluidityViscosity) and -div sigma of the exact
/// fields as body force, the fluidity with xi(mu_h) (A = 0.5, xi capped at 0.5) and g_loc(mu_h,
/// p_h) plus the exact fields' residual as source, g exact on the boundary; Q2-Q1 and Q2 on
/// 2^refinement cells per side; solved by alternating the two solves from g = 1.5 (@p params:
/// mu_s below 0.26 and mu(I = 1) above 0.73, the exact mu's range).
CoupledManufacturedResult manufactured_coupled_fluidity(int refinement,
                                                        const RheologyParams& params);

/// Steady mu(I) layer down an incline of slope theta with an overburden P_top and a shear
/// traction P_top tan(theta) on its surface, so that tau / p = tan(theta) everywhere:
/// I = I_beta = mu^{-1}(tan theta) and u(z) = 2 I_beta / (3 d sqrt(rho_s) G)
/// [(P_top + G h)^{3/2} - (P_top + G (h - z))^{3/2}], G = rho g cos(theta) (Bagnold profile).
struct InclineSpec {
  double slope = 0.463647609;   ///< rad (tan = 0.5)
  double depth = 0.03;          ///< m
  double overburden = 40;       ///< Pa, P_top
  double bulk_density = 1500;   ///< kg/m^3
  double gravity = 9.81;        ///< m/s^2
  int cells_across = 16;        ///< cells through the depth
  double tangent_floor = 0;     ///< Newton's tangent floor (0: the exact Jacobian)
  RheologyParams rheology;
};
struct InclineResult {
  double max_relative_error = 0;  ///< max |u_h - u| / u_surface at the nodes
  double surface_velocity = 0, surface_velocity_exact = 0;  ///< m/s
  int picard_steps = 0, newton_steps = 0;
  bool converged = false;
};
InclineResult incline_layer(const InclineSpec& spec);

/// A box with no intruder as the cylinder problem's periodic far field makes it: periodic in
/// x, a wall at rest below (no slip), a rigid lid above moving along x at @p lid_speed whose
/// load per length is @p lid_pressure times its length (the mean pressure on it,
/// BoundarySpec::mean_pressure), gravity @p gravity downwards. The exact state is a simple
/// shear under the hydrostatic pressure: p = P_lid + rho g (H - y) and, with g = 0, u = U y / H
/// with tau / p = mu(I), I = (U / H) d / sqrt(P_lid / rho_s).
struct LidBoxSpec {
  double width = 0.04, height = 0.02;  ///< m
  double lid_pressure = 100;           ///< Pa
  double lid_speed = 0;                ///< m/s
  double gravity = 0;                  ///< m/s^2, |g| (pointing down)
  double bulk_density = 1500;          ///< kg/m^3
  int cells_x = 8, cells_y = 8;
  RheologyParams rheology;
  /// > 0: a dilatant medium, delta(I) = min(dilatancy_a I, 0.9) (continuum.dilatancy's law):
  /// it weighs rho (1 - delta) g, so p = P_lid + rho g int_y^H (1 - delta)
  double dilatancy_a = 0;
};
struct LidBoxResult {
  bool converged = false;
  /// max |p_h - p| / P_lid at the nodes of a 9 x 9 grid (p of the dilated weight with
  /// dilatancy_a, delta from the solution's own I)
  double max_pressure_error = 0;
  /// rho g int_0^H delta / P_lid: the weight the dilatancy took off the column
  double weight_deficit = 0;
  /// max |u_h - U y / H| / U on that grid (0 when the lid rests)
  double max_velocity_error = 0;
  double lid_mean_pressure = 0;        ///< Pa, the mean pressure over the lid
  double lid_shear_stress = 0;         ///< Pa, -x force of the medium on the lid per length
  double shear_stress_exact = 0;       ///< Pa, mu(I) P_lid (g = 0)
};
LidBoxResult lid_box(const LidBoxSpec& spec);

}  // namespace grainlift::continuum::verification
