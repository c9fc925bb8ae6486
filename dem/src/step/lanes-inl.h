// The gather the step's Highway kernels share (step_kernels.cc, contact_law_batch.cc). No
// include guard and no namespace of its own, on purpose: each of those files includes it inside
// every SIMD target's namespace (Highway compiles them once per target), after defining
// D = hn::CappedTag<double, 8> and the alias hn. Only operations exact or rounded once as in
// IEEE arithmetic: every lane keeps the bits of the scalar code.

/// x[index] lane by lane for the pair list's 32-bit indices (all >= 0). Two things of
/// Highway 1.0's GatherIndex cost the pair screen of a dilute bed 18% against the hand-written
/// AVX-512 loop it replaces: it takes only 64-bit indices (widened first), and on x86 it leaves
/// the register the gather merges into to the compiler, which may pick one that still waits
/// for the previous vector's arithmetic, so that successive gathers wait for each other. On x86
/// therefore the gather of 32-bit indices, masked by index >= 0 (every lane: a mask the
/// compiler cannot fold away) into a zeroed register, which depends on nothing; elsewhere the
/// widened indices and Highway's gather.
HWY_INLINE hn::Vec<D> gather32(D d, const double* base,
                               hn::Vec<hn::Rebind<std::int32_t, D>> index) {
  const hn::Rebind<std::int32_t, D> d32;
#if HWY_TARGET == HWY_AVX3 || HWY_TARGET == HWY_AVX3_DL
  (void)d;
  const auto valid = hn::Gt(index, hn::Set(d32, -1));
  return hn::Vec<D>{_mm512_mask_i32gather_pd(_mm512_setzero_pd(), valid.raw, index.raw, base, 8)};
#elif HWY_TARGET == HWY_AVX2
  (void)d32;
  const hn::RebindToSigned<D> di;
  const auto valid = hn::VecFromMask(di, hn::Gt(hn::PromoteTo(di, index), hn::Set(di, -1)));
  return hn::Vec<D>{_mm256_mask_i32gather_pd(_mm256_setzero_pd(), base, index.raw,
                                             hn::BitCast(d, valid).raw, 8)};
#else
  (void)d32;
  return hn::GatherIndex(d, base, hn::PromoteTo(hn::RebindToSigned<D>(), index));
#endif
}
