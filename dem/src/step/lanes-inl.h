// The gather the step's Highway kernels share (step_kernels.cc, contact_law_batch.cc). No
// include guard and no namespace of its own, on purpose: each of those files includes it inside
// every SIMD target's namespace (Highway compiles them once per target), after defining
// D = hn::CappedTag<double, 8> and the alias hn. Loads only: every lane keeps its bits.

/// base[idx[lane]] lane by lane, for indices in memory (the pair list's 32-bit grains, or
/// 64-bit pair indices). On x86 one scalar load per lane, assembled into the vector: on the
/// reference machine (AMD EPYC) the CPU's gather instructions took longer than that (the whole
/// reduced production run of the AVX2 target 25.3 s with them, 21.8 s without; AVX-512 18.7 s
/// and 16.9 s; same bits). Elsewhere Highway's gather of the indices widened to 64 bits.
template <class I>
HWY_INLINE hn::Vec<D> gather_at(D d, const double* base, const I* idx) {
#if HWY_TARGET == HWY_AVX2
  (void)d;
  return hn::Vec<D>{_mm256_set_pd(base[idx[3]], base[idx[2]], base[idx[1]], base[idx[0]])};
#elif HWY_TARGET == HWY_AVX3 || HWY_TARGET == HWY_AVX3_DL
  (void)d;
  return hn::Vec<D>{_mm512_set_pd(base[idx[7]], base[idx[6]], base[idx[5]], base[idx[4]],
                                  base[idx[3]], base[idx[2]], base[idx[1]], base[idx[0]])};
#else
  const hn::RebindToSigned<D> di;
  if constexpr (sizeof(I) == 4) {
    return hn::GatherIndex(d, base, hn::PromoteTo(di, hn::LoadU(hn::Rebind<I, D>(), idx)));
  } else {
    return hn::GatherIndex(d, base, hn::LoadU(di, idx));
  }
#endif
}
