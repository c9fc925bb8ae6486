// The pair screen and the kick of the step (step_kernels.h), one source for every SIMD target.
// Google Highway compiles the code between HWY_BEFORE_NAMESPACE and HWY_AFTER_NAMESPACE once
// per target (foreach_target.h includes this file again for each, into its own namespace);
// HWY_DYNAMIC_DISPATCH calls the target simd_target.cc chose. The part under HWY_ONCE, compiled
// once, holds the scalar code (the reference) and the entry points.
// Bits: compiled with -ffp-contract=off (dem/CMakeLists.txt), no fused multiply-add; the
// vector code uses only operations that are exact or rounded once as in IEEE arithmetic (add,
// subtract, multiply, ordered compares, selects, bit operations), lane by lane in the order of
// the scalar code, so each lane gives the bits of the scalar loop.
#include "step/step_kernels.h"

#include <cmath>
#include <cstring>

#include "step/pair_screen.h"
#include "step/simd_target.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "step/step_kernels.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep (before highway.h)
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace grainlift::dem::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

#if GRAINLIFT_DOUBLE_LANES
namespace {

// At most eight lanes (AVX-512: eight, AVX2: four, NEON: two, SVE: as many as the CPU has up
// to eight): the kick takes grains in groups of eight, the flags of a group as one word.
using D = hn::CappedTag<double, 8>;
using V = hn::Vec<D>;
using DI = hn::RebindToSigned<D>;    // 64-bit integers: pair indices
using DU = hn::RebindToUnsigned<D>;  // the bits of a double

#include "step/lanes-inl.h"  // gather_at

/// v - (l where above, -l where below, +0.0 elsewhere): PeriodicBox::wrap and min_image lane
/// by lane, bit for bit (x - (-l) is x + l, and x - (+0.0) is x, -0.0 included).
template <class M>
HWY_INLINE V shift(D d, V v, M above, M below, V l, V neg_l) {
  return hn::Sub(v, hn::IfThenElse(above, l, hn::IfThenElse(below, neg_l, hn::Zero(d))));
}

/// For each mask of up to eight lanes (bit j: lane j), its set lanes in increasing order, then
/// zeros. The indices of the touching pairs are compressed with it: Highway 1.0's Compress of
/// 64-bit lanes builds its own larger table on the stack at every call under GCC, and the
/// memory form of AVX-512's compress is slow on some CPUs.
struct SetLanes {
  std::uint8_t lane[256][8];
};
constexpr SetLanes make_set_lanes() {
  SetLanes t{};
  for (int m = 0; m < 256; ++m) {
    int n = 0;
    for (int j = 0; j < 8; ++j) {
      if ((m >> j) & 1) t.lane[m][n++] = static_cast<std::uint8_t>(j);
    }
  }
  return t;
}
constexpr SetLanes kSetLanes = make_set_lanes();

/// screen_pairs() with rs2 on this target: pairs [k0, k1) a vector at a time, with the
/// operations of screen_scalar() (pair_screen.h): x and y of the partners read lane by lane
/// (gather_at), those of the owners (sorted: usually fewer distinct rows than lanes) loaded
/// once and permuted;
/// (r_i + r_j)^2 from rs2. The indices of the touching pairs are compressed into out, their
/// separations into out_dx, out_dy. The last pairs (fewer than a vector) by screen_scalar().
/// Returns the number of touching pairs.
template <bool kPx, bool kPy>
std::size_t screen_lanes(const PeriodicBox& box, const int* owner, const int* partner,
                         const double* x, const double* y, const double* rs2, int n_total,
                         std::int64_t k0, std::int64_t k1, std::int64_t* out, double* out_dx,
                         double* out_dy) {
  const D d;
  const DI di;
  const hn::Rebind<std::int32_t, D> d32;
  const hn::Rebind<std::uint32_t, D> du32;
  const hn::Rebind<std::uint8_t, D> du8;
  const int lanes = static_cast<int>(hn::Lanes(d));
  const double lxs = box.lx(), lys = box.ly();
  const V lx = hn::Set(d, lxs), nlx = hn::Set(d, -lxs);
  const V ly = hn::Set(d, lys), nly = hn::Set(d, -lys);
  const V hx = hn::Set(d, 0.5 * lxs), nhx = hn::Set(d, -(0.5 * lxs));
  const V hy = hn::Set(d, 0.5 * lys), nhy = hn::Set(d, -(0.5 * lys));
  std::size_t count = 0;
  std::int64_t k = k0;
  for (; k + lanes <= k1; k += lanes) {
    const auto vi = hn::LoadU(d32, owner + k);
    const int i0 = owner[k];
    V xi, yi;
    if (owner[k + lanes - 1] - i0 < lanes && i0 + lanes <= n_total) {
      const auto rel = hn::IndicesFromVec(d, hn::PromoteTo(di, hn::Sub(vi, hn::Set(d32, i0))));
      xi = hn::TableLookupLanes(hn::LoadU(d, x + i0), rel);
      yi = hn::TableLookupLanes(hn::LoadU(d, y + i0), rel);
    } else {
      xi = gather_at(d, x, owner + k);
      yi = gather_at(d, y, owner + k);
    }
    V dx = hn::Sub(xi, gather_at(d, x, partner + k));
    V dy = hn::Sub(yi, gather_at(d, y, partner + k));
    if (kPx) dx = shift(d, dx, hn::Gt(dx, hx), hn::Lt(dx, nhx), lx, nlx);
    if (kPy) dy = shift(d, dy, hn::Gt(dy, hy), hn::Lt(dy, nhy), ly, nly);
    const V d2 = hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy));
    const auto touch = hn::Lt(d2, hn::LoadU(d, rs2 + k));
    if (!hn::AllFalse(d, touch)) {
      // k plus the touching lanes first, then whatever: a whole vector stored (out has room
      // for it), the count advanced by the touching pairs
      std::uint8_t bits[8] = {};
      hn::StoreMaskBits(d, touch, bits);
      const auto set = hn::PromoteTo(hn::RebindToUnsigned<DI>(),
                                     hn::PromoteTo(du32, hn::LoadU(du8, kSetLanes.lane[bits[0]])));
      hn::StoreU(hn::Add(hn::Set(di, k), hn::BitCast(di, set)), di, out + count);
      const auto lanes_set = hn::IndicesFromVec(d, hn::BitCast(di, set));
      hn::StoreU(hn::TableLookupLanes(dx, lanes_set), d, out_dx + count);
      hn::StoreU(hn::TableLookupLanes(dy, lanes_set), d, out_dy + count);
      count += hn::CountTrue(d, touch);
    }
  }
  return count + screen_scalar<kPx, kPy, true>(box, owner, partner, x, y, nullptr, rs2, k, k1,
                                               out + count, out_dx + count, out_dy + count);
}

/// @p v into the lanes of @p p where @p m is set; @p old holds the bits at @p p. AVX-512 stores
/// under the mask. On AVX2 the masked store (vmaskmovpd) is microcoded and slow on AMD's cores
/// (the reference machine: the kick took 35% of the AVX2 target's production run with it), so
/// the whole vector is stored, the other lanes with their own bits: memory holds the same bits,
/// and the lanes are this thread's rows, which no other thread reads or writes during the kick
/// (step_schedule.cc). Elsewhere Highway's own masked store.
template <class M>
HWY_INLINE void store_where(D d, M m, V v, V old, double* p) {
#if HWY_TARGET == HWY_AVX2
  hn::StoreU(hn::IfThenElse(m, v, old), d, p);
#else
  (void)old;
  hn::BlendedStore(v, m, d, p);
#endif
}

/// Stores the lanes of @p v whose bits differ from @p old at @p p (with a masked store, a lane
/// that keeps its value is not written: no dirty cache line for it). On AVX2, whose store_where
/// writes the whole vector anyway, the blend of v's changed lanes with old's equal bits is v
/// itself: v is stored as it is, without the comparison.
HWY_INLINE void store_changed(D d, V v, V old, double* p) {
#if HWY_TARGET == HWY_AVX2
  (void)old;
  hn::StoreU(v, d, p);
#else
  const DU du;
  store_where(d, hn::RebindMask(d, hn::Ne(hn::BitCast(du, v), hn::BitCast(du, old))), v, old, p);
#endif
}

/// PeriodicBox::wrap and min_image's constants, for the periodic directions.
struct BoxShifts {
  double lx, ly, nlx, nly, xmax, xmin, ymax, ymin, hx, hy, nhx, nhy;
  explicit BoxShifts(const PeriodicBox& b)
      : lx(b.lx()), ly(b.ly()), nlx(-b.lx()), nly(-b.ly()), xmax(b.xmax), xmin(b.xmin),
        ymax(b.ymax), ymin(b.ymin), hx(0.5 * b.lx()), hy(0.5 * b.ly()), nhx(-(0.5 * b.lx())),
        nhy(-(0.5 * b.ly())) {}
};

/// The accelerations of the grains [r, r + lanes) from their pair-force sums (finish_impl's
/// general branch; none of them touches the intruder), stored where a bit changes; the sums
/// zeroed for the next step by whole stores (an untouched lane's are +0.0 already). Returns
/// h a in (kx, ky, kw). An untouched lane has sums +0.0 and gets exactly a0 from the same
/// expressions.
HWY_INLINE void accelerate(D d, const PlainKick& k, std::size_t r, V gx, V gy, V h, V& kx,
                           V& ky, V& kw) {
  V fx, fy;
  hn::LoadInterleaved2(d, k.sfxy + 2 * r, fx, fy);
  const V qs = hn::LoadU(d, k.sq + r);
  const V inv_m = hn::LoadU(d, k.inv_m + r);
  // tq = -r qs (the sign of r flipped, as unary minus on a double, then the product)
  const V mr = hn::Xor(hn::LoadU(d, k.r + r), hn::SignBit(d));
  const V axn = hn::Add(hn::Mul(fx, inv_m), gx);
  const V ayn = hn::Add(hn::Mul(fy, inv_m), gy);
  const V aln = hn::Mul(hn::Mul(mr, qs), hn::LoadU(d, k.inv_i + r));
  store_changed(d, axn, hn::LoadU(d, k.ax + r), k.ax + r);
  store_changed(d, ayn, hn::LoadU(d, k.ay + r), k.ay + r);
  store_changed(d, aln, hn::LoadU(d, k.al + r), k.al + r);
  hn::StoreU(hn::Zero(d), d, k.sfxy + 2 * r);
  hn::StoreU(hn::Zero(d), d, k.sfxy + 2 * r + hn::Lanes(d));
  hn::StoreU(hn::Zero(d), d, k.sq + r);
  kx = hn::Mul(h, axn);
  ky = hn::Mul(h, ayn);
  kw = hn::Mul(h, aln);
}

/// The second half kick v(t+dt) = (v + h a) damp of the grains [r, r + lanes), h a given as
/// (kx, ky, kw); with kDrift also the next step's half kick and drift, the largest squared
/// displacement since the list build kept in @p md2 lane by lane. One copy per periodicity
/// (kPx, kPy): no image code along a wall direction, where PeriodicBox changes nothing.
template <bool kDrift, bool kPx, bool kPy>
HWY_INLINE void kick_lanes(D d, const PlainKick& k, const BoxShifts& b, std::size_t r, V dt,
                           V damp, V kx, V ky, V kw, V& md2) {
  const V vx0 = hn::LoadU(d, k.vx + r), vy0 = hn::LoadU(d, k.vy + r);
  const V w0 = hn::LoadU(d, k.w + r);
  V vx = hn::Mul(hn::Add(vx0, kx), damp);
  V vy = hn::Mul(hn::Add(vy0, ky), damp);
  V w = hn::Mul(hn::Add(w0, kw), damp);
  if (kDrift) {
    vx = hn::Add(vx, kx);
    vy = hn::Add(vy, ky);
    w = hn::Add(w, kw);
    const V x0 = hn::LoadU(d, k.x + r), y0 = hn::LoadU(d, k.y + r);
    V x = hn::Add(x0, hn::Mul(dt, vx));
    V y = hn::Add(y0, hn::Mul(dt, vy));
    // wrap: subtract l when x >= max, -l when x < min
    if (kPx) {
      x = shift(d, x, hn::Ge(x, hn::Set(d, b.xmax)), hn::Lt(x, hn::Set(d, b.xmin)),
                hn::Set(d, b.lx), hn::Set(d, b.nlx));
    }
    if (kPy) {
      y = shift(d, y, hn::Ge(y, hn::Set(d, b.ymax)), hn::Lt(y, hn::Set(d, b.ymin)),
                hn::Set(d, b.ly), hn::Set(d, b.nly));
    }
    // positions too are stored only where a bit changes
    store_changed(d, x, x0, k.x + r);
    store_changed(d, y, y0, k.y + r);
    const hn::Rebind<float, D> df;
    V dx = hn::Sub(x, hn::PromoteTo(d, hn::LoadU(df, k.xb + r)));
    V dy = hn::Sub(y, hn::PromoteTo(d, hn::LoadU(df, k.yb + r)));
    // minimum image: dx > l/2 subtracts l, dx < -l/2 adds it
    if (kPx) {
      dx = shift(d, dx, hn::Gt(dx, hn::Set(d, b.hx)), hn::Lt(dx, hn::Set(d, b.nhx)),
                 hn::Set(d, b.lx), hn::Set(d, b.nlx));
    }
    if (kPy) {
      dy = shift(d, dy, hn::Gt(dy, hn::Set(d, b.hy)), hn::Lt(dy, hn::Set(d, b.nhy)),
                 hn::Set(d, b.ly), hn::Set(d, b.nly));
    }
    const V d2 = hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy));
    md2 = hn::IfThenElse(hn::Gt(d2, md2), d2, md2);  // a NaN d2 is ignored, as by the scalar test
  }
  // a grain in free flight keeps its velocity bit for bit: no store, no dirty cache line
  store_changed(d, vx, vx0, k.vx + r);
  store_changed(d, vy, vy0, k.vy + r);
  store_changed(d, w, w0, k.w + r);
}

/// kick_plain() on this target: groups of eight grains, each a vector (or several) at a time.
template <bool kDrift, bool kPx, bool kPy>
int kick_groups(const PlainKick& k, int i, int hi, double& max_d2) {
  const D d;
  const std::size_t lanes = hn::Lanes(d);
  const BoxShifts box(k.box);
  // h a0, as the scalar code computes it for each grain
  const V hax = hn::Set(d, k.h * k.ax0), hay = hn::Set(d, k.h * k.ay0);
  const V hal = hn::Set(d, k.h * k.al0);
  // the constants as locals: the compiler keeps them in registers across the stores
  const V gx = hn::Set(d, k.gx), gy = hn::Set(d, k.gy), h = hn::Set(d, k.h);
  const V dt = hn::Set(d, k.dt), damp = hn::Set(d, k.damp);
  constexpr std::uint64_t kOnes = 0x0101010101010101ULL;
  V md2 = hn::Set(d, max_d2);
  for (; i + 8 <= hi; i += 8) {
    std::uint64_t f, t;
    if (k.dormant) {
      // eight sleepers: the kick would leave every bit of them as it is (sleeping.cc)
      std::uint64_t s;
      std::memcpy(&s, k.dormant + i, 8);
      if (s == kOnes) continue;
    }
    std::memcpy(&f, k.flags + i, 8);
    std::memcpy(&t, k.touched + i, 8);
    // grains with pair forces summed in sfxy, sq, none touching the intruder
    const bool forces = (f | t) != 0;
    if (forces && (f & (kOnes * k.candidate_bit))) break;
    for (std::size_t o = 0; o < 8; o += lanes) {
      const std::size_t r = static_cast<std::size_t>(i) + o;
      V kx = hax, ky = hay, kw = hal;  // h a of each lane
      if (forces) accelerate(d, k, r, gx, gy, h, kx, ky, kw);
      kick_lanes<kDrift, kPx, kPy>(d, k, box, r, dt, damp, kx, ky, kw, md2);
    }
    if (forces) {
      // touched cleared; the flag "accelerations set" on exactly the touched grains (no grain
      // is a candidate; a sleeper is never touched and has no flag, as sleeping.cc lets no
      // grain with "accelerations set" sleep)
      const std::uint64_t nf = t * k.accel_bit, nt = 0;
      std::memcpy(k.flags + i, &nf, 8);
      std::memcpy(k.touched + i, &nt, 8);
    }
  }
  if (kDrift) max_d2 = hn::GetLane(hn::MaxOfLanes(d, md2));
  return i;
}

}  // namespace

std::size_t ScreenLanes(const PeriodicBox& box, const int* owner, const int* partner,
                        const double* x, const double* y, const double* rs2, int n_total,
                        std::int64_t k0, std::int64_t k1, std::int64_t* out, double* odx,
                        double* ody) {
  auto run = [&](auto screen) {
    return screen(box, owner, partner, x, y, rs2, n_total, k0, k1, out, odx, ody);
  };
  if (box.periodic_x) {
    return box.periodic_y ? run(screen_lanes<true, true>) : run(screen_lanes<true, false>);
  }
  return box.periodic_y ? run(screen_lanes<false, true>) : run(screen_lanes<false, false>);
}

int KickLanes(const PlainKick& k, bool drift, int i, int hi, double& max_d2) {
  if (!drift) return kick_groups<false, false, false>(k, i, hi, max_d2);  // no box code
  if (k.box.periodic_x) {
    return k.box.periodic_y ? kick_groups<true, true, true>(k, i, hi, max_d2)
                            : kick_groups<true, true, false>(k, i, hi, max_d2);
  }
  return k.box.periodic_y ? kick_groups<true, false, true>(k, i, hi, max_d2)
                          : kick_groups<true, false, false>(k, i, hi, max_d2);
}
#else
// no lanes of doubles here: the scalar code does everything (never chosen: simd_target.cc)
std::size_t ScreenLanes(const PeriodicBox& box, const int* owner, const int* partner,
                        const double* x, const double* y, const double* rs2, int,
                        std::int64_t k0, std::int64_t k1, std::int64_t* out, double* odx,
                        double* ody) {
  return screen_scalar_box<true>(box, owner, partner, x, y, nullptr, rs2, k0, k1, out, odx, ody);
}
int KickLanes(const PlainKick&, bool, int i, int, double&) { return i; }
#endif

std::int64_t KernelTarget() { return HWY_TARGET; }

}  // namespace HWY_NAMESPACE
}  // namespace grainlift::dem::detail
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace grainlift::dem::detail {

HWY_EXPORT(ScreenLanes);
HWY_EXPORT(KickLanes);
HWY_EXPORT(KernelTarget);

std::size_t screen_pairs(const PeriodicBox& box, const int* owner, const int* partner,
                         const double* x, const double* y, const double* r, const double* rs2,
                         int n_total, std::int64_t k0, std::int64_t k1, std::int64_t* out,
                         double* odx, double* ody) {
  if (rs2 != nullptr && vector_enabled()) {
    return HWY_DYNAMIC_DISPATCH(ScreenLanes)(box, owner, partner, x, y, rs2, n_total, k0, k1, out,
                                             odx, ody);
  }
  // the scalar code, (r_i + r_j)^2 from r
  return screen_scalar_box<false>(box, owner, partner, x, y, r, rs2, k0, k1, out, odx, ody);
}

int kick_plain(const PlainKick& k, bool drift, int i, int hi, double& max_d2) {
  if (!vector_enabled()) return i;
  return HWY_DYNAMIC_DISPATCH(KickLanes)(k, drift, i, hi, max_d2);
}

std::int64_t dispatched_target() { return HWY_DYNAMIC_DISPATCH(KernelTarget)(); }

}  // namespace grainlift::dem::detail
#endif  // HWY_ONCE
