// The arrays the kinematics of a listed grain pair reads (stage 2 of the step, pair_forces.cc),
// its scalar kinematics, and the vector loop that takes a batch of touching pairs from these
// arrays through Kumar's law (contact_law_batch.cc).
#pragma once

#include <cstddef>
#include <cstdint>

#include "grainlift/dem/contact/contact_law_batch.h"

namespace grainlift::dem {

/// The arrays of the grains (r .. inv_m, index of a grain) and of the listed pairs (reff, meff,
/// owner, partner, index of a pair); local copies of the pointers: no aliasing with the
/// arrays written. The pairs' separations come from the pair screen (TouchList::dx, dy).
struct PairInputs {
  const double *r, *vx, *vy, *w, *ax, *ay, *al, *inv_m, *reff, *meff;
  const int *owner, *partner;
  bool pair_consts;  ///< r_eff and m_eff from the list build (no radius changed since)
  double h, dt;      ///< half the spring step; the spring step
  int n_rows;        ///< the grain arrays' length (grains and wall disks)

  /// Normal, overlap, r_eff, m_eff and the contact-point motion of pair k whose centres are
  /// (@p dx, @p dy) apart (the minimum image x_i - x_j, from the pair screen; predicted
  /// velocities at t + dt for the force, half-step velocities for the spring).
  ContactKinematics of(std::int64_t k, double dx, double dy) const {
    const int i = owner[k], j = partner[k];
    const double ri = r[i], rj = r[j];
    const double rs = ri + rj;
    ContactKinematics kin;
    pair_normal(dx, dy, rs, kin.nx, kin.ny, kin.delta);
    if (pair_consts) {
      kin.r_eff = reff[k];
      kin.m_eff = meff[k];
    } else {
      kin.r_eff = ri * rj / rs;
      kin.m_eff = 1.0 / (inv_m[i] + inv_m[j]);
    }
    contact_point_motion(kin.nx, kin.ny, ri, rj,
                         {vx[i] + h * ax[i], vy[i] + h * ay[i], w[i] + h * al[i]},
                         {vx[j] + h * ax[j], vy[j] + h * ay[j], w[j] + h * al[j]},
                         {vx[i], vy[i], w[i]}, {vx[j], vy[j], w[j]}, dt, kin);
    return kin;
  }
};

/// @brief The contact law on the @p nb touching pairs @p kb (in increasing order) with the
/// Coulomb coefficient @p mu, a vector of pairs at a time: their kinematics (PairInputs::of)
/// from the arrays and their minimum-image separations @p dx, @p dy (the pair screen's), the
/// springs read from @p sx, @p sy, then contact_lanes(). Fills lanes
/// [0, nb) of @p out's nx, ny, delta, sx, sy (the advanced springs), fx, fy, ftx, fty, q with
/// the bits of PairInputs::of followed by contact_force(), and raises @p max_ov to the pairs'
/// largest overlap fraction as raise_max_overlap() would. Returns nb, or 0 (nothing done) where
/// there is no vector loop for it (the scalar target, GRAINLIFT_SIMD=scalar).
std::size_t pair_lanes(const PairInputs& in, const LawCoefficients& law, double mu,
                       const std::int64_t* kb, const double* dx, const double* dy, std::size_t nb,
                       const double* sx, const double* sy, ContactBatch& out, double& max_ov);

}  // namespace grainlift::dem
