// The contact law for any lane type T, written once. No include guard and no namespace of its
// own, on purpose: contact_law.h includes it inside grainlift::dem (T a double, for
// contact_force()), and contact_law_batch.cc includes it again inside each SIMD target's
// namespace (T a vector of independent contacts), so that every copy is compiled for the
// instruction set of the lanes it runs on (a template defined outside a target's code could not
// inline that target's vector operations). T provides +, -, *, / and unary minus, T(double),
// and sqrt_of, abs_of, greater, both, any, select found by argument-dependent lookup (for a
// double: namespace lane in contact_law.h). Include it only after LawCoefficients and lane.

/// Kumar 2019 eq. (1)-(2) prefactors: A_n = Kn r, B_n = m_eff gamma_n r, A_t = Kt r,
/// B_t = m_eff gamma_t r with r = sqrt(R_eff delta).
template <class T>
inline void kumar_prefactors(const LawCoefficients& c, const T& r_eff, const T& delta,
                             const T& m_eff, T& an, T& bn, T& at, T& bt) {
  using lane::sqrt_of;
  const T root = sqrt_of(r_eff * delta);
  an = T(c.kn) * root;
  bn = m_eff * T(c.gamma_n) * root;
  at = T(c.kt) * root;
  bt = m_eff * T(c.gamma_t) * root;
}

/// Guillard 2014 eq. (A1) with Table I prefactors: kn* = (2/3) E/(1-nu^2) sqrt(R_eff),
/// kt* = 3(1-nu)/(2-nu) kn*; A_n = kn* sqrt(delta), A_t = kt* sqrt(delta),
/// B_n = sqrt(5) |beta| sqrt(kn* m_eff) delta^(1/4), B_t = sqrt(10/3) |beta| sqrt(kt* m_eff)
/// delta^(1/4).
template <class T>
inline void guillard_prefactors(const LawCoefficients& c, const T& r_eff, const T& delta,
                                const T& m_eff, T& an, T& bn, T& at, T& bt) {
  using lane::sqrt_of;
  const T sd = sqrt_of(delta);
  const T qd = sqrt_of(sd);  // delta^(1/4)
  const T kns = T(c.hertz_kn_factor) * sqrt_of(r_eff);
  const T kts = T(c.hertz_kt_ratio) * kns;
  an = kns * sd;
  at = kts * sd;
  bn = T(std::sqrt(5.0) * c.hertz_beta) * sqrt_of(kns * m_eff) * qd;
  bt = T(std::sqrt(10.0 / 3.0) * c.hertz_beta) * sqrt_of(kts * m_eff) * qd;
}

/// The prefactors A_n, B_n, A_t, B_t of the law @p c names, for any lane type. The names in
/// parentheses: this copy's functions, not the double's that LawCoefficients would bring in.
template <class T>
inline void prefactors_of_law(const LawCoefficients& c, const T& r_eff, const T& delta,
                              const T& m_eff, T& an, T& bn, T& at, T& bt) {
  if (c.law == ContactLaw::kumar2019)
    (kumar_prefactors)(c, r_eff, delta, m_eff, an, bn, at, bt);
  else
    (guillard_prefactors)(c, r_eff, delta, m_eff, an, bn, at, bt);
}

/// The law once, for any lane type T (a double, or a vector of independent contacts whose
/// `if`s become lane masks): the spring (sx, sy) rotated into the contact plane and advanced,
/// F_n = A_n delta - B_n v_n, F_t = -(A_t s + B_t v_t) limited to mu |F_n| with the spring
/// truncated on slip. Every lane sees the same IEEE operations in the same order, so a vector
/// lane gives the bits of the double.
template <class T, class Mask>
inline void contact_lanes(const T& nx, const T& ny, const T& delta, const T& vn, const T& vtx,
                          const T& vty, const T& dsx, const T& dsy, const T& an, const T& bn,
                          const T& at, const T& bt, const T& mu, T& sx, T& sy, T& fn, T& ftx,
                          T& fty, Mask& slipping) {
  using lane::abs_of;
  using lane::any;
  using lane::both;
  using lane::greater;
  using lane::select;
  using lane::sqrt_of;
  const T zero(0.0);
  // Rotate the spring into the plane normal to n, keeping its length.
  const T s_old2 = sx * sx + sy * sy;
  const T sdotn = sx * nx + sy * ny;
  sx = sx - sdotn * nx;
  sy = sy - sdotn * ny;
  const T s_new2 = sx * sx + sy * sy;
  const Mask rotate = greater(s_new2, zero);
  if (any(rotate)) {
    const T scale = sqrt_of(s_old2 / s_new2);
    sx = select(rotate, sx * scale, sx);
    sy = select(rotate, sy * scale, sy);
  }
  // Add this step's tangential displacement (projected on the plane).
  const T dsn = dsx * nx + dsy * ny;
  sx = sx + (dsx - dsn * nx);
  sy = sy + (dsy - dsn * ny);

  fn = an * delta - bn * vn;
  ftx = -(at * sx + bt * vtx);
  fty = -(at * sy + bt * vty);
  const T ft2 = ftx * ftx + fty * fty;
  const T fmax = mu * abs_of(fn);
  slipping = greater(ft2, fmax * fmax);
  if (any(slipping)) {
    const T scale = fmax / sqrt_of(ft2);
    ftx = select(slipping, ftx * scale, ftx);
    fty = select(slipping, fty * scale, fty);
    // Truncate the spring so that it alone (with the damping) gives the Coulomb force;
    // without a spring (A_t = 0) it is reset.
    const Mask spring = both(slipping, greater(at, zero));
    sx = select(spring, -(ftx + bt * vtx) / at, select(slipping, zero, sx));
    sy = select(spring, -(fty + bt * vty) / at, select(slipping, zero, sy));
  }
}

/// The unit normal (nx, ny) from j to i and the overlap of a pair whose centres are (dx, dy)
/// apart (the minimum image) with radii summing to @p rs, for any lane type T.
template <class T>
inline void pair_normal(const T& dx, const T& dy, const T& rs, T& nx, T& ny, T& delta) {
  using lane::sqrt_of;
  const T dist = sqrt_of(dx * dx + dy * dy);
  const T inv_dist = T(1.0) / dist;
  nx = dx * inv_dist;
  ny = dy * inv_dist;
  delta = rs - dist;
}

/// n x F_t = nx fty - ny ftx of a contact with unit normal (nx, ny) and tangential force
/// (ftx, fty), for any lane type T: the torque of F_t on a body of radius r is -r (n x F_t).
template <class T>
inline T normal_cross_tangential(const T& nx, const T& ny, const T& ftx, const T& fty) {
  return nx * fty - ny * ftx;
}

/// contact_point_motion() (contact_law.h) for any lane type T: @p Body holds T members vx, vy,
/// w; @p p* are the predicted velocities at t + dt, @p h* the half-step ones.
template <class T, class Body>
inline void point_motion(const T& nx, const T& ny, const T& ri, const T& rj, const Body& pi,
                         const Body& pj, const Body& hi, const Body& hj, const T& dt, T& vn,
                         T& vtx, T& vty, T& dsx, T& dsy) {
  const T tx = -ny, ty = nx;
  const T wp = pi.w * ri + pj.w * rj;
  const T vrx = pi.vx - pj.vx - wp * tx;
  const T vry = pi.vy - pj.vy - wp * ty;
  vn = vrx * nx + vry * ny;
  vtx = vrx - vn * nx;
  vty = vry - vn * ny;
  const T wh = hi.w * ri + hj.w * rj;
  dsx = dt * (hi.vx - hj.vx - wh * tx);
  dsy = dt * (hi.vy - hj.vy - wh * ty);
}
