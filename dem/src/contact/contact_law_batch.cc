// contact_force() on a batch of contacts (contact_law_batch.h), one source for every SIMD
// target: either law as contact_lanes() (contact_lanes-inl.h) instantiated for a lane type
// of the target Highway's dynamic dispatch calls (step/simd_target.h), contact_force() lane by
// lane otherwise (the scalar target, and SVE, whose vectors have no size that a lane type
// could hold). Compiled with -ffp-contract=off (dem/CMakeLists.txt): every lane gives the bits
// of contact_force().
#include "grainlift/dem/contact/contact_law_batch.h"

#include "step/pair_inputs.h"
#include "step/simd_target.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "contact/contact_law_batch.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep (before highway.h)
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace grainlift::dem {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

#if GRAINLIFT_DOUBLE_LANES && !HWY_HAVE_SCALABLE
namespace {

using D = hn::CappedTag<double, 8>;  // up to eight contacts per instruction

// The constructors are written out, not implicit: an implicit one would be compiled without
// this target's instruction set (GCC gives this target's options to the functions written
// here), and could not inline the target's own constructors (NEON's masks have one).

/// Independent contacts, one per lane: the arithmetic of a double, lane by lane.
struct Lanes {
  hn::Vec<D> v;
  HWY_INLINE Lanes() {}
  HWY_INLINE explicit Lanes(double x) : v(hn::Set(D(), x)) {}
  HWY_INLINE explicit Lanes(hn::Vec<D> x) : v(x) {}
};
/// Which lanes a condition holds for.
struct LaneMask {
  hn::Mask<D> m;
  HWY_INLINE LaneMask() {}
  HWY_INLINE explicit LaneMask(hn::Mask<D> x) : m(x) {}
};

HWY_INLINE Lanes operator+(Lanes a, Lanes b) { return Lanes(hn::Add(a.v, b.v)); }
HWY_INLINE Lanes operator-(Lanes a, Lanes b) { return Lanes(hn::Sub(a.v, b.v)); }
HWY_INLINE Lanes operator*(Lanes a, Lanes b) { return Lanes(hn::Mul(a.v, b.v)); }
HWY_INLINE Lanes operator/(Lanes a, Lanes b) { return Lanes(hn::Div(a.v, b.v)); }
HWY_INLINE Lanes operator-(Lanes a) {  // a sign flip, as unary minus on a double
  return Lanes(hn::Xor(a.v, hn::SignBit(D())));
}
// IEEE square root (never an approximate reciprocal square root)
HWY_INLINE Lanes sqrt_of(Lanes a) { return Lanes(hn::Sqrt(a.v)); }
HWY_INLINE Lanes abs_of(Lanes a) { return Lanes(hn::Abs(a.v)); }  // the sign bit cleared
// a > b lane by lane, false for NaN
HWY_INLINE LaneMask greater(Lanes a, Lanes b) { return LaneMask(hn::Gt(a.v, b.v)); }
HWY_INLINE LaneMask both(LaneMask a, LaneMask b) { return LaneMask(hn::And(a.m, b.m)); }
HWY_INLINE bool any(LaneMask a) { return !hn::AllFalse(D(), a.m); }
HWY_INLINE Lanes select(LaneMask m, Lanes a, Lanes b) {
  return Lanes(hn::IfThenElse(m.m, a.v, b.v));
}

HWY_INLINE Lanes load(const double* p) { return Lanes(hn::Load(D(), p)); }
HWY_INLINE void store(double* p, Lanes a) { hn::Store(a.v, D(), p); }

// the law itself, compiled here for this target's lanes
#include "grainlift/dem/contact/contact_lanes-inl.h"
#include "step/lanes-inl.h"  // gather_at

/// The velocities of one side of a vector of contacts (point_motion's Body).
struct Body {
  Lanes vx, vy, w;
};

/// One side's arrays at its grains, gathered.
struct Gathered {
  const std::int32_t* g;
  HWY_INLINE Lanes at(const double* a) const { return Lanes(gather_at(D(), a, g)); }
};
/// One side's arrays at grains within one vector from the first, @p g0 (the owners of
/// consecutive pairs: few distinct rows): a contiguous load permuted.
struct Permuted {
  decltype(hn::IndicesFromVec(D(), hn::Zero(hn::RebindToSigned<D>()))) rel;
  const std::int32_t g0;
  HWY_INLINE Lanes at(const double* a) const {
    return Lanes(hn::TableLookupLanes(hn::LoadU(D(), a + g0), rel));
  }
};

/// PairInputs::of() on the pairs @p kp (owners by @p si, partners by @p sj; minimum-image
/// separations @p dx, @p dy) into lanes [l, l + lanes) of @p b, with their springs from
/// @p sxa, @p sya; their overlap fractions delta / (2 min(r_i, r_j)) raise @p max_ov lane by
/// lane (divided only where the pre-test of the scalar loop, raise_max_overlap, passes).
template <class Owner>
HWY_INLINE void pair_kinematics(const PairInputs& in, const Owner& si, const Gathered& sj,
                                const std::int64_t* kp, Lanes dx, Lanes dy,
                                const double* sxa, const double* sya, ContactBatch& b,
                                std::size_t l, hn::Vec<D>& max_ov) {
  const D d;
  const Lanes h(in.h), dt(in.dt), one(1.0);
  const Lanes ri = si.at(in.r), rj = sj.at(in.r);
  const Lanes rs = ri + rj;
  Lanes nx, ny, delta, reff, meff;
  HWY_NAMESPACE::pair_normal(dx, dy, rs, nx, ny, delta);
  if (in.pair_consts) {
    reff = Lanes(gather_at(d, in.reff, kp));
    meff = Lanes(gather_at(d, in.meff, kp));
  } else {
    reff = ri * rj / rs;
    meff = one / (si.at(in.inv_m) + sj.at(in.inv_m));
  }
  const Body hi{si.at(in.vx), si.at(in.vy), si.at(in.w)};
  const Body hj{sj.at(in.vx), sj.at(in.vy), sj.at(in.w)};
  const Body pi{hi.vx + h * si.at(in.ax), hi.vy + h * si.at(in.ay), hi.w + h * si.at(in.al)};
  const Body pj{hj.vx + h * sj.at(in.ax), hj.vy + h * sj.at(in.ay), hj.w + h * sj.at(in.al)};
  Lanes vn, vtx, vty, dsx, dsy;
  HWY_NAMESPACE::point_motion(nx, ny, ri, rj, pi, pj, hi, hj, dt, vn, vtx, vty, dsx, dsy);
  store(b.nx + l, nx);
  store(b.ny + l, ny);
  store(b.delta + l, delta);
  store(b.r_eff + l, reff);
  store(b.m_eff + l, meff);
  store(b.vn + l, vn);
  store(b.vtx + l, vtx);
  store(b.vty + l, vty);
  store(b.dsx + l, dsx);
  store(b.dsy + l, dsy);
  hn::Store(gather_at(d, sxa, kp), d, b.sx + l);
  hn::Store(gather_at(d, sya, kp), d, b.sy + l);
  const hn::Vec<D> dmin = hn::Mul(hn::Set(d, 2.0), hn::Min(ri.v, rj.v));
  const auto raise = hn::Gt(delta.v, hn::Mul(hn::Mul(max_ov, dmin), hn::Set(d, 1.0 - 1e-12)));
  if (!hn::AllFalse(d, raise)) {
    const hn::Vec<D> ov = hn::Div(delta.v, dmin);
    max_ov = hn::IfThenElse(hn::And(raise, hn::Gt(ov, max_ov)), ov, max_ov);
  }
}

}  // namespace

std::size_t LawLanes(const LawCoefficients& c, double mu, ContactBatch& b, std::size_t n);

std::size_t PairLanes(const PairInputs& in, const LawCoefficients& c, double mu,
                      const std::int64_t* kb, const double* dxa, const double* dya,
                      std::size_t nb, const double* sxa, const double* sya, ContactBatch& b,
                      double& max_ov) {
  const D d;
  hn::Vec<D> best = hn::Set(d, max_ov);
  const hn::RebindToSigned<D> di;
  const hn::Rebind<std::int32_t, D> d32;
  const int lanes = static_cast<int>(hn::Lanes(D()));
  alignas(64) std::int32_t gi[8], gj[8];
  alignas(64) std::int64_t kk[8];
  alignas(64) double sep[2][8];
  for (std::size_t l = 0; l < nb; l += static_cast<std::size_t>(lanes)) {
    Lanes dx, dy;
    const std::int64_t* kp = kb + l;
    if (l + static_cast<std::size_t>(lanes) <= nb) {
      dx = Lanes(hn::LoadU(d, dxa + l));
      dy = Lanes(hn::LoadU(d, dya + l));
      for (int a = 0; a < lanes; ++a) {
        gi[a] = in.owner[kp[a]];
        gj[a] = in.partner[kp[a]];
      }
    } else {
      for (int a = 0; a < lanes; ++a) {  // lanes past the batch repeat its last pair
        const std::size_t m = std::min(l + static_cast<std::size_t>(a), nb - 1);
        kk[a] = kb[m];
        gi[a] = in.owner[kk[a]];
        gj[a] = in.partner[kk[a]];
        sep[0][a] = dxa[m];
        sep[1][a] = dya[m];
      }
      kp = kk;
      dx = load(sep[0]);
      dy = load(sep[1]);
    }
    const auto vi = hn::Load(d32, gi);
    const Gathered sj{gj};
    // the owners increase with the pair (the list is by rows)
    if (gi[lanes - 1] - gi[0] < lanes && gi[0] + lanes <= in.n_rows) {
      const auto rel = hn::PromoteTo(di, hn::Sub(vi, hn::Set(d32, gi[0])));
      const Permuted si{hn::IndicesFromVec(D(), rel), gi[0]};
      pair_kinematics(in, si, sj, kp, dx, dy, sxa, sya, b, l, best);
    } else {
      pair_kinematics(in, Gathered{gi}, sj, kp, dx, dy, sxa, sya, b, l, best);
    }
  }
  // the law on the whole batch: the vectors' long chains of square roots and divisions
  // overlap (one vector of pairs through kinematics and law at once did not gain)
  LawLanes(c, mu, b, nb);
  max_ov = hn::GetLane(hn::MaxOfLanes(d, best));
  return nb;
}

std::size_t LawLanes(const LawCoefficients& c, double mu, ContactBatch& b, std::size_t n) {
  const Lanes vmu(mu);
  const std::size_t lanes = hn::Lanes(D());
  for (std::size_t l = 0; l < n; l += lanes) {
    const Lanes nx = load(b.nx + l), ny = load(b.ny + l), delta = load(b.delta + l);
    Lanes sx = load(b.sx + l), sy = load(b.sy + l);
    Lanes an, bn, at, bt, fn, ftx, fty;
    LaneMask slipping;
    // this target's copies of the law (qualified: the double's copies in grainlift::dem would
    // be found too through LawCoefficients)
    HWY_NAMESPACE::prefactors_of_law(c, load(b.r_eff + l), delta, load(b.m_eff + l), an, bn, at,
                                     bt);
    HWY_NAMESPACE::contact_lanes(nx, ny, delta, load(b.vn + l), load(b.vtx + l),
                                 load(b.vty + l), load(b.dsx + l), load(b.dsy + l), an, bn, at,
                                 bt, vmu, sx, sy, fn, ftx, fty, slipping);
    store(b.sx + l, sx);
    store(b.sy + l, sy);
    store(b.ftx + l, ftx);
    store(b.fty + l, fty);
    store(b.fx + l, fn * nx + ftx);
    store(b.fy + l, fn * ny + fty);
    store(b.q + l, HWY_NAMESPACE::normal_cross_tangential(nx, ny, ftx, fty));
  }
  return n;
}

std::size_t LawLaneCount() { return hn::Lanes(D()); }
#else
// no lane type here: contact_force() lane by lane does the batch
std::size_t LawLanes(const LawCoefficients&, double, ContactBatch&, std::size_t) { return 0; }
std::size_t PairLanes(const PairInputs&, const LawCoefficients&, double, const std::int64_t*,
                      const double*, const double*, std::size_t, const double*, const double*,
                      ContactBatch&, double&) {
  return 0;
}
std::size_t LawLaneCount() { return 0; }
#endif

}  // namespace HWY_NAMESPACE
}  // namespace grainlift::dem
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace grainlift::dem {

HWY_EXPORT(LawLanes);
HWY_EXPORT(LawLaneCount);
HWY_EXPORT(PairLanes);

bool contact_force_batch_vectorized(const LawCoefficients&) {
  return detail::vector_enabled() && HWY_DYNAMIC_DISPATCH(LawLaneCount)() > 0;
}

std::size_t pair_lanes(const PairInputs& in, const LawCoefficients& law, double mu,
                       const std::int64_t* kb, const double* dx, const double* dy, std::size_t nb,
                       const double* sx, const double* sy, ContactBatch& out, double& max_ov) {
  if (!detail::vector_enabled()) return 0;
  return HWY_DYNAMIC_DISPATCH(PairLanes)(in, law, mu, kb, dx, dy, nb, sx, sy, out, max_ov);
}

void contact_force_batch(const LawCoefficients& c, double mu, ContactBatch& b, std::size_t n) {
  std::size_t done = 0;
  if (detail::vector_enabled()) done = HWY_DYNAMIC_DISPATCH(LawLanes)(c, mu, b, n);
  for (std::size_t l = done; l < n; ++l) {
    ContactForce f;
    contact_force(c, b.kinematics(l, mu), b.sx[l], b.sy[l], f);
    b.fx[l] = f.fx;
    b.fy[l] = f.fy;
    b.ftx[l] = f.ftx;
    b.fty[l] = f.fty;
    b.q[l] = normal_cross_tangential(b.nx[l], b.ny[l], f.ftx, f.fty);
  }
}

}  // namespace grainlift::dem
#endif  // HWY_ONCE
