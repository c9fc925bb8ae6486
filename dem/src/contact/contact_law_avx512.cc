// Kumar's contact law on eight contacts per instruction: contact_lanes() (contact_law.h)
// instantiated for a lane type of eight doubles. This file alone is compiled with -mavx512f
// (and -ffp-contract=off, so every lane gives the bits of contact_force()); it is called only
// after the CPU check (contact_law_batch.cc). Everything it instantiates has internal
// linkage, so no AVX-512 copy of an inline function can replace the generic one at link time.
#include "contact/contact_law_avx512.h"

#ifdef __AVX512F__
// GCC 12 warns inside its own AVX-512 headers (the undefined source of unmasked intrinsics)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <immintrin.h>

namespace grainlift::dem {

namespace {

/// Eight contacts: the arithmetic of a double, lane by lane.
struct Lanes8 {
  __m512d v;
  Lanes8() = default;
  explicit Lanes8(double x) : v(_mm512_set1_pd(x)) {}
  explicit Lanes8(__m512d x) : v(x) {}
};
/// Which of the eight lanes a condition holds for.
struct Mask8 {
  __mmask8 m;
};

inline Lanes8 operator+(Lanes8 a, Lanes8 b) { return Lanes8(_mm512_add_pd(a.v, b.v)); }
inline Lanes8 operator-(Lanes8 a, Lanes8 b) { return Lanes8(_mm512_sub_pd(a.v, b.v)); }
inline Lanes8 operator*(Lanes8 a, Lanes8 b) { return Lanes8(_mm512_mul_pd(a.v, b.v)); }
inline Lanes8 operator/(Lanes8 a, Lanes8 b) { return Lanes8(_mm512_div_pd(a.v, b.v)); }
inline Lanes8 operator-(Lanes8 a) {  // a sign flip, as unary minus on a double
  const __m512i sign = _mm512_set1_epi64(static_cast<long long>(0x8000000000000000ULL));
  return Lanes8(_mm512_castsi512_pd(_mm512_xor_si512(_mm512_castpd_si512(a.v), sign)));
}
inline Lanes8 sqrt_of(Lanes8 a) { return Lanes8(_mm512_sqrt_pd(a.v)); }
inline Lanes8 abs_of(Lanes8 a) { return Lanes8(_mm512_abs_pd(a.v)); }
inline Mask8 greater(Lanes8 a, Lanes8 b) { return {_mm512_cmp_pd_mask(a.v, b.v, _CMP_GT_OQ)}; }
inline Mask8 both(Mask8 a, Mask8 b) { return {static_cast<__mmask8>(a.m & b.m)}; }
inline bool any(Mask8 a) { return a.m != 0; }
inline Lanes8 select(Mask8 m, Lanes8 a, Lanes8 b) {
  return Lanes8(_mm512_mask_mov_pd(b.v, m.m, a.v));
}

inline Lanes8 load(const double* p) { return Lanes8(_mm512_load_pd(p)); }
inline void store(double* p, Lanes8 a) { _mm512_store_pd(p, a.v); }

}  // namespace

void kumar_contacts_avx512(const LawCoefficients& c, double mu, ContactBatch& b, std::size_t n) {
  const Lanes8 vmu(mu);
  for (std::size_t l = 0; l < n; l += 8) {
    const Lanes8 nx = load(b.nx + l), ny = load(b.ny + l), delta = load(b.delta + l);
    Lanes8 sx = load(b.sx + l), sy = load(b.sy + l);
    Lanes8 an, bn, at, bt, fn, ftx, fty;
    Mask8 slipping;
    kumar_prefactors(c, load(b.r_eff + l), delta, load(b.m_eff + l), an, bn, at, bt);
    contact_lanes(nx, ny, delta, load(b.vn + l), load(b.vtx + l), load(b.vty + l),
                  load(b.dsx + l), load(b.dsy + l), an, bn, at, bt, vmu, sx, sy, fn, ftx, fty,
                  slipping);
    store(b.sx + l, sx);
    store(b.sy + l, sy);
    store(b.ftx + l, ftx);
    store(b.fty + l, fty);
    store(b.fx + l, fn * nx + ftx);
    store(b.fy + l, fn * ny + fty);
  }
}

}  // namespace grainlift::dem
#endif
