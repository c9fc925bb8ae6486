// Unit tests of the contact kernel alone (no integrator): force against overlap at rest,
// the stick-then-slip sequence of an oblique contact and the spring truncation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "grainlift/dem/contact/contact_law.h"
#include "grainlift/dem/contact/contact_law_batch.h"
#include "grainlift/dem/errors.h"
#include "grainlift/dem/step/vector_kernels.h"
#include "grainlift/dem/periodic_box.h"
#include "step/pair_inputs.h"

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
                      same(b.fty[l], f.fty) && same(b.sx[l], sx) && same(b.sy[l], sy) &&
                      same(b.q[l], k.nx * f.fty - k.ny * f.ftx))
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
    std::printf("%s: contact_force_batch vectorised: %s\n", target.c_str(),
                gd::contact_force_batch_vectorized(gd::LawCoefficients::from(gd::ContactParams{}))
                    ? "yes"
                    : "no");
  }
  gd::set_simd_target(before);
}

namespace {
/// A small bed for the pair lanes: grains (and wall rows after them) placed at random in a box
/// periodic in x and y, so that about four neighbours overlap each, some across the edges; the
/// overlapping pairs listed by owner row (a grain; the partner a grain of a later row or a wall).
struct PairBed {
  gd::PeriodicBox box{0.0, 0.3, 0.0, 0.2, true, true};
  static constexpr int kGrains = 180, kRows = 200;
  std::vector<double> x, y, r, vx, vy, w, ax, ay, al, inv_m, reff, meff, sx, sy, dx, dy;
  std::vector<int> owner, partner;

  explicit PairBed(std::uint64_t seed) {
    auto uniform = [&seed](double lo, double hi) {
      seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
      return lo + (hi - lo) * static_cast<double>(seed >> 11) * 0x1.0p-53;
    };
    for (auto* v : {&x, &y, &r, &vx, &vy, &w, &ax, &ay, &al, &inv_m}) v->resize(kRows);
    for (int g = 0; g < kRows; ++g) {
      r[g] = uniform(0.009, 0.011);
      x[g] = uniform(box.xmin, box.xmax);
      y[g] = uniform(box.ymin, box.ymax);
      const bool wall = g >= kGrains;  // frozen rows: no motion, no inverse mass
      vx[g] = wall ? 0.0 : uniform(-0.5, 0.5);
      vy[g] = wall ? 0.0 : uniform(-0.5, 0.5);
      w[g] = wall ? 0.0 : uniform(-20, 20);
      ax[g] = wall ? 0.0 : uniform(-50, 50);
      ay[g] = wall ? 0.0 : uniform(-50, 50);
      al[g] = wall ? 0.0 : uniform(-500, 500);
      inv_m[g] = wall ? 0.0 : uniform(150, 250);
    }
    for (int i = 0; i < kGrains; ++i) {
      for (int j = i + 1; j < kRows; ++j) {
        double ddx = x[i] - x[j], ddy = y[i] - y[j];
        box.min_image(ddx, ddy);
        if (ddx * ddx + ddy * ddy < (r[i] + r[j]) * (r[i] + r[j])) {
          owner.push_back(i);
          partner.push_back(j);
        }
      }
    }
    // the separations, constants and springs of the pairs, as the screen and the list build
    for (std::size_t k = 0; k < owner.size(); ++k) {
      const int i = owner[k], j = partner[k];
      double ddx = x[i] - x[j], ddy = y[i] - y[j];
      box.min_image(ddx, ddy);
      dx.push_back(ddx);
      dy.push_back(ddy);
      reff.push_back(r[i] * r[j] / (r[i] + r[j]));
      meff.push_back(1.0 / (inv_m[i] + inv_m[j]));
      const bool fresh = k % 5 == 0;
      sx.push_back(fresh ? 0.0 : uniform(-2e-5, 2e-5));
      sy.push_back(fresh ? 0.0 : uniform(-2e-5, 2e-5));
    }
  }
  gd::PairInputs inputs(bool pair_consts) const {
    return {r.data(),     vx.data(),    vy.data(),      w.data(),    ax.data(), ay.data(),
            al.data(),    inv_m.data(), reff.data(),    meff.data(), owner.data(),
            partner.data(), pair_consts, 1e-6,          2e-6,        kRows};
  }
};
}  // namespace

// The touching pairs' kinematics and the law (Kumar's and Guillard's) a vector of pairs at a
// time (pair_lanes, every SIMD target this CPU runs) give, pair by pair, the bits of the
// scalar PairInputs::of() followed by contact_force(): normal, overlap, advanced spring and
// forces, on pairs across the periodic box's edges and with wall rows, whose owners are
// consecutive (one load permuted) or far apart (one load per lane), r_eff and m_eff from the
// list or from the radii, in batches of 32, 13 and 1; and the largest overlap fraction is the
// scalar loop's, delta / (2 min(r_i, r_j)). Tolerance: none (the same bits).
static void pair_lanes_match_the_scalar_code(const gd::LawCoefficients& law) {
  const PairBed bed(2026);
  auto same = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  std::vector<std::int64_t> all(bed.owner.size()), strided;
  for (std::size_t k = 0; k < all.size(); ++k) all[k] = static_cast<std::int64_t>(k);
  for (std::size_t k = 0; k < all.size(); k += 7) strided.push_back(static_cast<std::int64_t>(k));
  const std::string before = gd::simd_target();
  int vector_targets = 0;
  for (const std::string& target : gd::runnable_simd_targets()) {
    SCOPED_TRACE(target);
    ASSERT_TRUE(gd::set_simd_target(target));
    long pairs = 0;
    for (bool consts : {true, false}) {
      const gd::PairInputs in = bed.inputs(consts);
      for (const auto* list : {&all, &strided}) {
        for (std::size_t nb : {std::size_t{32}, std::size_t{13}, std::size_t{1}}) {
          for (std::size_t b0 = 0; b0 + nb <= list->size(); b0 += nb) {
            const std::int64_t* kb = list->data() + b0;
            std::vector<double> ddx(nb), ddy(nb);  // the screen's separations, batch order
            for (std::size_t l = 0; l < nb; ++l) {
              ddx[l] = bed.dx[static_cast<std::size_t>(kb[l])];
              ddy[l] = bed.dy[static_cast<std::size_t>(kb[l])];
            }
            gd::ContactBatch cb{};
            double max_ov = 0.0;
            const std::size_t done = gd::pair_lanes(in, law, 0.5, kb, ddx.data(), ddy.data(),
                                                          nb, bed.sx.data(), bed.sy.data(), cb,
                                                          max_ov);
            if (target == "scalar") {
              ASSERT_EQ(done, 0u);  // no lanes: the caller's scalar loop runs
              continue;
            }
            ASSERT_EQ(done, nb);
            double ref_ov = 0.0;
            for (std::size_t l = 0; l < nb; ++l, ++pairs) {
              const auto k = static_cast<std::size_t>(kb[l]);
              gd::ContactKinematics kin = in.of(kb[l], bed.dx[k], bed.dy[k]);
              kin.mu = 0.5;
              double sx = bed.sx[k], sy = bed.sy[k];
              gd::ContactForce f;
              gd::contact_force(law, kin, sx, sy, f);
              ASSERT_TRUE(same(cb.nx[l], kin.nx) && same(cb.ny[l], kin.ny) &&
                          same(cb.delta[l], kin.delta) && same(cb.fx[l], f.fx) &&
                          same(cb.fy[l], f.fy) && same(cb.ftx[l], f.ftx) &&
                          same(cb.fty[l], f.fty) && same(cb.sx[l], sx) && same(cb.sy[l], sy) &&
                          same(cb.q[l], kin.nx * f.fty - kin.ny * f.ftx))
                  << "pair " << k << " lane " << l << " of " << nb << " consts " << consts;
              const int i = bed.owner[k], j = bed.partner[k];
              ref_ov = std::max(ref_ov, kin.delta / (2.0 * std::min(bed.r[i], bed.r[j])));
            }
            ASSERT_TRUE(same(max_ov, ref_ov)) << max_ov << " against " << ref_ov;
          }
        }
      }
    }
    if (target != "scalar") {
      ++vector_targets;
      EXPECT_GT(pairs, 500);
    }
    std::printf("%s: %ld pairs compared\n", target.c_str(), pairs);
  }
  std::printf("vector targets: %d\n", vector_targets);
  gd::set_simd_target(before);
}

TEST(ContactLaw, PairLanesGiveTheBitsOfTheScalarKinematicsAndLaw) {
  gd::ContactParams guillard;
  guillard.law = gd::ContactLaw::guillard2014;
  for (const gd::ContactParams& p : {gd::ContactParams{}, guillard}) {
    SCOPED_TRACE(p.law == gd::ContactLaw::kumar2019 ? "kumar2019" : "guillard2014");
    pair_lanes_match_the_scalar_code(gd::LawCoefficients::from(p));
  }
}
