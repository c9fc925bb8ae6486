// contact_force() on a batch of contacts (contact_law_batch.h), one source for every SIMD
// target: Kumar's law as contact_lanes() (contact_lanes-inl.h) instantiated for a lane type
// of the target Highway's dynamic dispatch calls (step/simd_target.h), contact_force() lane by
// lane otherwise (Guillard's law, the scalar target, and SVE, whose vectors have no size that
// a lane type could hold). Compiled with -ffp-contract=off (dem/CMakeLists.txt): every lane
// gives the bits of contact_force().
#include "grainlift/dem/contact/contact_law_batch.h"

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

}  // namespace

std::size_t KumarLanes(const LawCoefficients& c, double mu, ContactBatch& b, std::size_t n) {
  const Lanes vmu(mu);
  const std::size_t lanes = hn::Lanes(D());
  for (std::size_t l = 0; l < n; l += lanes) {
    const Lanes nx = load(b.nx + l), ny = load(b.ny + l), delta = load(b.delta + l);
    Lanes sx = load(b.sx + l), sy = load(b.sy + l);
    Lanes an, bn, at, bt, fn, ftx, fty;
    LaneMask slipping;
    // this target's copies of the law (qualified: the double's copies in grainlift::dem would
    // be found too through LawCoefficients)
    HWY_NAMESPACE::kumar_prefactors(c, load(b.r_eff + l), delta, load(b.m_eff + l), an, bn, at,
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
  }
  return n;
}

std::size_t KumarLaneCount() { return hn::Lanes(D()); }
#else
// no lane type here: contact_force() lane by lane does the batch
std::size_t KumarLanes(const LawCoefficients&, double, ContactBatch&, std::size_t) { return 0; }
std::size_t KumarLaneCount() { return 0; }
#endif

}  // namespace HWY_NAMESPACE
}  // namespace grainlift::dem
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace grainlift::dem {

HWY_EXPORT(KumarLanes);
HWY_EXPORT(KumarLaneCount);

bool contact_force_batch_vectorized(const LawCoefficients& c) {
  return c.law == ContactLaw::kumar2019 && detail::vector_enabled() &&
         HWY_DYNAMIC_DISPATCH(KumarLaneCount)() > 0;
}

void contact_force_batch(const LawCoefficients& c, double mu, ContactBatch& b, std::size_t n) {
  std::size_t done = 0;
  if (c.law == ContactLaw::kumar2019 && detail::vector_enabled())
    done = HWY_DYNAMIC_DISPATCH(KumarLanes)(c, mu, b, n);
  for (std::size_t l = done; l < n; ++l) {
    ContactForce f;
    contact_force(c, b.kinematics(l, mu), b.sx[l], b.sy[l], f);
    b.fx[l] = f.fx;
    b.fy[l] = f.fy;
    b.ftx[l] = f.ftx;
    b.fty[l] = f.fty;
  }
}

}  // namespace grainlift::dem
#endif  // HWY_ONCE
