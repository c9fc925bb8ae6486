// Grain-grain and grain-wall contact forces of a range of rows (stage 2 of the step): a
// distance screen over the listed pairs, the history of separated pairs forgotten, then the
// contact law (contact_law.h) on the touching pairs in batches.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "grainlift/dem/contact/contact_law_batch.h"
#include "grainlift/dem/system/dem_system.h"
#include "step/pair_inputs.h"
#include "step/step_kernels.h"

namespace grainlift::dem {

namespace {
/// The stored forces of the listed pairs (null: not stored).
struct PairForces {
  double* fx = nullptr;
  double* fy = nullptr;
  double* q = nullptr;
};

/// A pair that is apart forgets its history (springs @p sx, @p sy) and its stored force. Only
/// pairs that touched at the step before (@p before, sorted) can hold any: those that no
/// longer touch (not in @p touching, sorted) are found by a merge of the two lists; after a
/// list build (@p full_check) every pair of [k0, k1) is checked.
void forget_apart_pairs(const std::int64_t* touching, std::size_t n_touching,
                        const std::int64_t* before, std::size_t n_before, std::int64_t k0,
                        std::int64_t k1, bool full_check, PairForces f, double* sx, double* sy) {
  auto forget = [&](std::int64_t k) {
    if (sx[k] != 0.0 || sy[k] != 0.0) sx[k] = sy[k] = 0;
    if (f.fx && (f.fx[k] != 0.0 || f.fy[k] != 0.0 || f.q[k] != 0.0)) f.fx[k] = f.fy[k] = f.q[k] = 0;
  };
  if (full_check) {
    std::size_t a = 0;
    for (std::int64_t k = k0; k < k1; ++k) {
      if (a < n_touching && touching[a] == k) {
        ++a;
        continue;
      }
      forget(k);
    }
  } else {
    // Most contacts last from one step to the next: the two lists agree over long runs, taken
    // four at a time without a branch per pair; a new contact or a separation ends a run, and
    // one step of the merge handles it
    std::size_t a = 0, b = 0;
    while (b < n_before) {
      while (b + 4 <= n_before && a + 4 <= n_touching &&
             ((touching[a] ^ before[b]) | (touching[a + 1] ^ before[b + 1]) |
              (touching[a + 2] ^ before[b + 2]) | (touching[a + 3] ^ before[b + 3])) == 0) {
        a += 4;
        b += 4;
      }
      if (b == n_before) break;
      const std::int64_t k = before[b++];
      while (a < n_touching && touching[a] < k) ++a;
      if (a < n_touching && touching[a] == k) {
        ++a;
      } else {
        forget(k);
      }
    }
  }
}

/// The kinematics of the @p nb touching pairs @p kb (separations @p dx, @p dy) into the batch
/// @p cb (with their springs), or on the frictionless path (@p normal_only) their normal
/// forces at once.
inline void fill_batch(const PairInputs& in, const LawCoefficients& law, bool normal_only,
                       const std::int64_t* kb, const double* dx, const double* dy,
                       std::size_t nb, const double* sx, const double* sy, ContactBatch& cb) {
  for (std::size_t b = 0; b < nb; ++b) {
    const std::int64_t k = kb[b];
    const ContactKinematics kin = in.of(k, dx[b], dy[b]);
    if (normal_only) {
      const double fn = normal_contact_force(law, kin);
      cb.nx[b] = kin.nx;
      cb.ny[b] = kin.ny;
      cb.delta[b] = kin.delta;
      cb.fx[b] = fn * kin.nx;
      cb.fy[b] = fn * kin.ny;
      cb.ftx[b] = cb.fty[b] = 0.0;
      cb.q[b] = normal_cross_tangential(cb.nx[b], cb.ny[b], cb.ftx[b], cb.fty[b]);
    } else {
      cb.set(b, kin, sx[k], sy[k]);
    }
  }
}
/// The pair force (fx, fy) and n x F_t (q) added to grain @p g's sums (the owner gets +F, the
/// partner -F; both +q; fx and fy side by side in @p sfxy, added as one pair of lanes: the
/// same two IEEE additions) and @p g marked touched; a grain shared between threads is only
/// marked (its sum is gathered at the kick; another thread may mark it too: a relaxed atomic
/// store).
template <bool kOwner>
inline void add_to_grain(int g, bool shared, double fx, double fy, double q, double* sfxy,
                         double* sq, std::uint8_t* touched) {
  if (shared) {
    __atomic_store_n(&touched[g], std::uint8_t{1}, __ATOMIC_RELAXED);
    return;
  }
  double* s = sfxy + 2 * static_cast<std::ptrdiff_t>(g);
#if defined(__SSE2__)
  const __m128d f = _mm_set_pd(fy, fx);
  _mm_store_pd(s, kOwner ? _mm_add_pd(_mm_load_pd(s), f) : _mm_sub_pd(_mm_load_pd(s), f));
#else
  if (kOwner) {
    s[0] += fx;
    s[1] += fy;
  } else {
    s[0] -= fx;
    s[1] -= fy;
  }
#endif
  sq[g] += q;
  touched[g] = 1;
}

/// The largest overlap fraction @p max_ov raised by a pair of radii @p ri, @p rj overlapping by
/// @p delta: the division only where it can raise the maximum (the pre-test has a margin far
/// above the rounding of either side).
inline void raise_max_overlap(double delta, double ri, double rj, double& max_ov) {
  const double dmin = 2.0 * std::min(ri, rj);
  if (delta > max_ov * dmin * (1.0 - 1e-12)) {
    const double ov = delta / dmin;
    if (ov > max_ov) max_ov = ov;
  }
}
}  // namespace

void DemSystem::chunk_forces(int chunk, double spring_dt, double& max_ov, bool full_check,
                             bool last_step) {
  const int lo = chunk * kChunkRows, hi = std::min(n_grains_, lo + kChunkRows);
  range_forces(lo, hi, touch_[static_cast<std::size_t>(chunk)],
               touch_prev_[static_cast<std::size_t>(chunk)], spring_dt, max_ov, full_check,
               last_step, nullptr);
}

void DemSystem::range_forces(int lo, int hi, TouchList& now, TouchList& before,
                             double spring_dt, double& max_ov, bool full_check, bool last_step,
                             const std::uint8_t* shared) {
  if (shared) {
    range_forces_impl<true>(lo, hi, now, before, spring_dt, max_ov, full_check, last_step,
                            shared);
  } else {
    range_forces_impl<false>(lo, hi, now, before, spring_dt, max_ov, full_check, last_step,
                             nullptr);
  }
}

template <bool kTeam>
void DemSystem::range_forces_impl(int lo, int hi, TouchList& touch_list, TouchList& before_list,
                                  double spring_dt, double& max_ov, bool full_check,
                                  bool last_step, const std::uint8_t* shared) {
  // local copies: the compiler can keep them in registers (no aliasing with the arrays)
  const PeriodicBox box = opt_.box;
  const LawCoefficients law = law_;
  const double mu = mu_;
  const double* x = p_.x.data();
  const double* y = p_.y.data();
  const double* r = p_.r.data();
  const int* owner = nl_.owner.data();
  const int* partner = nl_.partner.data();
  double* sx = nl_.sx.data();
  double* sy = nl_.sy.data();
  double* pfx = nl_.fx.data();
  double* pfy = nl_.fy.data();
  double* pq = nl_.q.data();
  const int ng = n_grains_;
  // The forces are summed per grain in the pair loop itself (Newton's third law), in pair
  // order, except for the shared grains of a team (run_segment_team): their pair forces are
  // stored and summed at the kick, in the same order (pairs where the grain is the partner,
  // by pair index, then its own row), so the results are the same bits.
  const bool store_all = store_pair_forces_ && last_step;
  const bool store_frozen = store_pair_forces_;  // pairs with a frozen disk: every step
  const bool forget_forces = store_pair_forces_ || kTeam;
  double* sfxy = fxy_.data();
  double* sq = tq_.data();
  std::uint8_t* touched = touched_.data();
  const std::int64_t k0 = nl_.first[lo], k1 = nl_.first[hi];
  std::swap(touch_list, before_list);
  // Pass 1: distance checks only, one flat loop over the range's pairs (most listed pairs of
  // a relaxed bed are apart); no stores but the list of touching pairs and their separations.
  touch_list.n = detail::screen_pairs(box, owner, partner, x, y, r,
                                      radii_scaled_ ? nullptr : pair_rs2_.data(), n_total_,
                                      k0, k1, touch_list.k.data(), touch_list.dx.data(),
                                      touch_list.dy.data());
  const std::int64_t* touching = touch_list.k.data();
  const std::size_t n_touching = touch_list.n;
  forget_apart_pairs(touching, n_touching, before_list.k.data(), before_list.n, k0, k1,
                    full_check, forget_forces ? PairForces{pfx, pfy, pq} : PairForces{}, sx, sy);
  // Pass 2: the contact law on the touching pairs, in pair order, in batches of kBatch: the
  // kinematics of the batch, then the law on each (independent contacts, so that the long
  // chains of divisions and square roots of several contacts overlap), then the sums. Every
  // contact goes through the same operations as one at a time: the same bits.
  constexpr std::size_t kBatch = 32;
  // the pairs' kinematics (PairInputs::of); r_eff and m_eff of each pair computed by the same
  // expressions at the list build (valid until a radius changes)
  const PairInputs in{p_.r.data(),      p_.vx.data(),     p_.vy.data(),    p_.w.data(),
                      p_.ax.data(),     p_.ay.data(),     p_.alpha.data(), p_.inv_m.data(),
                      pair_reff_.data(), pair_meff_.data(), nl_.owner.data(), nl_.partner.data(),
                      !radii_scaled_,   0.5 * spring_dt,  spring_dt,       n_total_};
  // the batch in structure-of-arrays form (contact_law_batch.h); value-initialised: lanes
  // past a short batch hold finite numbers
  ContactBatch cb{};
  static_assert(kBatch == ContactBatch::kLanes);
  const std::size_t nt = n_touching;
  // The frictionless path (set_frictionless_path, mu = 0): the normal force only. The Coulomb
  // cap makes F_t zero in the general law, so the forces are the same (the torques +-0), and no
  // spring is read or written: they stay zero (the general law would store -B_t v_t / A_t on
  // slip, which no force reads while mu = 0).
  const bool normal_only = frictionless_path_active();
  for (std::size_t b0 = 0; b0 < nt; b0 += kBatch) {
    const std::size_t nb = std::min(kBatch, nt - b0);
    const std::int64_t* kb = touching + b0;
    // the kinematics and the law a vector of pairs at a time where a vector loop does both
    // (which also raises max_ov)
    const double* dxb = touch_list.dx.data() + b0;
    const double* dyb = touch_list.dy.data() + b0;
    const bool lanes =
        !normal_only && pair_lanes(in, law, mu, kb, dxb, dyb, nb, sx, sy, cb, max_ov) > 0;
    if (!lanes) {
      fill_batch(in, law, normal_only, kb, dxb, dyb, nb, sx, sy, cb);
      if (!normal_only) contact_force_batch(law, mu, cb, nb);
    }
    for (std::size_t b = 0; b < nb; ++b) {
      const std::int64_t k = kb[b];
      const int i = owner[k], j = partner[k];
      if (sleep_active_) wake(i, j);
      if (!normal_only) {
        sx[k] = cb.sx[b];
        sy[k] = cb.sy[b];
      }
      const double fxb = cb.fx[b], fyb = cb.fy[b];
      const double qk = cb.q[b];
      const bool si = kTeam && shared[i] != 0;
      const bool sj = kTeam && j < ng && shared[j] != 0;
      if (store_all || si || sj || (store_frozen && j >= ng)) {
        pfx[k] = fxb;
        pfy[k] = fyb;
        pq[k] = qk;
      }
      add_to_grain<true>(i, si, fxb, fyb, qk, sfxy, sq, touched);
      if (j < ng) add_to_grain<false>(j, sj, fxb, fyb, qk, sfxy, sq, touched);
      if (!lanes) raise_max_overlap(cb.delta[b], r[i], r[j], max_ov);
    }
  }
}


}  // namespace grainlift::dem
