// mu(I) and Newtonian viscosity kernels. Formulas: mu(I) and I of Jop, Forterre & Pouliquen,
// Nature 441 (2006); regularisation of Chauchat & Medale, JCP 256 (2014); partial
// regularisation of Barker & Gray, JFM 828 (2017) (the C1 joint at I_N is derived here).
#include "grainlift/continuum/mu_i_rheology.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace grainlift::continuum {

namespace {
// Floor of |D| where a division by |D| cannot be avoided. The Newton terms that use
// d eta / d|D|^2 multiply it by (D:D_phi)^2 ~ |D|^2, so the product stays finite.
constexpr double kStrainFloor = 1e-100;

double mu_jop(const RheologyParams& p, double I) {
  // mu(I) = mu_s + (mu_2 - mu_s) I / (I_0 + I)
  return p.mu_s + (p.mu_2 - p.mu_s) * I / (p.I0 + I);
}
double dmu_jop(const RheologyParams& p, double I) {
  return (p.mu_2 - p.mu_s) * p.I0 / ((p.I0 + I) * (p.I0 + I));
}
}  // namespace

double barker_criterion(double mu, double nu) {
  return 4 * nu * nu - 4 * nu + mu * mu * (1 - 0.5 * nu) * (1 - 0.5 * nu);
}

InertialRange well_posed_range(const RheologyParams& p) {
  const auto c = [&p](double I) {
    const double mu = mu_jop(p, I);
    return barker_criterion(mu, I * dmu_jop(p, I) / mu);
  };
  // scan log-spaced I from 1e-10 to 1e4 for where C turns negative and, after that, where it
  // turns positive again; bisect each crossing
  const auto bisect = [&c](double a, double b) {  // c(a) and c(b) differ in sign
    for (int k = 0; k < 100 && b - a > 1e-14 * b; ++k) {
      const double m = std::sqrt(a * b);
      ((c(m) < 0) == (c(a) < 0) ? a : b) = m;
    }
    return std::sqrt(a * b);
  };
  InertialRange r;
  constexpr int n = 400;
  constexpr double lo = 1e-10, hi = 1e4;
  double prev = lo;
  bool inside = c(lo) < 0, found = false;
  for (int k = 1; k <= n; ++k) {
    const double I = lo * std::pow(hi / lo, double(k) / n);
    const bool now = c(I) < 0;
    if (now && !inside && !found) { r.low = bisect(prev, I); found = true; }
    if (!now && inside && found) r.high = bisect(prev, I);
    inside = now;
    prev = I;
  }
  if (!found || !(r.high > r.low)) return {};
  return r;
}

void NewtonianViscosity::evaluate(const RheologyInputs& in, RheologyOutputs& out) const {
  for (std::size_t q = 0; q < in.size(); ++q) {
    out.viscosity[q] = eta_;
    out.deta_dstrain_sq[q] = 0;
    out.deta_dpressure[q] = 0;
    out.friction[q] = 0;
    out.inertial_number[q] = 0;
  }
}

MuIRheology::MuIRheology(const RheologyParams& params) : p_(params) {
  if (p_.regularisation == Regularisation::barker_gray) {
    bg_IN_ = p_.barker_gray_IN;
    if (bg_IN_ <= 0) {
      const InertialRange w = well_posed_range(p_);
      bg_IN_ = w.empty() ? 1e-3 : std::min(1.5 * w.low, std::sqrt(w.low * w.high));
    }
    // C1 continuity at I_N of sqrt(alpha / ln(A / I)):
    //   alpha = mu_N^3 / (2 I_N mu'_N),  A = I_N exp(alpha / mu_N^2).
    const double IN = bg_IN_;
    const double muN = mu_jop(p_, IN), dmuN = dmu_jop(p_, IN);
    bg_alpha_ = muN * muN * muN / (2 * IN * dmuN);
    bg_A_ = IN * std::exp(bg_alpha_ / (muN * muN));
  }
}

double MuIRheology::friction(double I) const {
  if (!std::isfinite(I)) return p_.mu_2;
  if (p_.regularisation == Regularisation::barker_gray && I < bg_IN_) {
    if (I <= 0) return 0;
    return std::sqrt(bg_alpha_ / std::log(bg_A_ / I));
  }
  return mu_jop(p_, I);
}

double MuIRheology::dfriction_dI(double I) const {
  if (!std::isfinite(I)) return 0;
  if (p_.regularisation == Regularisation::barker_gray && I < bg_IN_) {
    if (I <= 0) return 0;
    const double mu = friction(I);
    return mu * mu * mu / (2 * bg_alpha_ * I);  // d/dI sqrt(alpha / ln(A/I))
  }
  return dmu_jop(p_, I);
}

double MuIRheology::inertial_number_for_friction(double mu) const {
  return p_.I0 * (mu - p_.mu_s) / (p_.mu_2 - mu);
}

double MuIRheology::well_posedness(double I) const {
  const double mu = friction(I);
  if (!(mu > 0)) return 0;  // I = 0 on the Barker-Gray branch: the marginal limit
  return barker_criterion(mu, I * dfriction_dI(I) / mu);
}

void cap_viscosity(const RheologyParams& params, double& eta, double& deta_ds,
                   double& deta_dp) {
  if (eta > 20 * params.eta_max) {
    eta = params.eta_max;
    deta_ds = 0;
    deta_dp = 0;
  } else {
    const double th = std::tanh(eta / params.eta_max), dcap = 1 - th * th;
    eta = params.eta_max * th;
    deta_ds *= dcap;
    deta_dp *= dcap;
  }
  if (eta < params.eta_min) {
    eta = params.eta_min;
    deta_ds = 0;
    deta_dp = 0;
  }
}

void MuIRheology::evaluate(const RheologyInputs& in, RheologyOutputs& out) const {
  const double d = p_.grain_diameter, rho_s = p_.solid_density, delta2 = p_.delta * p_.delta;
  for (std::size_t q = 0; q < in.size(); ++q) {
    const double s = std::max(in.strain_rate_sq[q], 0.0);  // |D|^2
    // gd = sqrt(|D|^2 + delta^2) (|D| when delta = 0, floored) is used both in I and in the
    // denominator of eta, with either friction law.
    const double gd = std::max(std::sqrt(s + delta2), kStrainFloor);
    // pressure clamped in the rheology only: max(p, 0), or its smooth version
    // (p + sqrt(p^2 + p_eps^2)) / 2 when pressure_smoothing = p_eps > 0
    const double p = in.pressure[q];
    double pe = std::max(p, 0.0), dpe_dp = p > 0 ? 1.0 : 0.0;
    if (p_.pressure_smoothing > 0) {
      const double root = std::sqrt(p * p + p_.pressure_smoothing * p_.pressure_smoothing);
      pe = 0.5 * (p + root);
      dpe_dp = 0.5 * (1 + p / root);
    }
    // I = 2 gd d / sqrt(p / rho_s); dI/ds = I / (2 gd^2); dI/dp = -I / (2 p)
    const double I = pe > 0 ? 2 * gd * d * std::sqrt(rho_s / pe)
                            : std::numeric_limits<double>::infinity();
    const double mu = friction(I), dmu = dfriction_dI(I);
    double eta = mu * pe / (2 * gd);
    double deta_ds = 0, deta_dp = 0, dI_ds = 0, dI_dp = 0;
    if (pe > 0) {
      dI_ds = d * std::sqrt(rho_s / pe) / gd;  // = I / (2 gd^2)
      dI_dp = -0.5 * I / pe * dpe_dp;
      deta_ds = pe / (2 * gd) * dmu * dI_ds - mu * pe / (4 * gd * gd * gd);
      deta_dp = (mu - 0.5 * I * dmu) / (2 * gd) * dpe_dp;
    }
    cap_viscosity(p_, eta, deta_ds, deta_dp);
    out.viscosity[q] = eta;
    out.deta_dstrain_sq[q] = deta_ds;
    out.deta_dpressure[q] = deta_dp;
    out.friction[q] = mu;
    out.inertial_number[q] = std::isfinite(I) ? I : std::numeric_limits<double>::max();
    out.dI_dstrain_sq[q] = s + delta2 > kStrainFloor * kStrainFloor ? dI_ds : 0.0;
    out.dI_dpressure[q] = dI_dp;
  }
}

}  // namespace grainlift::continuum
