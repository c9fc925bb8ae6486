// One contact law, written once and used for grain-grain, grain-wall and grain-intruder
// contacts. A pure kernel: no allocation, no I/O. Material parameters (LawCoefficients)
// live apart from the per-contact history (the tangential spring s), which the caller owns.
#pragma once

#include <cmath>

#include "grainlift/dem/dem_config.h"

namespace grainlift::dem {

/// Coefficients of the contact law derived once from ContactParams.
struct LawCoefficients {
  ContactLaw law = ContactLaw::kumar2019;
  // Kumar 2019 Table I
  double kn = 0, kt = 0;            ///< Pa
  double gamma_n = 0, gamma_t = 0;  ///< 1/(m s)
  // Guillard 2014 Table I, written for any R_eff and m_eff:
  //   kn* = (2/3) E/(1-nu^2) sqrt(R_eff), kt* = 3(1-nu)/(2-nu) kn*,
  //   gamma_n/delta^(1/4) = sqrt(5) |beta| sqrt(kn* m_eff), gamma_t/delta^(1/4) = sqrt(10/3) |beta| sqrt(kt* m_eff),
  //   beta = ln(e)/sqrt(ln^2(e) + pi^2).
  double hertz_kn_factor = 0;  ///< Pa, (2/3) E/(1-nu^2)
  double hertz_kt_ratio = 0;   ///< -, 3(1-nu)/(2-nu)
  double hertz_beta = 0;       ///< -, |beta|

  /// @brief Derive the coefficients of the chosen law. Throws ConfigError on bad values.
  static LawCoefficients from(const ContactParams& p);
};

/// Kinematics of one contact, filled by the caller. "i" is the body the force acts on,
/// "j" its partner; n points from j to i.
struct ContactKinematics {
  double nx = 0, ny = 0;  ///< unit normal from j to i
  double delta = 0;       ///< m, overlap r_i + r_j - |x_i - x_j| (> 0)
  double r_eff = 0;       ///< m, r_i r_j / (r_i + r_j) = d_i d_j / (2 (d_i + d_j))
  double m_eff = 0;       ///< kg, m_i m_j / (m_i + m_j); m_i for a frozen or prescribed partner
  double vn = 0;          ///< m/s, (v_i - v_j).n at the contact point, time t+dt (negative approaching)
  double vtx = 0, vty = 0;  ///< m/s, tangential relative velocity at the contact point, time t+dt
  double dsx = 0, dsy = 0;  ///< m, tangential relative displacement of the contact point from t to t+dt
  double mu = 0;          ///< Coulomb coefficient of this pair
};

/// Result of one contact evaluation (force on i; the force on j is its opposite).
struct ContactForce {
  double fx = 0, fy = 0;  ///< N (per unit length in the 2D reading), total force on i
  double fn = 0;          ///< N, normal force on i along n (positive repulsive)
  double ftx = 0, fty = 0;  ///< N, tangential force on i
  bool slipping = false;  ///< Coulomb limit reached: |F_t| = mu |F_n|
};

/// @brief Evaluate the contact force and advance the tangential spring (sx, sy) in place.
///
/// Kumar 2019 eq. (1)-(2):
///   F_n = sqrt(R_eff delta) (Kn delta n - m_eff gamma_n v_n),
///   F_t = -sqrt(R_eff delta) (Kt s + m_eff gamma_t v_t),  |F_t| <= mu |F_n|.
/// Guillard 2014 eq. (A1) with Table I: F_n = kn* delta^(3/2) - gn delta^(1/4) v_n,
///   F_t = -(kt* delta^(1/2) s + gt delta^(1/4) v_t).
/// Both are written as F_n = A_n delta - B_n v_n, F_t = -(A_t s + B_t v_t).
/// The spring s is first rotated into the current contact plane (its magnitude kept),
/// then incremented by the tangential displacement of the step, and truncated on slip
/// so that A_t s = -(F_t + B_t v_t) with |F_t| = mu |F_n|.
inline void contact_force(const LawCoefficients& c, const ContactKinematics& k, double& sx,
                          double& sy, ContactForce& out) {
  // Rotate the spring into the plane normal to n, keeping its length.
  const double s_old2 = sx * sx + sy * sy;
  const double sdotn = sx * k.nx + sy * k.ny;
  sx -= sdotn * k.nx;
  sy -= sdotn * k.ny;
  const double s_new2 = sx * sx + sy * sy;
  if (s_new2 > 0) {
    const double scale = std::sqrt(s_old2 / s_new2);
    sx *= scale;
    sy *= scale;
  }
  // Add this step's tangential displacement (projected on the plane).
  const double dsn = k.dsx * k.nx + k.dsy * k.ny;
  sx += k.dsx - dsn * k.nx;
  sy += k.dsy - dsn * k.ny;

  double an, bn, at, bt;
  if (c.law == ContactLaw::kumar2019) {
    const double root = std::sqrt(k.r_eff * k.delta);  // Kumar eq. (1)-(2) prefactor
    an = c.kn * root;
    bn = k.m_eff * c.gamma_n * root;
    at = c.kt * root;
    bt = k.m_eff * c.gamma_t * root;
  } else {
    const double sd = std::sqrt(k.delta);
    const double qd = std::sqrt(sd);  // delta^(1/4)
    const double kns = c.hertz_kn_factor * std::sqrt(k.r_eff);
    const double kts = c.hertz_kt_ratio * kns;
    an = kns * sd;
    at = kts * sd;
    bn = std::sqrt(5.0) * c.hertz_beta * std::sqrt(kns * k.m_eff) * qd;
    bt = std::sqrt(10.0 / 3.0) * c.hertz_beta * std::sqrt(kts * k.m_eff) * qd;
  }

  const double fn = an * k.delta - bn * k.vn;
  double ftx = -(at * sx + bt * k.vtx);
  double fty = -(at * sy + bt * k.vty);
  const double ft2 = ftx * ftx + fty * fty;
  const double fmax = k.mu * std::fabs(fn);
  bool slipping = false;
  if (ft2 > fmax * fmax) {
    slipping = true;
    const double ft = std::sqrt(ft2);
    const double scale = fmax / ft;
    ftx *= scale;
    fty *= scale;
    // Truncate the spring so that it alone (with the damping) gives the Coulomb force.
    if (at > 0) {
      sx = -(ftx + bt * k.vtx) / at;
      sy = -(fty + bt * k.vty) / at;
    } else {
      sx = sy = 0;
    }
  }
  out.fn = fn;
  out.ftx = ftx;
  out.fty = fty;
  out.fx = fn * k.nx + ftx;
  out.fy = fn * k.ny + fty;
  out.slipping = slipping;
}

/// @brief Elastic binary collision time of two disks under the chosen law's Hertz spring.
///
/// With F = k delta^(3/2) (Kumar: k = Kn sqrt(R_eff); Guillard: k = kn*), energy conservation
/// gives delta_max = (5 m_eff v^2 / (4 k))^(2/5) and
///   t_c = 2 (delta_max / v) * integral_0^1 dx / sqrt(1 - x^(5/2)) = 2.94328 delta_max / v,
/// the integral being (2/5) B(2/5, 1/2) = 1.47164.
/// @param r1, r2 radii (m); @param m1, m2 masses (kg); @param v impact speed (m/s, > 0)
double hertz_collision_time(const LawCoefficients& c, double r1, double r2, double m1, double m2,
                            double v);

}  // namespace grainlift::dem
