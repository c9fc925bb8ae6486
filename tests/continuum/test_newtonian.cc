// Newtonian limits of the finite-element engine: circular Couette flow and a manufactured
// Stokes solution with the Taylor-Hood convergence rates.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "grainlift/continuum/verification.h"

using namespace grainlift::continuum::verification;

// Cylinder of radius R1 = 0.05 m spinning at omega = 2 rad/s inside a fixed cylinder of radius
// R2 = 0.2 m, eta = 3 Pa s. Analytic torque of the fluid on the inner cylinder:
// T = -4 pi eta omega R1^2 R2^2 / (R2^2 - R1^2). The consistent reaction must match it to 1e-4
// (relative) on the 8-cell shell refined 3 times (512 cells; measured 7.4e-5, converging at
// rate ~3.5), the surface integral of sigma.n (a less accurate diagnostic, rate ~1.6) to 3e-2,
// and the net force must vanish (|F| R1 < 1e-8 |T|). The wall shear stress -2 eta B / R1^2 must
// be matched to 2e-4 by the consistent traction (the sigma_t that solve_flow reports; measured
// 7.7e-5) at 16 angles, and to 3e-2 by sigma(grad u_h).n (measured 2.2e-2).
TEST(NewtonianFlow, RotatingCylinderCouetteTorque) {
  const CouetteResult r = rotating_cylinder_couette(0.05, 0.2, 3.0, 2.0, 3);
  const double rel_reaction = std::abs(r.torque_reaction / r.torque_exact - 1);
  const double rel_surface = std::abs(r.torque_surface / r.torque_exact - 1);
  RecordProperty("torque_exact", std::to_string(r.torque_exact));
  RecordProperty("torque_reaction_rel_error", std::to_string(rel_reaction));
  RecordProperty("torque_surface_rel_error", std::to_string(rel_surface));
  std::printf(
      "Couette: exact %.8g  reaction %.8g (rel %.2e)  surface %.8g (rel %.2e)  cells %d  u L2 err "
      "%.3e\n",
      r.torque_exact, r.torque_reaction, rel_reaction, r.torque_surface, rel_surface, r.cells,
      r.velocity_l2_error);
  EXPECT_LT(rel_reaction, 1e-4);
  EXPECT_LT(rel_surface, 3e-2);
  EXPECT_LT(std::hypot(r.fx, r.fy) * 0.05, 1e-8 * std::abs(r.torque_exact));
  std::printf("Couette wall shear: consistent traction %.2e, from the stress %.2e\n",
              r.shear_error_consistent, r.shear_error_gradient);
  EXPECT_LT(r.shear_error_consistent, 2e-4);
  EXPECT_LT(r.shear_error_gradient, 3e-2);
}

// Manufactured Stokes solution on [0,1]^2 (see verification.h). Q2-Q1 Taylor-Hood must give
// rates 3 (L2 velocity), 2 (H1 velocity) and 2 (L2 pressure): the observed rate between the two
// finest of h = 1/4 ... 1/32 must be within 0.25 of the theory.
TEST(NewtonianFlow, ManufacturedStokesConvergenceRates) {
  std::vector<ManufacturedResult> runs;
  for (int level = 2; level <= 5; ++level) runs.push_back(manufactured_stokes(level));
  for (std::size_t k = 0; k < runs.size(); ++k) {
    EXPECT_TRUE(runs[k].converged);
    std::printf("Stokes MMS h=%.4f  |u|L2 %.3e  |u|H1 %.3e  |p|L2 %.3e\n", runs[k].h,
                runs[k].velocity_l2, runs[k].velocity_h1, runs[k].pressure_l2);
  }
  const auto rate = [&](double ManufacturedResult::*f) {
    const auto& a = runs[runs.size() - 2];
    const auto& b = runs.back();
    return std::log(a.*f / b.*f) / std::log(a.h / b.h);
  };
  const double ru = rate(&ManufacturedResult::velocity_l2);
  const double rg = rate(&ManufacturedResult::velocity_h1);
  const double rp = rate(&ManufacturedResult::pressure_l2);
  std::printf("Stokes MMS rates: u L2 %.3f  u H1 %.3f  p L2 %.3f\n", ru, rg, rp);
  EXPECT_NEAR(ru, 3.0, 0.25);
  EXPECT_NEAR(rg, 2.0, 0.25);
  EXPECT_NEAR(rp, 2.0, 0.25);
}

// The same manufactured Stokes problem solved with FGMRES and the block preconditioner
// (LinearSolver::amg), with both Schur complement approximations (B diag(A)^-1 B^T, the
// default, and the lumped pressure mass matrix / eta), must give the discrete solution of the
// direct solver: errors equal to 1e-6 relative at every level (the iterative solves stop at
// 1e-10 |rhs| in the scaled norm, then the outer loop checks |R| <= 1e-12 |R_0|), hence the
// same rates.
TEST(NewtonianFlow, ManufacturedStokesAmgMatchesDirect) {
  using grainlift::continuum::LinearSolver;
  using grainlift::continuum::SchurApproximation;
  for (int level = 2; level <= 5; ++level) {
    const ManufacturedResult d = manufactured_stokes(level);
    for (const auto schur : {SchurApproximation::diagonal_a, SchurApproximation::viscosity_mass}) {
      const ManufacturedResult a = manufactured_stokes(level, LinearSolver::amg, schur);
      std::printf("Stokes MMS h=%.4f  amg (%s): %d solves, %ld FGMRES iterations; |u|L2 %.6e vs "
                  "%.6e, |p|L2 %.6e vs %.6e\n",
                  a.h, schur == SchurApproximation::diagonal_a ? "B diag(A)^-1 B^T" : "M_p/eta",
                  a.nonlinear_iterations, a.krylov_iterations, a.velocity_l2, d.velocity_l2,
                  a.pressure_l2, d.pressure_l2);
      EXPECT_TRUE(a.converged);
      EXPECT_GT(a.krylov_iterations, 0);
      EXPECT_NEAR(a.velocity_l2 / d.velocity_l2, 1.0, 1e-6);
      EXPECT_NEAR(a.velocity_h1 / d.velocity_h1, 1.0, 1e-6);
      EXPECT_NEAR(a.pressure_l2 / d.pressure_l2, 1.0, 1e-6);
    }
  }
}

// Couette torque with the iterative solver: same as the direct solve to 1e-8 relative
// (the pressure is pinned at one node: the pinned row must be handled by the preconditioner).
TEST(NewtonianFlow, RotatingCylinderCouetteAmgMatchesDirect) {
  const CouetteResult d = rotating_cylinder_couette(0.05, 0.2, 3.0, 2.0, 3);
  const CouetteResult a =
      rotating_cylinder_couette(0.05, 0.2, 3.0, 2.0, 3, grainlift::continuum::LinearSolver::amg);
  std::printf("Couette amg: torque %.10g vs direct %.10g, %ld FGMRES iterations\n",
              a.torque_reaction, d.torque_reaction, a.krylov_iterations);
  EXPECT_NEAR(a.torque_reaction / d.torque_reaction, 1.0, 1e-8);
  EXPECT_NEAR(a.shear_error_consistent, d.shear_error_consistent, 1e-7);
}
