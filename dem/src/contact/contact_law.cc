// Coefficients of the contact laws and the binary collision time used for the dt check.
#include "grainlift/dem/contact/contact_law.h"

#include <cmath>
#include <sstream>

#include "grainlift/dem/errors.h"

namespace grainlift::dem {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

LawCoefficients LawCoefficients::from(const ContactParams& p) {
  LawCoefficients c;
  c.law = p.law;
  auto fail = [](const std::string& what) { throw ConfigError(what); };
  if (!(p.friction >= 0) || !(p.intruder_friction >= 0)) {
    std::ostringstream m;
    m << "contact friction = " << p.friction << ", intruder_friction = " << p.intruder_friction
      << ": Coulomb coefficients must be >= 0";
    fail(m.str());
  }
  if (p.law == ContactLaw::kumar2019) {
    if (!(p.kn > 0) || !(p.kt >= 0) || !(p.gamma_n >= 0) || !(p.gamma_t >= 0)) {
      std::ostringstream m;
      m << "kumar2019 contact: kn = " << p.kn << " Pa, kt = " << p.kt << " Pa, gamma_n = "
        << p.gamma_n << ", gamma_t = " << p.gamma_t << "; need kn > 0, kt >= 0, gammas >= 0";
      fail(m.str());
    }
    c.kn = p.kn;
    c.kt = p.kt;
    c.gamma_n = p.gamma_n;
    c.gamma_t = p.gamma_t;
  } else {
    const double e = p.restitution, nu = p.poisson_ratio;
    if (!(p.youngs_modulus > 0) || !(nu > -1 && nu < 0.5 + 1e-12) || !(e > 0 && e <= 1)) {
      std::ostringstream m;
      m << "guillard2014 contact: E = " << p.youngs_modulus << " Pa, nu = " << nu
        << ", e = " << e << "; need E > 0, -1 < nu <= 0.5, 0 < e <= 1";
      fail(m.str());
    }
    c.hertz_kn_factor = 2.0 / 3.0 * p.youngs_modulus / (1.0 - nu * nu);
    c.hertz_kt_ratio = 3.0 * (1.0 - nu) / (2.0 - nu);
    const double le = std::log(e);
    c.hertz_beta = std::fabs(le) / std::sqrt(le * le + kPi * kPi);
  }
  return c;
}

double hertz_collision_time(const LawCoefficients& c, double r1, double r2, double m1, double m2,
                            double v) {
  const double r_eff = r1 * r2 / (r1 + r2);
  const double m_eff = m1 * m2 / (m1 + m2);
  const double k = c.hertz_stiffness(r_eff);
  const double delta_max = std::pow(5.0 * m_eff * v * v / (4.0 * k), 0.4);
  // (2/5) B(2/5, 1/2) = (2/5) Gamma(2/5) Gamma(1/2) / Gamma(9/10)
  const double integral = 0.4 * std::tgamma(0.4) * std::tgamma(0.5) / std::tgamma(0.9);
  return 2.0 * integral * delta_max / v;
}

}  // namespace grainlift::dem
