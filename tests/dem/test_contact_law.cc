// Unit tests of the contact kernel alone (no integrator): force against overlap at rest,
// the stick-then-slip sequence of an oblique contact and the spring truncation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

#include "grainlift/dem/contact/contact_law.h"
#include "grainlift/dem/contact/contact_law_batch.h"
#include "grainlift/dem/errors.h"
#include "grainlift/dem/step/vector_kernels.h"

namespace gd = grainlift::dem;

namespace {

gd::ContactKinematics at_rest(double delta, double r1, double r2, double m_eff) {
  gd::ContactKinematics k;
  k.nx = 1;
  k.ny = 0;
  k.delta = delta;
  k.r_eff = r1 * r2 / (r1 + r2);
  k.m_eff = m_eff;
  k.mu = 0.5;
  return k;
}

}  // namespace

// Physics: at rest (no velocity, no spring) Kumar eq. (1) reduces to
// F_n = sqrt(R_eff delta) Kn delta with R_eff = d1 d2 / (2 (d1 + d2)). Tolerance 1e-14 relative.
TEST(ContactLaw, KumarForceAgainstOverlapAtRest) {
  const auto c = gd::LawCoefficients::from(gd::ContactParams{});
  for (double delta : {1e-7, 1e-6, 1e-5, 1e-4}) {
    const double d1 = 0.021, d2 = 0.019;
    auto k = at_rest(delta, d1 / 2, d2 / 2, 1e-3);
    double sx = 0, sy = 0;
    gd::ContactForce f;
    gd::contact_force(c, k, sx, sy, f);
    const double expected = std::sqrt(d1 * d2 / (2 * (d1 + d2)) * delta) * 2e9 * delta;
    EXPECT_NEAR(f.fn, expected, 1e-14 * expected) << "delta = " << delta;
    EXPECT_NEAR(f.fx, expected, 1e-14 * expected);
    EXPECT_EQ(f.fy, 0.0);
    EXPECT_EQ(f.ftx, 0.0);
    EXPECT_FALSE(f.slipping);
  }
}

// Physics: Guillard 2014 Table I at rest: F_n = kn* delta^(3/2) with
// kn* = (2/3) E/(1-nu^2) sqrt(R_eff); for two equal grains of diameter d this is
// E/(3(1-nu^2)) sqrt(d) = 81e3 N m^-3/2 for d = 1.5 mm (Table I value, to its 2 digits).
// Tolerance 1e-14 relative against the formula, 1% against the tabulated 81e3.
TEST(ContactLaw, GuillardForceAgainstOverlapAtRest) {
  gd::ContactParams p;
  p.law = gd::ContactLaw::guillard2014;
  const auto c = gd::LawCoefficients::from(p);
  const double d = 1.5e-3, delta = 1e-6;
  auto k = at_rest(delta, d / 2, d / 2, 1e-6);
  double sx = 0, sy = 0;
  gd::ContactForce f;
  gd::contact_force(c, k, sx, sy, f);
  const double kn_star = 5e6 / (3 * (1 - 0.45 * 0.45)) * std::sqrt(d);
  EXPECT_NEAR(f.fn, kn_star * std::pow(delta, 1.5), 1e-14 * kn_star * std::pow(delta, 1.5));
  EXPECT_NEAR(kn_star, 81e3, 0.01 * 81e3);
}

// Physics: an oblique contact at fixed overlap driven at constant tangential velocity v_t
// (no damping) first sticks, |F_t| = Kt sqrt(R delta) v_t t (tolerance 1e-12 relative), then
// slips at |F_t| = mu |F_n| (tolerance 1e-12 relative). On reversing the motion the truncated
// spring unloads at once: after one reversed step |F_t| = mu F_n - Kt sqrt(R delta) v_t dt.
TEST(ContactLaw, ObliqueContactSticksThenSlipsAtMu) {
  gd::ContactParams p;
  p.gamma_n = 0;
  p.gamma_t = 0;
  const auto c = gd::LawCoefficients::from(p);
  const double r = 0.01, delta = 2e-5, vt = 0.01, dt = 2e-6;
  auto k = at_rest(delta, r, r, 3e-3);
  const double root = std::sqrt(k.r_eff * delta);
  const double fn = 2e9 * root * delta;
  const double stick_limit = 0.5 * fn;
  double sx = 0, sy = 0;
  gd::ContactForce f;
  int step = 0;
  bool slipped = false;
  for (; step < 10000; ++step) {
    k.dsx = 0;
    k.dsy = vt * dt;
    k.vty = vt;
    gd::contact_force(c, k, sx, sy, f);
    const double stick_force = 2.45e9 * root * vt * dt * (step + 1);
    if (stick_force < stick_limit * (1 - 1e-9)) {
      ASSERT_FALSE(f.slipping) << "step " << step;
      ASSERT_NEAR(-f.fty, stick_force, 1e-12 * stick_force) << "step " << step;
    } else if (stick_force > stick_limit * (1 + 1e-9)) {
      slipped = true;
      ASSERT_TRUE(f.slipping) << "step " << step;
      ASSERT_NEAR(-f.fty, stick_limit, 1e-12 * stick_limit) << "step " << step;
    }
    EXPECT_NEAR(f.fn, fn, 1e-14 * fn);
  }
  EXPECT_TRUE(slipped);
  // reverse the sliding direction for one step
  k.dsy = -vt * dt;
  k.vty = -vt;
  gd::contact_force(c, k, sx, sy, f);
  EXPECT_FALSE(f.slipping);
  const double expected = stick_limit - 2.45e9 * root * vt * dt;
  EXPECT_NEAR(-f.fty, expected, 1e-12 * stick_limit);
}

// Physics: the spring is rotated into the current contact plane with its length kept, so a
// rotation of the contact by 30 degrees keeps |F_t| and leaves it normal to n (1e-12).
TEST(ContactLaw, SpringRotatesWithTheContactPlane) {
  gd::ContactParams p;
  p.gamma_n = p.gamma_t = 0;
  p.friction = 10;
  const auto c = gd::LawCoefficients::from(p);
  auto k = at_rest(1e-5, 0.01, 0.01, 3e-3);
  double sx = 0, sy = 1e-6;
  gd::ContactForce f1, f2;
  gd::contact_force(c, k, sx, sy, f1);
  k.nx = std::cos(M_PI / 6);
  k.ny = std::sin(M_PI / 6);  // contact rotated by +30 degrees
  gd::contact_force(c, k, sx, sy, f2);
  EXPECT_NEAR(std::hypot(f2.ftx, f2.fty), std::hypot(f1.ftx, f1.fty), 1e-12 * std::abs(f1.fty));
  EXPECT_NEAR(f2.ftx * k.nx + f2.fty * k.ny, 0.0, 1e-12 * std::abs(f1.fty));
}

// Physics: bad material parameters are refused with a ConfigError naming them.
TEST(ContactLaw, RefusesBadParameters) {
  gd::ContactParams p;
  p.kn = -1;
  EXPECT_THROW(gd::LawCoefficients::from(p), gd::ConfigError);
  gd::ContactParams g;
  g.law = gd::ContactLaw::guillard2014;
  g.restitution = 1.5;
  EXPECT_THROW(gd::LawCoefficients::from(g), gd::ConfigError);
}

/// One pass of ContactLaw.BatchGivesTheBitsOfContactForce on the SIMD target in use.
static void batch_matches_contact_force() {
  std::uint64_t state = 12345;
  auto uniform = [&state](double lo, double hi) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return lo + (hi - lo) * static_cast<double>(state >> 11) * 0x1.0p-53;
  };
  auto same = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  long slipping = 0, sticking = 0;
  for (int variant = 0; variant < 3; ++variant) {
    gd::ContactParams p;
    if (variant == 1) p.kt = 0;
    if (variant == 2) p.law = gd::ContactLaw::guillard2014;
    const auto c = gd::LawCoefficients::from(p);
    for (std::size_t n : {std::size_t{32}, std::size_t{13}, std::size_t{1}}) {
      for (int rep = 0; rep < 200; ++rep) {
        gd::ContactBatch b{};
        const double mu = rep % 3 == 0 ? 0.0 : uniform(0.05, 0.8);
        for (std::size_t l = 0; l < n; ++l) {
          const double a = uniform(0, 6.283185307179586);
          b.nx[l] = std::cos(a);
          b.ny[l] = std::sin(a);
          b.delta[l] = uniform(1e-9, 1e-4);
          b.r_eff[l] = uniform(0.004, 0.006);
          b.m_eff[l] = uniform(1e-3, 5e-3);
          b.vn[l] = uniform(-0.5, 0.5);
          b.vtx[l] = uniform(-0.5, 0.5);
          b.vty[l] = uniform(-0.5, 0.5);
          b.dsx[l] = uniform(-1e-6, 1e-6);
          b.dsy[l] = uniform(-1e-6, 1e-6);
          const bool empty = (rep + l) % 4 == 0;  // a fresh contact: no spring yet
          b.sx[l] = empty ? 0.0 : uniform(-1e-5, 1e-5);
          b.sy[l] = empty ? 0.0 : uniform(-1e-5, 1e-5);
        }
        gd::ContactBatch ref = b;
        gd::contact_force_batch(c, mu, b, n);
        for (std::size_t l = 0; l < n; ++l) {
          const gd::ContactKinematics k = ref.kinematics(l, mu);
          double sx = ref.sx[l], sy = ref.sy[l];
          gd::ContactForce f;
          gd::contact_force(c, k, sx, sy, f);
          ASSERT_TRUE(same(b.fx[l], f.fx) && same(b.fy[l], f.fy) && same(b.ftx[l], f.ftx) &&
                      same(b.fty[l], f.fty) && same(b.sx[l], sx) && same(b.sy[l], sy))
              << "variant " << variant << " n " << n << " rep " << rep << " lane " << l
              << " slipping " << f.slipping;
          (f.slipping ? slipping : sticking) += 1;
        }
      }
    }
  }
  EXPECT_GT(slipping, 1000);  // both branches of the Coulomb cut are exercised
  EXPECT_GT(sticking, 1000);
  std::printf("slipping %ld, sticking %ld\n", slipping, sticking);
}

// The batched law (contact_law_batch.h; vector lanes on every SIMD target this build and CPU
// run, scalar among them) gives the bits of contact_force() contact by contact: random
// contacts that stick and slip, springs of zero length, a law without tangential spring
// (kt = 0: the slip truncation sets s = 0), both laws, full and short batches.
TEST(ContactLaw, BatchGivesTheBitsOfContactForce) {
  const std::string before = gd::simd_target();
  for (const std::string& target : gd::runnable_simd_targets()) {
    SCOPED_TRACE(target);
    ASSERT_TRUE(gd::set_simd_target(target));
    batch_matches_contact_force();
    std::printf("%s: contact_force_batch vectorised for Kumar's law: %s\n", target.c_str(),
                gd::contact_force_batch_vectorized(gd::LawCoefficients::from(gd::ContactParams{}))
                    ? "yes"
                    : "no");
  }
  gd::set_simd_target(before);
}
