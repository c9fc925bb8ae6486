// Spin ramp (intruder.spin_ramp_time): the prescribed angular velocity rises linearly from 0 to
// omega over the ramp time, and the grains respond to it: the friction torque and the lift along
// -omega x V (Kumar 2019 Sec. III) appear as the spin builds up.
#include <gtest/gtest.h>

#include <cmath>

#include "grainlift/dem/system/dem_system.h"
#include "grainlift/dem/scenes/simulation.h"
#include "dem_beds.h"

namespace gd = grainlift::dem;

namespace {

/// The small bed of the simulation tests: 30 d x 20 d, walls top and bottom, Phi 0.8,
/// intruder 5 d at V = 1 m/s along +x.
gd::DemConfig ramp_case() {
  gd::DemConfig c = grainlift::test_support::walled_bed(30, 20, 0.8);
  c.dt = 4e-6;
  c.seed = 3;
  return c;
}

}  // namespace

// Physics: omega(t) = omega_target t / T for 0 <= t <= T, omega_target after, counted from the
// moment the intruder is placed (not from t = 0 of the system). Checked on the intruder that a
// DemSystem actually steps: 0 at the start, half at T/2, full at T and at 2 T. Tolerance: 1e-12
// relative (the ramp is exact; only the rounding of the accumulated time enters).
TEST(SpinRamp, PrescribedOmegaFollowsTheRamp) {
  const auto c = ramp_case();
  gd::SystemOptions o;
  o.box = {c.xmin, c.xmax, c.ymin, c.ymax, true, false};
  o.dt = 1e-5;
  gd::DemSystem s(o);
  gd::Disk g;
  g.x = c.xmin + 0.1 * (c.xmax - c.xmin);
  g.y = 0.5 * c.ymax;
  g.r = 0.5 * c.grain_diameter;
  g.mass = 1e-2;
  s.set_bodies({g}, {});
  for (int k = 0; k < 7; ++k) s.step();  // the motion starts later than the system clock
  const double target = 20.0, ramp = 100 * o.dt;
  s.set_intruder(0, 0, 2.5 * c.grain_diameter, 1.0, 0, target, ramp);
  const double t0 = s.time();
  auto omega_now = [&] { return s.intruder().omega(s.time() - t0); };
  EXPECT_EQ(omega_now(), 0.0);
  for (int k = 0; k < 50; ++k) s.step();
  EXPECT_NEAR(omega_now(), 0.5 * target, 1e-12 * target);
  for (int k = 0; k < 25; ++k) s.step();
  EXPECT_NEAR(omega_now(), 0.75 * target, 1e-12 * target);
  for (int k = 0; k < 25; ++k) s.step();
  EXPECT_NEAR(omega_now(), target, 1e-12 * target);
  for (int k = 0; k < 100; ++k) s.step();
  EXPECT_EQ(omega_now(), target);
  // no ramp: full spin at once
  s.set_intruder(0, 0, 2.5 * c.grain_diameter, 1.0, 0, target, 0.0);
  EXPECT_EQ(s.intruder().omega(0.0), target);
}

namespace {

struct Window {
  double drag = 0, lift = 0, torque_ratio = 0;  // means; torque / (mu R sum fn)
};

/// Means over the samples with t in [t0, t1): drag -F_x, lift F_y, and the torque of the
/// grains over its Coulomb bound mu R sum(F_N) (-1: every contact slides against a
/// counter-clockwise spin).
Window window(const gd::DemOutput& out, double t0, double t1, double mu, double R) {
  std::vector<double> fn(out.samples.size(), 0.0);
  for (const auto& k : out.contacts) fn[static_cast<std::size_t>(k.sample)] += k.fn;
  Window w;
  double tq = 0, bound = 0;
  int n = 0;
  for (std::size_t i = 0; i < out.samples.size(); ++i) {
    const auto& s = out.samples[i];
    if (s.time < t0 || s.time >= t1) continue;
    w.drag -= s.fx;
    w.lift += s.fy;
    tq += s.torque;
    bound += mu * R * fn[i];
    ++n;
  }
  w.drag /= n;
  w.lift /= n;
  w.torque_ratio = tq / bound;
  return w;
}

}  // namespace

// Physics: with omega ramped from 0 to Omega = omega R / V = 10 over the first 10 d of travel,
// the grains feel the spin only as it builds up. Compared with the same bed and a non-spinning
// intruder (same seed, so the same bed and the same first steps):
//  * early (the first 0.25 d of travel, Omega(t) < 0.25) the forces are those of the
//    non-spinning run: lift and torque differ from it by less than 5% of the drag and of the
//    Coulomb bound respectively;
//  * after the ramp (travel 12 d to 22 d) the lift points along -omega x V (Kumar 2019 Sec. III):
//    L < -0.1 D (Kumar: L/D -> kappa mu - (1 - kappa)/mu ~ -0.25 at high Omega), and most
//    contacts slide against the spin: torque < -0.5 mu R sum F_N; without spin the torque is
//    small: |torque| < 0.25 mu R sum F_N.
TEST(SpinRamp, LiftAndTorqueFollowTheSpin) {
  auto c = ramp_case();
  const double d = c.grain_diameter, R = 0.5 * c.intruder_diameter, V = 1.0, mu = 0.5;
  c.intruder_omega = 10.0 * V / R;
  c.spin_ramp_time = 10 * d / V;
  c.travel = 22;
  c.steady_travel = 0;
  c.sample_every = 10;
  const auto spin = gd::run_simulation(c);
  c.intruder_omega = 0;
  const auto none = gd::run_simulation(c);
  const double t_early = 0.25 * d / V, t_late = 12 * d / V, t_end = 1.0;
  const Window se = window(spin, 0, t_early, mu, R), ne = window(none, 0, t_early, mu, R);
  const Window sl = window(spin, t_late, t_end, mu, R), nl = window(none, t_late, t_end, mu, R);
  EXPECT_GT(se.drag, 0.0);
  EXPECT_LT(std::abs(se.lift - ne.lift), 0.05 * ne.drag);
  EXPECT_LT(std::abs(se.torque_ratio - ne.torque_ratio), 0.05);
  EXPECT_LT(sl.lift, -0.1 * sl.drag);
  EXPECT_LT(sl.torque_ratio, -0.5);
  EXPECT_LT(std::abs(nl.torque_ratio), 0.25);
}
