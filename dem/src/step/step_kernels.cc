// Compiled with -ffp-contract=off (dem/CMakeLists.txt): no fused multiply-add may change a
// bit against the scalar code of dem_system.cc.
#include "step/step_kernels.h"

#include <atomic>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

#include "grainlift/dem/step/vector_kernels.h"

#if defined(__x86_64__) && defined(__GNUC__)
// GCC 12 warns inside its own AVX-512 headers (the undefined source of unmasked intrinsics)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <immintrin.h>
#define GRAINLIFT_AVX512 1
#endif

namespace grainlift::dem::detail {

namespace {
// Every k is written, the count advances only for touching pairs (a touching pair is rare
// and unpredictable). The minimum image subtracts l, -l or +0.0 (d - 0.0 is d, d - (-l) is
// d + l): the bits of PeriodicBox::min_image. One copy per periodicity (no image code along
// a wall direction).
template <bool kPx, bool kPy>
std::size_t screen(const PeriodicBox& box, const int* owner, const int* partner,
                   const double* x, const double* y, const double* r, std::int64_t k0,
                   std::int64_t k1, std::int64_t* out) {
  const double lx = box.lx(), ly = box.ly();
  const double hx = 0.5 * lx, hy = 0.5 * ly;
  std::size_t n = 0;
#pragma GCC unroll 2
  for (std::int64_t k = k0; k < k1; ++k) {
    const int i = owner[k], j = partner[k];
    double dx = x[i] - x[j], dy = y[i] - y[j];
    if (kPx) dx -= dx > hx ? lx : (dx < -hx ? -lx : 0.0);
    if (kPy) dy -= dy > hy ? ly : (dy < -hy ? -ly : 0.0);
    const double rs = r[i] + r[j];
    out[n] = k;
    n += dx * dx + dy * dy < rs * rs ? 1 : 0;
  }
  return n;
}
}  // namespace

#ifdef GRAINLIFT_AVX512
namespace {
// Eight pairs per iteration: x and y of the partners gathered; those of the owners (sorted,
// usually fewer than eight distinct rows) loaded and permuted; (r_i + r_j)^2 from rs2. The
// same operations lane by lane as screen(), and a compress-store of the touching indices.
template <bool kPx, bool kPy>
__attribute__((target("avx512f"))) std::size_t screen_avx512(
    const PeriodicBox& box, const int* owner, const int* partner, const double* x,
    const double* y, const double* rs2, int n_total, std::int64_t k0, std::int64_t k1,
    std::int64_t* out) {
  const double lxs = box.lx(), lys = box.ly();
  const __m512d lx = _mm512_set1_pd(lxs), nlx = _mm512_set1_pd(-lxs);
  const __m512d ly = _mm512_set1_pd(lys), nly = _mm512_set1_pd(-lys);
  const __m512d hx = _mm512_set1_pd(0.5 * lxs), nhx = _mm512_set1_pd(-(0.5 * lxs));
  const __m512d hy = _mm512_set1_pd(0.5 * lys), nhy = _mm512_set1_pd(-(0.5 * lys));
  const __m512d zero = _mm512_setzero_pd();
  const __m512i step = _mm512_set1_epi64(8);
  __m512i kv = _mm512_add_epi64(_mm512_set1_epi64(k0), _mm512_set_epi64(7, 6, 5, 4, 3, 2, 1, 0));
  std::size_t n = 0;
  std::int64_t k = k0;
  for (; k + 8 <= k1; k += 8) {
    const __m256i vi = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(owner + k));
    const __m256i vj = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(partner + k));
    const int i0 = owner[k];
    __m512d xi, yi;
    if (owner[k + 7] - i0 < 8 && i0 + 8 <= n_total) {
      const __m512i rel = _mm512_cvtepi32_epi64(_mm256_sub_epi32(vi, _mm256_set1_epi32(i0)));
      xi = _mm512_permutexvar_pd(rel, _mm512_loadu_pd(x + i0));
      yi = _mm512_permutexvar_pd(rel, _mm512_loadu_pd(y + i0));
    } else {
      xi = _mm512_i32gather_pd(vi, x, 8);
      yi = _mm512_i32gather_pd(vi, y, 8);
    }
    __m512d dx = _mm512_sub_pd(xi, _mm512_i32gather_pd(vj, x, 8));
    __m512d dy = _mm512_sub_pd(yi, _mm512_i32gather_pd(vj, y, 8));
    if (kPx) {
      const __m512d s = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(dx, nhx, _CMP_LT_OQ), zero, nlx);
      dx = _mm512_sub_pd(dx, _mm512_mask_blend_pd(_mm512_cmp_pd_mask(dx, hx, _CMP_GT_OQ), s, lx));
    }
    if (kPy) {
      const __m512d s = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(dy, nhy, _CMP_LT_OQ), zero, nly);
      dy = _mm512_sub_pd(dy, _mm512_mask_blend_pd(_mm512_cmp_pd_mask(dy, hy, _CMP_GT_OQ), s, ly));
    }
    const __m512d d2 = _mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy));
    const __mmask8 touch = _mm512_cmp_pd_mask(d2, _mm512_loadu_pd(rs2 + k), _CMP_LT_OQ);
    if (touch) {
      _mm512_mask_compressstoreu_epi64(out + n, touch, kv);
      n += static_cast<std::size_t>(__builtin_popcount(touch));
    }
    kv = _mm512_add_epi64(kv, step);
  }
  // the last pairs (fewer than eight) one by one, with rs2 as well
  const double hxs = 0.5 * lxs, hys = 0.5 * lys;
  for (; k < k1; ++k) {
    const int i = owner[k], j = partner[k];
    double dx = x[i] - x[j], dy = y[i] - y[j];
    if (kPx) dx -= dx > hxs ? lxs : (dx < -hxs ? -lxs : 0.0);
    if (kPy) dy -= dy > hys ? lys : (dy < -hys ? -lys : 0.0);
    out[n] = k;
    n += dx * dx + dy * dy < rs2[k] ? 1 : 0;
  }
  return n;
}
}  // namespace
#endif

std::size_t screen_pairs(const PeriodicBox& box, const int* owner, const int* partner,
                         const double* x, const double* y, const double* r, const double* rs2,
                         int n_total, std::int64_t k0, std::int64_t k1, std::int64_t* out) {
#ifdef GRAINLIFT_AVX512
  if (rs2 != nullptr && avx512_enabled()) {
    if (box.periodic_x) {
      return box.periodic_y
                 ? screen_avx512<true, true>(box, owner, partner, x, y, rs2, n_total, k0, k1, out)
                 : screen_avx512<true, false>(box, owner, partner, x, y, rs2, n_total, k0, k1, out);
    }
    return box.periodic_y
               ? screen_avx512<false, true>(box, owner, partner, x, y, rs2, n_total, k0, k1, out)
               : screen_avx512<false, false>(box, owner, partner, x, y, rs2, n_total, k0, k1, out);
  }
#else
  (void)rs2;
  (void)n_total;
#endif
  if (box.periodic_x) {
    return box.periodic_y ? screen<true, true>(box, owner, partner, x, y, r, k0, k1, out)
                          : screen<true, false>(box, owner, partner, x, y, r, k0, k1, out);
  }
  return box.periodic_y ? screen<false, true>(box, owner, partner, x, y, r, k0, k1, out)
                        : screen<false, false>(box, owner, partner, x, y, r, k0, k1, out);
}

#ifdef GRAINLIFT_AVX512
namespace {

const bool kHaveAvx512 = __builtin_cpu_supports("avx512f");

/// Stores the lanes of @p v whose bits differ from @p old at @p p (no dirty cache line for
/// the lanes that keep their value).
__attribute__((target("avx512f"))) inline void store_changed(double* p, __m512d v, __m512d old) {
  _mm512_mask_storeu_pd(
      p, _mm512_cmpneq_epi64_mask(_mm512_castpd_si512(v), _mm512_castpd_si512(old)), v);
}

/// PeriodicBox::wrap and min_image on eight lanes, bit for bit.
struct BoxLanes {
  __m512d wlx, wly, nwlx, nwly, xmax, xmin, ymax, ymin, hx, hy, nhx, nhy;
  __attribute__((target("avx512f"))) explicit BoxLanes(const PeriodicBox& b) {
    // wrap: subtract l when x >= max, -l when x < min, +0.0 otherwise
    wlx = _mm512_set1_pd(b.periodic_x ? b.lx() : 0.0);
    wly = _mm512_set1_pd(b.periodic_y ? b.ly() : 0.0);
    nwlx = _mm512_set1_pd(b.periodic_x ? -b.lx() : 0.0);
    nwly = _mm512_set1_pd(b.periodic_y ? -b.ly() : 0.0);
    xmax = _mm512_set1_pd(b.periodic_x ? b.xmax : HUGE_VAL);
    xmin = _mm512_set1_pd(b.periodic_x ? b.xmin : -HUGE_VAL);
    ymax = _mm512_set1_pd(b.periodic_y ? b.ymax : HUGE_VAL);
    ymin = _mm512_set1_pd(b.periodic_y ? b.ymin : -HUGE_VAL);
    // minimum image: dx > l/2 subtracts l, dx < -l/2 adds it
    hx = _mm512_set1_pd(b.periodic_x ? 0.5 * b.lx() : HUGE_VAL);
    hy = _mm512_set1_pd(b.periodic_y ? 0.5 * b.ly() : HUGE_VAL);
    nhx = _mm512_set1_pd(b.periodic_x ? -(0.5 * b.lx()) : -HUGE_VAL);
    nhy = _mm512_set1_pd(b.periodic_y ? -(0.5 * b.ly()) : -HUGE_VAL);
  }
  __attribute__((target("avx512f"))) void wrap(__m512d& x, __m512d& y) const {
    const __m512d zero = _mm512_setzero_pd();
    __m512d s = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(x, xmin, _CMP_LT_OQ), zero, nwlx);
    x = _mm512_sub_pd(x, _mm512_mask_blend_pd(_mm512_cmp_pd_mask(x, xmax, _CMP_GE_OQ), s, wlx));
    s = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(y, ymin, _CMP_LT_OQ), zero, nwly);
    y = _mm512_sub_pd(y, _mm512_mask_blend_pd(_mm512_cmp_pd_mask(y, ymax, _CMP_GE_OQ), s, wly));
  }
  __attribute__((target("avx512f"))) void min_image(__m512d& dx, __m512d& dy) const {
    const __m512d zero = _mm512_setzero_pd();
    __m512d s = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(dx, nhx, _CMP_LT_OQ), zero, nwlx);
    dx = _mm512_sub_pd(dx, _mm512_mask_blend_pd(_mm512_cmp_pd_mask(dx, hx, _CMP_GT_OQ), s, wlx));
    s = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(dy, nhy, _CMP_LT_OQ), zero, nwly);
    dy = _mm512_sub_pd(dy, _mm512_mask_blend_pd(_mm512_cmp_pd_mask(dy, hy, _CMP_GT_OQ), s, wly));
  }
};

template <bool kDrift>
__attribute__((target("avx512f"))) int kick_avx512(const PlainKick& k, int i, int hi,
                                                   double& max_d2) {
  const BoxLanes box(k.box);
  const __m512d zero = _mm512_setzero_pd();
  const __m512d dt = _mm512_set1_pd(k.dt), damp = _mm512_set1_pd(k.damp);
  // h a0, as the scalar code computes it for each grain
  const __m512d hax = _mm512_set1_pd(k.h * k.ax0), hay = _mm512_set1_pd(k.h * k.ay0);
  const __m512d hal = _mm512_set1_pd(k.h * k.al0);
  const __m512d h = _mm512_set1_pd(k.h);
  const __m512d gx = _mm512_set1_pd(k.gx), gy = _mm512_set1_pd(k.gy);
  const __m512i sign = _mm512_set1_epi64(static_cast<long long>(0x8000000000000000ULL));
  constexpr std::uint64_t kOnes = 0x0101010101010101ULL;
  __m512d md2 = _mm512_set1_pd(max_d2);
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
    __m512d kx = hax, ky = hay, kw = hal;  // h a of each lane
    if (f | t) {
      // Grains with pair forces summed in sfx, sfy, sq, none touching the intruder: the
      // accelerations of finish_impl's general branch. An untouched lane has sums +0.0 and
      // gets exactly a0 from the same expressions.
      if (f & (kOnes * k.candidate_bit)) break;
      if (k.shared) {
        std::uint64_t sh;
        std::memcpy(&sh, k.shared + i, 8);
        if (sh & t) break;  // a touched shared grain: its sum is gathered (finish_impl)
      }
      const __m512d fx = _mm512_loadu_pd(k.sfx + i), fy = _mm512_loadu_pd(k.sfy + i);
      const __m512d qs = _mm512_loadu_pd(k.sq + i);
      const __m512d inv_m = _mm512_loadu_pd(k.inv_m + i);
      // tq = -r qs (unary minus of r, then the product)
      const __m512d mr = _mm512_castsi512_pd(
          _mm512_xor_si512(_mm512_castpd_si512(_mm512_loadu_pd(k.r + i)), sign));
      __m512d axn = _mm512_add_pd(_mm512_mul_pd(fx, inv_m), gx);
      __m512d ayn = _mm512_add_pd(_mm512_mul_pd(fy, inv_m), gy);
      __m512d aln = _mm512_mul_pd(_mm512_mul_pd(mr, qs), _mm512_loadu_pd(k.inv_i + i));
      const __m512d ax0 = _mm512_loadu_pd(k.ax + i), ay0 = _mm512_loadu_pd(k.ay + i);
      const __m512d al0 = _mm512_loadu_pd(k.al + i);
      store_changed(k.ax + i, axn, ax0);
      store_changed(k.ay + i, ayn, ay0);
      store_changed(k.al + i, aln, al0);
      // sums of the touched lanes zeroed for the next step; touched cleared; the flag
      // "accelerations set" on exactly the touched lanes (no lane is a candidate)
      const __mmask8 touched =
          _mm512_test_epi64_mask(_mm512_cvtepu8_epi64(_mm_cvtsi64_si128(static_cast<long long>(t))),
                                 _mm512_set1_epi64(0xff));
      _mm512_mask_storeu_pd(k.sfx + i, touched, zero);
      _mm512_mask_storeu_pd(k.sfy + i, touched, zero);
      _mm512_mask_storeu_pd(k.sq + i, touched, zero);
      // (a sleeper is never touched and has no flag, as sleeping.cc lets no grain with
      // "accelerations set" sleep)
      const std::uint64_t nf = t * k.accel_bit;
      const std::uint64_t nt = 0;
      std::memcpy(k.flags + i, &nf, 8);
      std::memcpy(k.touched + i, &nt, 8);
      kx = _mm512_mul_pd(h, axn);
      ky = _mm512_mul_pd(h, ayn);
      kw = _mm512_mul_pd(h, aln);
    }
    // second half kick: v(t+dt) = (v + h a) damp
    const __m512d vx0 = _mm512_loadu_pd(k.vx + i), vy0 = _mm512_loadu_pd(k.vy + i);
    const __m512d w0 = _mm512_loadu_pd(k.w + i);
    __m512d vx = _mm512_mul_pd(_mm512_add_pd(vx0, kx), damp);
    __m512d vy = _mm512_mul_pd(_mm512_add_pd(vy0, ky), damp);
    __m512d w = _mm512_mul_pd(_mm512_add_pd(w0, kw), damp);
    if (kDrift) {
      // the next step's half kick and drift
      vx = _mm512_add_pd(vx, kx);
      vy = _mm512_add_pd(vy, ky);
      w = _mm512_add_pd(w, kw);
      const __m512d x0 = _mm512_loadu_pd(k.x + i), y0 = _mm512_loadu_pd(k.y + i);
      __m512d x = _mm512_add_pd(x0, _mm512_mul_pd(dt, vx));
      __m512d y = _mm512_add_pd(y0, _mm512_mul_pd(dt, vy));
      box.wrap(x, y);
      // positions too are stored only where a bit changes
      store_changed(k.x + i, x, x0);
      store_changed(k.y + i, y, y0);
      __m512d dx = _mm512_sub_pd(x, _mm512_cvtps_pd(_mm256_loadu_ps(k.xb + i)));
      __m512d dy = _mm512_sub_pd(y, _mm512_cvtps_pd(_mm256_loadu_ps(k.yb + i)));
      box.min_image(dx, dy);
      const __m512d d2 = _mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy));
      md2 = _mm512_max_pd(d2, md2);  // a NaN d2 is ignored, as by the scalar test
    }
    // a grain in free flight keeps its velocity bit for bit: no store, no dirty cache line
    store_changed(k.vx + i, vx, vx0);
    store_changed(k.vy + i, vy, vy0);
    store_changed(k.w + i, w, w0);
  }
  if (kDrift) max_d2 = _mm512_reduce_max_pd(md2);
  return i;
}

}  // namespace
#endif

namespace {
std::atomic<bool> g_vector_allowed{true};
}  // namespace

bool avx512_enabled() {
#ifdef GRAINLIFT_AVX512
  static const bool cpu = kHaveAvx512 && grainlift::dem::simd_setting_error().empty() &&
                          requested_simd() != "scalar";
  return cpu && g_vector_allowed.load(std::memory_order_relaxed);
#else
  return false;
#endif
}

std::string requested_simd() {
  if (std::getenv("GRAINLIFT_NO_SIMD")) return "scalar";  // the older switch
  const char* s = std::getenv("GRAINLIFT_SIMD");
  return s && *s ? std::string(s) : std::string("auto");
}

}  // namespace grainlift::dem::detail

namespace grainlift::dem {
void set_vector_kernels(bool on) { detail::g_vector_allowed.store(on, std::memory_order_relaxed); }
bool vector_kernels() { return detail::avx512_enabled(); }

std::string simd_target() { return detail::avx512_enabled() ? "avx512" : "scalar"; }

std::string simd_targets() {
#ifdef GRAINLIFT_AVX512
  return detail::kHaveAvx512 ? "scalar, avx512"
                              : "scalar (avx512 is built; this CPU lacks AVX-512F)";
#else
  return "scalar";
#endif
}

std::string simd_setting_error() {
  const std::string want = detail::requested_simd();
  if (want == "auto" || want == "scalar") return {};
#ifdef GRAINLIFT_AVX512
  if (want == "avx512" && detail::kHaveAvx512) return {};
#endif
  return "GRAINLIFT_SIMD=" + want + ": the DEM's vector targets here are " + simd_targets() +
         "; unset it (the best the CPU runs) or name one of them";
}
}  // namespace grainlift::dem

namespace grainlift::dem::detail {

int kick_plain(const PlainKick& k, bool drift, int i, int hi, double& max_d2) {
#ifdef GRAINLIFT_AVX512
  if (avx512_enabled()) {
    return drift ? kick_avx512<true>(k, i, hi, max_d2) : kick_avx512<false>(k, i, hi, max_d2);
  }
#endif
  (void)k;
  (void)drift;
  (void)hi;
  (void)max_d2;
  return i;
}

}  // namespace grainlift::dem::detail
