// The mu(I) kernel: formula, limits and derivatives (no finite elements involved).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "grainlift/continuum/mu_i_rheology.h"

using namespace grainlift::continuum;

namespace {
struct Eval {
  double eta, eta_s, eta_p, mu, I;
};
Eval eval(const ViscosityModel& m, double s, double p) {
  RheologyInputs in;
  in.resize(1);
  RheologyOutputs out;
  out.resize(1);
  in.strain_rate_sq[0] = s;
  in.pressure[0] = p;
  m.evaluate(in, out);
  return {out.viscosity[0], out.deta_dstrain_sq[0], out.deta_dpressure[0], out.friction[0],
          out.inertial_number[0]};
}
}  // namespace

// Simple shear at rate gamma: |D| = gamma / 2, so I = gamma d / sqrt(p / rho_s) and the
// shear stress 2 eta D_xy = eta gamma must equal mu(I) p (Jop et al. 2006) when delta << |D|.
TEST(MuIRheology, SimpleShearGivesMuOfIP) {
  RheologyParams prm;
  prm.delta = 1e-9;
  prm.eta_max = 1e12;
  MuIRheology m(prm);
  const double gamma = 20, p = 300;
  const Eval e = eval(m, 0.25 * gamma * gamma, p);
  const double I = gamma * prm.grain_diameter / std::sqrt(p / prm.solid_density);
  const double mu = prm.mu_s + (prm.mu_2 - prm.mu_s) / (prm.I0 / I + 1);
  EXPECT_NEAR(e.I, I, 1e-12 * I);
  EXPECT_NEAR(e.mu, mu, 1e-12);
  EXPECT_NEAR(e.eta * gamma, mu * p, 1e-6 * mu * p);
}

// The pressure is clamped at zero inside the rheology: p <= 0 gives the floor eta_min and no
// pressure derivative. At vanishing strain rate the smooth cap eta_max tanh(eta / eta_max)
// gives eta_max (to 1e-12) with vanishing derivatives; well below the cap eta is unchanged
// (relative change (eta/eta_max)^2/3 < 1e-6 for eta = 1e-3 eta_max).
TEST(MuIRheology, ClampFloorAndCap) {
  RheologyParams prm;
  prm.regularisation = Regularisation::chauchat_medale;
  MuIRheology m(prm);
  const Eval neg = eval(m, 1.0, -5.0);
  EXPECT_EQ(neg.eta, prm.eta_min);
  EXPECT_EQ(neg.eta_p, 0.0);
  const Eval rigid = eval(m, 0.0, 1000.0);
  EXPECT_NEAR(rigid.eta, prm.eta_max, 1e-12 * prm.eta_max);
  EXPECT_NEAR(rigid.eta_s, 0.0, 1e-12 * prm.eta_max / (prm.delta * prm.delta));
  // simple shear at 50 1/s, p = 100 Pa: eta = mu p / (2 sqrt(|D|^2 + delta^2)) ~ 0.9 Pa s
  const double s = 625.0, p = 100.0;
  const Eval e = eval(m, s, p);
  const double I = 2 * 25.0 * prm.grain_diameter / std::sqrt(p / prm.solid_density);
  const double mu = prm.mu_s + (prm.mu_2 - prm.mu_s) / (prm.I0 / I + 1);
  EXPECT_NEAR(e.eta, mu * p / (2 * std::sqrt(s + prm.delta * prm.delta)), 1e-6 * e.eta);
}

// d eta / d|D|^2 and d eta / dp against central differences (relative error < 1e-6), for both
// regularisations, away from the cap.
TEST(MuIRheology, DerivativesMatchFiniteDifferences) {
  for (const auto reg : {Regularisation::chauchat_medale, Regularisation::barker_gray}) {
    RheologyParams prm;
    prm.regularisation = reg;
    prm.delta = 0.5;
    prm.eta_max = 1e12;
    prm.barker_gray_IN = 1e-2;
    MuIRheology m(prm);
    for (const double s : {1e-3, 0.3, 10.0, 400.0})
      for (const double p : {5.0, 100.0, 2000.0}) {
        const Eval e = eval(m, s, p);
        const double hs = 1e-6 * s, hp = 1e-6 * p;
        const double fd_s = (eval(m, s + hs, p).eta - eval(m, s - hs, p).eta) / (2 * hs);
        const double fd_p = (eval(m, s, p + hp).eta - eval(m, s, p - hp).eta) / (2 * hp);
        EXPECT_NEAR(e.eta_s, fd_s, 1e-6 * std::abs(fd_s) + 1e-12 * e.eta / s)
            << "s=" << s << " p=" << p;
        EXPECT_NEAR(e.eta_p, fd_p, 1e-6 * std::abs(fd_p) + 1e-12) << "s=" << s << " p=" << p;
      }
  }
}

// Barker & Gray 2017: below I_N, mu = sqrt(alpha / ln(A / I)) joins mu(I) with the same value
// and slope at I_N (relative mismatch < 1e-9) and tends to 0 as I -> 0.
TEST(MuIRheology, BarkerGrayBranchIsC1AndVanishesAtZero) {
  RheologyParams prm;
  prm.regularisation = Regularisation::barker_gray;
  prm.barker_gray_IN = 5e-3;
  MuIRheology m(prm);
  const double IN = prm.barker_gray_IN, e = 1e-9;
  EXPECT_NEAR(m.friction(IN * (1 - e)), m.friction(IN * (1 + e)), 1e-9);
  EXPECT_NEAR(m.dfriction_dI(IN * (1 - e)), m.dfriction_dI(IN * (1 + e)),
              1e-6 * m.dfriction_dI(IN));
  EXPECT_LT(m.friction(1e-300), 0.1);
  EXPECT_GT(m.friction(1e-6), 0);
}

// Barker et al. (JFM 779, 2015): incompressible mu(I) in 2D is well posed only at intermediate
// I. For the glass-bead parameters (mu_s 0.38, mu_2 0.64, I_0 0.279) it must be ill posed deep
// in the quasi-static range (I = 1e-4) and far in the collisional one (I = 10), well posed at
// I = 0.1, and the ends of well_posed_range() must be roots of the criterion (|C| < 1e-9 there,
// with opposite signs 1% inside and outside).
TEST(MuIRheology, JopLawIsWellPosedOnlyAtIntermediateI) {
  RheologyParams prm;
  prm.regularisation = Regularisation::chauchat_medale;
  MuIRheology m(prm);
  EXPECT_GT(m.well_posedness(1e-4), 0);
  EXPECT_GT(m.well_posedness(10.0), 0);
  EXPECT_LT(m.well_posedness(0.1), 0);
  const InertialRange w = well_posed_range(prm);
  ASSERT_FALSE(w.empty());
  std::printf("mu(I) well posed for %.5g < I < %.5g\n", w.low, w.high);
  for (const double end : {w.low, w.high}) EXPECT_LT(std::abs(m.well_posedness(end)), 1e-9);
  EXPECT_GT(m.well_posedness(0.99 * w.low), 0);
  EXPECT_LT(m.well_posedness(1.01 * w.low), 0);
  EXPECT_LT(m.well_posedness(0.99 * w.high), 0);
  EXPECT_GT(m.well_posedness(1.01 * w.high), 0);
  // a constant friction (mu_2 -> mu_s: nu -> 0) is ill posed everywhere
  RheologyParams coulomb = prm;
  coulomb.mu_2 = prm.mu_s * (1 + 1e-9);
  EXPECT_TRUE(well_posed_range(coulomb).empty());
}

// Barker & Gray 2017: the low-I branch makes the law well posed for every I below I_N when I_N
// lies in mu(I)'s well-posed range: C < 0 at 200 points from I = 1e-12 to I_N, for the
// automatic I_N (1.5 x the lower end) and for I_N at the middle of the range. Joined below the
// range (I_N = 1e-3) it is not (C > 0 just below I_N).
TEST(MuIRheology, BarkerGrayBranchIsWellPosedBelowIN) {
  RheologyParams prm;
  prm.regularisation = Regularisation::barker_gray;
  const InertialRange w = well_posed_range(prm);
  for (const double IN : {0.0, std::sqrt(w.low * w.high)}) {
    prm.barker_gray_IN = IN;
    MuIRheology m(prm);
    EXPECT_GT(m.barker_gray_IN(), w.low);
    EXPECT_LT(m.barker_gray_IN(), w.high);
    double worst = -1e300;
    for (int k = 0; k < 200; ++k) {
      const double I = 1e-12 * std::pow(m.barker_gray_IN() / 1e-12, k / 199.0);
      worst = std::max(worst, m.well_posedness(I));
    }
    std::printf("I_N = %.4g: largest criterion below I_N %.3g\n", m.barker_gray_IN(), worst);
    EXPECT_LT(worst, 0) << "I_N = " << m.barker_gray_IN();
  }
  prm.barker_gray_IN = 1e-3;
  MuIRheology below(prm);
  EXPECT_GT(below.well_posedness(0.9e-3), 0);
}

// Smoothed clamp p+ = (p + sqrt(p^2 + p_eps^2)) / 2: far from p = 0 (|p| = 1e3 p_eps) the
// viscosity is that of the hard clamp within 1e-6 relative (p > 0) or tiny (p < 0: floored or
// below 1e-6 of the p > 0 value); d eta / dp is continuous across p = 0 (left and right
// derivatives at +-1e-9 p_eps agree to 1e-6) and matches central differences to 1e-6.
TEST(MuIRheology, SmoothedPressureClampIsContinuousAtZero) {
  RheologyParams prm;
  prm.delta = 0.5;
  prm.eta_max = 1e12;
  prm.eta_min = 0;
  RheologyParams hard = prm;
  prm.pressure_smoothing = 1.0;  // Pa
  const MuIRheology m(prm), mh(hard);
  const double s = 4.0;
  const Eval pos = eval(m, s, 1e3), pos_hard = eval(mh, s, 1e3);
  EXPECT_NEAR(pos.eta, pos_hard.eta, 1e-6 * pos_hard.eta);
  EXPECT_LT(eval(m, s, -1e3).eta, 1e-6 * pos.eta);
  const Eval left = eval(m, s, -1e-9), right = eval(m, s, 1e-9);
  EXPECT_GT(right.eta_p, 0);
  EXPECT_NEAR(left.eta_p, right.eta_p, 1e-6 * right.eta_p);
  for (const double p : {-3.0, -0.2, 0.0, 0.4, 7.0}) {
    const double h = 1e-6;
    const double fd = (eval(m, s, p + h).eta - eval(m, s, p - h).eta) / (2 * h);
    EXPECT_NEAR(eval(m, s, p).eta_p, fd, 1e-6 * std::abs(fd) + 1e-12) << "p=" << p;
  }
  // the hard clamp jumps: d eta / dp is 0 just below 0 and finite just above
  EXPECT_EQ(eval(mh, s, -1e-9).eta_p, 0.0);
  EXPECT_GT(eval(mh, s, 1e-9).eta_p, 0.0);
}
