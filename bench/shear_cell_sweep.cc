// mu(I) and Phi(I) of Kumar's grains (DemConfig defaults: d = 0.02 m, rho_s = 20 kg/m^2,
// Kumar Table I contact law, mu = 0.5) in the DEM simple-shear cell (shear_cell.h), at eight
// inertial numbers from 1e-3 to 0.5, for the mu(I) calibration of the continuum solver.
//
// Pressure P = 500 N/m: the stiffness number kn / P = Kn d / P = 8e4 (contact overlaps ~1e-3 d),
// nearly rigid grains (da Cruz et al. 2005: the rheology is independent of kn / P above ~1e4),
// and the time scale d / sqrt(P / rho_s) = 4 ms = 1000 steps of dt = 4e-6 s, so that the slow
// points stay affordable. U = I H sqrt(P / rho_s) / d for the target I (H the distance between
// the walls' centre lines). Usage: shear_cell_sweep [threads] [strain scale].
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "grainlift/dem/scenes/shear_cell.h"

namespace gd = grainlift::dem;

int main(int argc, char** argv) {
  const int threads = argc > 1 ? std::atoi(argv[1]) : 1;
  const double strain_scale = argc > 2 ? std::atof(argv[2]) : 1.0;
  const double targets[] = {1e-3, 3e-3, 1e-2, 3e-2, 0.06, 0.1, 0.2, 0.5};
  gd::ShearCellConfig c;
  c.grains.dt = 4e-6;
  c.grains.seed = 11;
  c.grains.threads = threads;
  c.grains.packing_cache_dir = "build/packing_cache";
  c.width = 20;
  c.height = 20;
  c.pressure = 500;
  const double d = c.grains.grain_diameter;
  const double gap = (c.height - 1) * d;  // between the walls' centre lines
  std::printf("shear cell %g d x %g d, P = %g N/m, kn/P = %.3g, dt = %g s, Kumar grains mu = %g\n",
              c.width, c.height, c.pressure, c.grains.contact.kn * d / c.pressure, c.grains.dt,
              c.grains.contact.friction);
  std::printf("%9s %9s %8s %14s %16s %7s %6s %7s %8s\n", "I_target", "I", "U(m/s)", "mu +- se",
              "Phi +- se", "R^2", "steady", "strain", "wall_s");
  const auto t_all = std::chrono::steady_clock::now();
  for (double target : targets) {
    c = gd::shear_cell_at(c, target, strain_scale);
    const double rate = c.wall_speed / gap;  // 1/s, nominal
    const auto t0 = std::chrono::steady_clock::now();
    const gd::ShearCellResult r = gd::run_shear_cell(c);
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("%9.3g %9.3g %8.3g %7.4f+-%.4f %8.4f+-%.4f %7.4f %6s %7.2f %8.1f\n", target,
                r.inertial_number, c.wall_speed, r.friction.mean, r.friction.se,
                r.area_fraction.mean, r.area_fraction.se, r.profile_r2, r.steady ? "yes" : "no",
                rate * r.steps * c.grains.dt, wall);
    std::fflush(stdout);
  }
  std::printf("sweep: %.1f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t_all).count());
  return 0;
}
