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
  //   gamma_n/delta^(1/4) = sqrt(5) |beta| sqrt(kn* m_eff), gamma_t/delta^(1/4) = sqrt(10/3) |beta|
  //   sqrt(kt* m_eff), beta = ln(e)/sqrt(ln^2(e) + pi^2).
  double hertz_kn_factor = 0;  ///< Pa, (2/3) E/(1-nu^2)
  double hertz_kt_ratio = 0;   ///< -, 3(1-nu)/(2-nu)
  double hertz_beta = 0;       ///< -, |beta|

  /// @brief Derive the coefficients of the chosen law. Throws ConfigError on bad values.
  static LawCoefficients from(const ContactParams& p);

  /// @brief The Hertz stiffness k of the law's normal spring, F_n = k delta^(3/2) (N/m^(3/2)),
  /// for a contact of effective radius @p r_eff (m): Kumar 2019 eq. (1), k = Kn sqrt(R_eff);
  /// Guillard 2014 Table I, k = kn* = (2/3) E/(1-nu^2) sqrt(R_eff).
  double hertz_stiffness(double r_eff) const {
    return (law == ContactLaw::kumar2019 ? kn : hertz_kn_factor) * std::sqrt(r_eff);
  }
};

/// Kinematics of one contact, filled by the caller. "i" is the body the force acts on,
/// "j" its partner; n points from j to i.
struct ContactKinematics {
  double nx = 0, ny = 0;  ///< unit normal from j to i
  double delta = 0;       ///< m, overlap r_i + r_j - |x_i - x_j| (> 0)
  double r_eff = 0;       ///< m, r_i r_j / (r_i + r_j) = d_i d_j / (2 (d_i + d_j))
  double m_eff = 0;       ///< kg, m_i m_j / (m_i + m_j); m_i for a frozen or prescribed partner
  double vn = 0;  ///< m/s, (v_i - v_j).n at the contact point, time t+dt (negative approaching)
  double vtx = 0, vty = 0;  ///< m/s, tangential relative velocity at the contact point, time t+dt
  double dsx = 0,
         dsy = 0;  ///< m, tangential relative displacement of the contact point from t to t+dt
  double mu = 0;          ///< Coulomb coefficient of this pair
};

/// Velocity (m/s) and angular velocity (rad/s, counter-clockwise) of one body of a contact
/// at one time level.
struct BodyVelocity {
  double vx = 0, vy = 0, w = 0;
};

/// The lane operations the law needs, for one contact held in doubles. A vector of contacts
/// (contact_law_batch.cc) provides the same names for its own lane type.
namespace lane {
inline double sqrt_of(double x) { return std::sqrt(x); }
inline double abs_of(double x) { return std::fabs(x); }
inline bool greater(double a, double b) { return a > b; }
inline bool both(bool a, bool b) { return a && b; }
inline bool any(bool m) { return m; }
inline double select(bool m, double a, double b) { return m ? a : b; }
}  // namespace lane

// the laws' prefactors and contact_lanes(), the law for any lane type: in this namespace for a
// double, and again in each SIMD target's namespace for its vector lanes (contact_law_batch.cc)
#include "grainlift/dem/contact/contact_lanes-inl.h"

/// @brief The motion of the contact point of bodies i and j (radii @p ri, @p rj, m; unit
/// normal (nx, ny) from j to i, tangent t = (-ny, nx)), written once for pairs, walls and the
/// intruder. From the predicted velocities at t+dt (@p pi, @p pj): the relative velocity
/// v_r = v_i - v_j - (w_i r_i + w_j r_j) t split into vn = v_r.n and v_t = v_r - vn n; from
/// the half-step velocities (@p hi, @p hj): the tangential displacement of the contact point
/// over the step, ds = dt (v_i - v_j - (w_i r_i + w_j r_j) t) (m). Fills k.vn, k.vtx, k.vty,
/// k.dsx, k.dsy.
inline void contact_point_motion(double nx, double ny, double ri, double rj,
                                 const BodyVelocity& pi, const BodyVelocity& pj,
                                 const BodyVelocity& hi, const BodyVelocity& hj, double dt,
                                 ContactKinematics& k) {
  point_motion(nx, ny, ri, rj, pi, pj, hi, hj, dt, k.vn, k.vtx, k.vty, k.dsx, k.dsy);
}

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
/// The prefactors A_n, B_n, A_t, B_t of either law for one contact.
inline void law_prefactors(const LawCoefficients& c, double r_eff, double delta, double m_eff,
                           double& an, double& bn, double& at, double& bt) {
  prefactors_of_law(c, r_eff, delta, m_eff, an, bn, at, bt);
}

/// @brief The normal force F_n = A_n delta - B_n v_n of a contact (positive repulsive): with
/// mu = 0 the whole force, F_t being capped to zero (the frictionless path of the pair loop;
/// the bits of contact_force's F_n).
inline double normal_contact_force(const LawCoefficients& c, const ContactKinematics& k) {
  double an, bn, at, bt;
  law_prefactors(c, k.r_eff, k.delta, k.m_eff, an, bn, at, bt);
  return an * k.delta - bn * k.vn;
}

inline void contact_force(const LawCoefficients& c, const ContactKinematics& k, double& sx,
                          double& sy, ContactForce& out) {
  double an, bn, at, bt;
  law_prefactors(c, k.r_eff, k.delta, k.m_eff, an, bn, at, bt);
  double fn, ftx, fty;
  bool slipping;
  contact_lanes(k.nx, k.ny, k.delta, k.vn, k.vtx, k.vty, k.dsx, k.dsy, an, bn, at, bt, k.mu, sx,
                sy, fn, ftx, fty, slipping);
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
