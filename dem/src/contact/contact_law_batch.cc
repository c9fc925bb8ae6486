// contact_force() on a batch of contacts: the AVX-512 instantiation of the law where the CPU
// has it (Kumar's law), contact_force() lane by lane otherwise.
#include "grainlift/dem/contact/contact_law_batch.h"

#include "contact/contact_law_avx512.h"
#include "step/step_kernels.h"

namespace grainlift::dem {

namespace {

void scalar_lanes(const LawCoefficients& c, double mu, ContactBatch& b, std::size_t n) {
  for (std::size_t l = 0; l < n; ++l) {
    ContactForce f;
    contact_force(c, b.kinematics(l, mu), b.sx[l], b.sy[l], f);
    b.fx[l] = f.fx;
    b.fy[l] = f.fy;
    b.ftx[l] = f.ftx;
    b.fty[l] = f.fty;
  }
}

}  // namespace

bool contact_force_batch_vectorized(const LawCoefficients& c) {
  return c.law == ContactLaw::kumar2019 && detail::avx512_enabled();
}

void contact_force_batch(const LawCoefficients& c, double mu, ContactBatch& b, std::size_t n) {
#ifdef GRAINLIFT_HAVE_AVX512_LAW
  if (contact_force_batch_vectorized(c)) {
    kumar_contacts_avx512(c, mu, b, n);
    return;
  }
#endif
  scalar_lanes(c, mu, b, n);
}

}  // namespace grainlift::dem
