// Compiled with -ffp-contract=off (dem/CMakeLists.txt): every lane must give the bits of
// contact_force().
#include "grainlift/dem/contact_law_batch.h"

#include <cstdlib>

#include "step_kernels.h"

#if defined(__x86_64__) && defined(__GNUC__)
// GCC 12 warns inside its own AVX-512 headers (the undefined source of unmasked intrinsics)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <immintrin.h>
#define GRAINLIFT_AVX512 1
#endif

namespace grainlift::dem {

namespace {

void scalar_lanes(const LawCoefficients& c, double mu, ContactBatch& b, std::size_t lo,
                  std::size_t n) {
  for (std::size_t l = lo; l < n; ++l) {
    ContactKinematics k;
    k.nx = b.nx[l];
    k.ny = b.ny[l];
    k.delta = b.delta[l];
    k.r_eff = b.r_eff[l];
    k.m_eff = b.m_eff[l];
    k.vn = b.vn[l];
    k.vtx = b.vtx[l];
    k.vty = b.vty[l];
    k.dsx = b.dsx[l];
    k.dsy = b.dsy[l];
    k.mu = mu;
    ContactForce f;
    contact_force(c, k, b.sx[l], b.sy[l], f);
    b.fx[l] = f.fx;
    b.fy[l] = f.fy;
    b.ftx[l] = f.ftx;
    b.fty[l] = f.fty;
  }
}

#ifdef GRAINLIFT_AVX512
// -a: a sign flip, as unary minus
__attribute__((target("avx512f"), always_inline)) inline __m512d neg(__m512d a) {
  const __m512i sign = _mm512_set1_epi64(static_cast<long long>(0x8000000000000000ULL));
  return _mm512_castsi512_pd(_mm512_xor_si512(_mm512_castpd_si512(a), sign));
}

// Kumar's law, contact_force() line by line; each `if` is a lane mask.
__attribute__((target("avx512f"))) void kumar_avx512(const LawCoefficients& c, double mu,
                                                     ContactBatch& b, std::size_t n) {
  const __m512d zero = _mm512_setzero_pd();
  const __m512d kn = _mm512_set1_pd(c.kn), kt = _mm512_set1_pd(c.kt);
  const __m512d gn = _mm512_set1_pd(c.gamma_n), gt = _mm512_set1_pd(c.gamma_t);
  const __m512d vmu = _mm512_set1_pd(mu);
  for (std::size_t l = 0; l < n; l += 8) {
    const __m512d nx = _mm512_load_pd(b.nx + l), ny = _mm512_load_pd(b.ny + l);
    __m512d sx = _mm512_load_pd(b.sx + l), sy = _mm512_load_pd(b.sy + l);
    // rotate the spring into the plane normal to n, keeping its length
    const __m512d s_old2 = _mm512_add_pd(_mm512_mul_pd(sx, sx), _mm512_mul_pd(sy, sy));
    const __m512d sdotn = _mm512_add_pd(_mm512_mul_pd(sx, nx), _mm512_mul_pd(sy, ny));
    sx = _mm512_sub_pd(sx, _mm512_mul_pd(sdotn, nx));
    sy = _mm512_sub_pd(sy, _mm512_mul_pd(sdotn, ny));
    const __m512d s_new2 = _mm512_add_pd(_mm512_mul_pd(sx, sx), _mm512_mul_pd(sy, sy));
    const __mmask8 rot = _mm512_cmp_pd_mask(s_new2, zero, _CMP_GT_OQ);
    if (rot) {
      const __m512d scale =
          _mm512_mask_sqrt_pd(zero, rot, _mm512_mask_div_pd(zero, rot, s_old2, s_new2));
      sx = _mm512_mask_mul_pd(sx, rot, sx, scale);
      sy = _mm512_mask_mul_pd(sy, rot, sy, scale);
    }
    // add this step's tangential displacement (projected on the plane)
    const __m512d dsx = _mm512_load_pd(b.dsx + l), dsy = _mm512_load_pd(b.dsy + l);
    const __m512d dsn = _mm512_add_pd(_mm512_mul_pd(dsx, nx), _mm512_mul_pd(dsy, ny));
    sx = _mm512_add_pd(sx, _mm512_sub_pd(dsx, _mm512_mul_pd(dsn, nx)));
    sy = _mm512_add_pd(sy, _mm512_sub_pd(dsy, _mm512_mul_pd(dsn, ny)));
    const __m512d delta = _mm512_load_pd(b.delta + l), m_eff = _mm512_load_pd(b.m_eff + l);
    const __m512d root = _mm512_sqrt_pd(_mm512_mul_pd(_mm512_load_pd(b.r_eff + l), delta));
    const __m512d an = _mm512_mul_pd(kn, root);
    const __m512d bn = _mm512_mul_pd(_mm512_mul_pd(m_eff, gn), root);
    const __m512d at = _mm512_mul_pd(kt, root);
    const __m512d bt = _mm512_mul_pd(_mm512_mul_pd(m_eff, gt), root);
    const __m512d vtx = _mm512_load_pd(b.vtx + l), vty = _mm512_load_pd(b.vty + l);
    const __m512d fn =
        _mm512_sub_pd(_mm512_mul_pd(an, delta), _mm512_mul_pd(bn, _mm512_load_pd(b.vn + l)));
    __m512d ftx = neg(_mm512_add_pd(_mm512_mul_pd(at, sx), _mm512_mul_pd(bt, vtx)));
    __m512d fty = neg(_mm512_add_pd(_mm512_mul_pd(at, sy), _mm512_mul_pd(bt, vty)));
    const __m512d ft2 = _mm512_add_pd(_mm512_mul_pd(ftx, ftx), _mm512_mul_pd(fty, fty));
    const __m512d fmax = _mm512_mul_pd(vmu, _mm512_abs_pd(fn));
    const __mmask8 slip = _mm512_cmp_pd_mask(ft2, _mm512_mul_pd(fmax, fmax), _CMP_GT_OQ);
    if (slip) {
      const __m512d ft = _mm512_mask_sqrt_pd(zero, slip, ft2);
      const __m512d scale = _mm512_mask_div_pd(zero, slip, fmax, ft);
      ftx = _mm512_mask_mul_pd(ftx, slip, ftx, scale);
      fty = _mm512_mask_mul_pd(fty, slip, fty, scale);
      // truncate the spring: A_t s = -(F_t + B_t v_t), or s = 0 without a spring
      const __mmask8 spring = slip & _mm512_cmp_pd_mask(at, zero, _CMP_GT_OQ);
      const __mmask8 none = slip & static_cast<__mmask8>(~spring);
      sx = _mm512_mask_div_pd(sx, spring, neg(_mm512_add_pd(ftx, _mm512_mul_pd(bt, vtx))), at);
      sy = _mm512_mask_div_pd(sy, spring, neg(_mm512_add_pd(fty, _mm512_mul_pd(bt, vty))), at);
      sx = _mm512_mask_mov_pd(sx, none, zero);
      sy = _mm512_mask_mov_pd(sy, none, zero);
    }
    _mm512_store_pd(b.sx + l, sx);
    _mm512_store_pd(b.sy + l, sy);
    _mm512_store_pd(b.ftx + l, ftx);
    _mm512_store_pd(b.fty + l, fty);
    _mm512_store_pd(b.fx + l, _mm512_add_pd(_mm512_mul_pd(fn, nx), ftx));
    _mm512_store_pd(b.fy + l, _mm512_add_pd(_mm512_mul_pd(fn, ny), fty));
  }
}
#endif

}  // namespace

bool contact_force_batch_vectorized(const LawCoefficients& c) {
  return c.law == ContactLaw::kumar2019 && detail::avx512_enabled();
}

void contact_force_batch(const LawCoefficients& c, double mu, ContactBatch& b, std::size_t n) {
#ifdef GRAINLIFT_AVX512
  if (contact_force_batch_vectorized(c)) {
    kumar_avx512(c, mu, b, n);
    return;
  }
#endif
  scalar_lanes(c, mu, b, 0, n);
}

}  // namespace grainlift::dem
