// Contacts of the grains with the intruder (stage 2 of the step, serial, fixed order): the
// intruder's motion is prescribed, its mass infinite; the force and torque on it are summed here.
#include <cmath>

#include "grainlift/dem/contact/contact_law.h"
#include "grainlift/dem/system/dem_system.h"

namespace grainlift::dem {

void DemSystem::intruder_forces(double spring_dt, double& max_ov) {
  const double h = 0.5 * spring_dt;
  ifx_ = ify_ = itq_ = 0;
  intruder_touching_ = 0;
  if (!intruder_.present) return;
  const PeriodicBox box = opt_.box;
  const LawCoefficients law = law_;
  const ParticleArrays& p = p_;
  const Intruder& in = intruder_;
  const double t_half = time_ - in.t0 + h;
  const double t_full = time_ - in.t0 + spring_dt;
  const double wh_in = in.omega(t_half), wp_in = in.omega(t_full);
  const double big_r = in.r;
  for (std::size_t c = 0; c < ic_.grain.size(); ++c) {
    const int g = ic_.grain[c];
    double dx = p.x[g] - in.x, dy = p.y[g] - in.y;
    box.min_image(dx, dy);
    const double rs = p.r[g] + big_r;
    const double d2 = dx * dx + dy * dy;
    if (d2 >= rs * rs) {
      ic_.sx[c] = ic_.sy[c] = 0;
      ic_.fx[c] = ic_.fy[c] = ic_.fn[c] = ic_.ft[c] = ic_.vt[c] = 0;
      ic_.touching[c] = ic_.slipping[c] = 0;
      continue;
    }
    const double dist = std::sqrt(d2);
    ContactKinematics kin;
    kin.nx = dx / dist;
    kin.ny = dy / dist;
    kin.delta = rs - dist;
    kin.r_eff = p.r[g] * big_r / rs;
    kin.m_eff = 1.0 / p.inv_m[g];  // the intruder has infinite mass
    kin.mu = mu_intruder_;
    // predicted velocities at t+dt, then the half-step velocities (the intruder's exact)
    contact_point_motion(kin.nx, kin.ny, p.r[g], big_r,
                         {p.vx[g] + h * p.ax[g], p.vy[g] + h * p.ay[g], p.w[g] + h * p.alpha[g]},
                         {in.vx, in.vy, wp_in}, {p.vx[g], p.vy[g], p.w[g]}, {in.vx, in.vy, wh_in},
                         spring_dt, kin);
    const double tx = -kin.ny, ty = kin.nx;
    ContactForce f;
    contact_force(law, kin, ic_.sx[c], ic_.sy[c], f);
    ic_.fx[c] = f.fx;
    ic_.fy[c] = f.fy;
    ic_.fn[c] = f.fn;
    ic_.ft[c] = f.ftx * tx + f.fty * ty;
    ic_.vt[c] = kin.vtx * tx + kin.vty * ty;
    ic_.nx[c] = kin.nx;
    ic_.ny[c] = kin.ny;
    ic_.touching[c] = 1;
    ic_.slipping[c] = f.slipping ? 1 : 0;
    ifx_ -= f.fx;
    ify_ -= f.fy;
    itq_ -= big_r * normal_cross_tangential(kin.nx, kin.ny, f.ftx, f.fty);
    ++intruder_touching_;
    const double ov = kin.delta / (2.0 * p.r[g]);
    if (ov > max_ov) max_ov = ov;
  }
}

}  // namespace grainlift::dem
