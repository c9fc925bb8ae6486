// The contact law on a batch of independent contacts, structure of arrays. The law itself is
// written once, as contact_lanes() (contact_lanes-inl.h): here it runs on as many contacts
// per instruction as the SIMD target has lanes (either law; Highway's dispatch, the lane type
// in contact_law_batch.cc), and as contact_force() lane by lane otherwise (the scalar
// target). The bits are those of contact_force(): the same IEEE operations lane by lane in the
// same order, branches as masks, no fused multiply-add.
#pragma once

#include <cstddef>

#include "grainlift/dem/contact/contact_law.h"

namespace grainlift::dem {

/// Up to kLanes contacts; inputs as ContactKinematics, the spring (sx, sy) in and out, the
/// outputs of ContactForce (fn and slipping are not kept). Lanes past the batch size are
/// computed too when they share an eight-lane group with a used one, so they must hold
/// finite values (value-initialise the batch once).
struct ContactBatch {
  static constexpr std::size_t kLanes = 32;
  alignas(64) double nx[kLanes], ny[kLanes], delta[kLanes], r_eff[kLanes], m_eff[kLanes];
  alignas(64) double vn[kLanes], vtx[kLanes], vty[kLanes], dsx[kLanes], dsy[kLanes];
  alignas(64) double sx[kLanes], sy[kLanes];
  alignas(64) double fx[kLanes], fy[kLanes], ftx[kLanes], fty[kLanes];
  /// n x F_t = nx fty - ny ftx, the factor of the pair's torques (contact_force_batch)
  alignas(64) double q[kLanes];

  /// @brief Lane @p l from the kinematics @p k (its mu aside) and the spring (@p s_x, @p s_y).
  void set(std::size_t l, const ContactKinematics& k, double s_x, double s_y) {
    nx[l] = k.nx;
    ny[l] = k.ny;
    delta[l] = k.delta;
    r_eff[l] = k.r_eff;
    m_eff[l] = k.m_eff;
    vn[l] = k.vn;
    vtx[l] = k.vtx;
    vty[l] = k.vty;
    dsx[l] = k.dsx;
    dsy[l] = k.dsy;
    sx[l] = s_x;
    sy[l] = s_y;
  }

  /// The inputs of lane @p l as contact_force() takes them, with the Coulomb coefficient @p mu.
  ContactKinematics kinematics(std::size_t l, double mu) const {
    ContactKinematics k;
    k.nx = nx[l];
    k.ny = ny[l];
    k.delta = delta[l];
    k.r_eff = r_eff[l];
    k.m_eff = m_eff[l];
    k.vn = vn[l];
    k.vtx = vtx[l];
    k.vty = vty[l];
    k.dsx = dsx[l];
    k.dsy = dsy[l];
    k.mu = mu;
    return k;
  }
};

/// @brief contact_force() on lanes [0, n) of b (n <= kLanes), all with the Coulomb
/// coefficient mu; the springs advanced in place, and q = nx fty - ny ftx of each.
void contact_force_batch(const LawCoefficients& c, double mu, ContactBatch& b, std::size_t n);

/// @brief Whether contact_force_batch has a vector loop for this law on this CPU (a SIMD
/// target with lanes of doubles in use, not GRAINLIFT_SIMD=scalar); the same for both laws.
bool contact_force_batch_vectorized(const LawCoefficients& c);

}  // namespace grainlift::dem
