// Internal: the AVX-512 instantiation of the contact law (contact_law_avx512.cc).
#pragma once

#include <cstddef>

#include "grainlift/dem/contact/contact_law_batch.h"

namespace grainlift::dem {

#if defined(__x86_64__) && defined(__GNUC__)
#define GRAINLIFT_HAVE_AVX512_LAW 1
/// contact_force_batch() for Kumar's law, eight lanes per instruction. Only call it when the
/// CPU has AVX-512F (detail::avx512_enabled()).
void kumar_contacts_avx512(const LawCoefficients& c, double mu, ContactBatch& b, std::size_t n);
#endif

}  // namespace grainlift::dem
