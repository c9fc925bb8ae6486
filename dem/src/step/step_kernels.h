// Inner loops of the time step kept apart from DemSystem: the pair screen (pass 1 of the
// pair loop) and the kick/drift of grains without any force, on the vector lanes of the SIMD
// target chosen at run time (simd_target.h; one Highway source for every target) or by the
// scalar code. Each vector loop does lane by lane the IEEE operations of the scalar code, in
// the same order (compiled without floating-point contraction): the same bits.
#pragma once

#include <cstddef>
#include <cstdint>

#include "grainlift/dem/periodic_box.h"

namespace grainlift::dem::detail {

/// @brief Write the indices k in [k0, k1) of the pairs (owner[k], partner[k]) that touch,
/// |x_i - x_j| < r_i + r_j (minimum image), to out in increasing order; return their number.
/// Branch-free: out needs room for k1 - k0 + 1 entries (it writes before it counts). With
/// rs2 (per pair (r_i + r_j)^2, computed as here) and a vector target, a vector of pairs at a
/// time; n_total: particles in x and y. The minimum-image separations x_i - x_j of the
/// touching pairs go to out_dx, out_dy (as much room as out) in the same order.
std::size_t screen_pairs(const PeriodicBox& box, const int* owner, const int* partner,
                         const double* x, const double* y, const double* r, const double* rs2,
                         int n_total, std::int64_t k0, std::int64_t k1, std::int64_t* out,
                         double* out_dx, double* out_dy);

/// The arrays and constants of the kick (DemSystem::finish_impl).
struct PlainKick {
  double* x;
  double* y;
  double* vx;
  double* vy;
  double* w;
  const float* xb;
  const float* yb;
  std::uint8_t* flags;    ///< per grain: candidate_bit, accel_bit
  std::uint8_t* touched;  ///< per grain: 1 if a listed pair touches
  /// per grain: 1 if asleep (sleeping.cc: the kick leaves its bits as they are), or nullptr
  const std::uint8_t* dormant;
  double dt, h, damp;
  double ax0, ay0, al0;  ///< the accelerations of a grain without force
  // the pair-force sums per grain (range_forces), and what the accelerations need
  double* sfxy;  ///< fx, fy side by side
  double* sq;
  const double* inv_m;
  const double* inv_i;
  const double* r;
  double* ax;
  double* ay;
  double* al;
  double gx, gy;
  std::uint8_t candidate_bit, accel_bit;
  PeriodicBox box;
};

/// @brief From row i on, in groups of eight, what DemSystem::finish_impl does: the second
/// half kick (and with drift, the next half kick and drift) of grains without any force
/// (flags and touched 0; groups of eight sleepers are skipped), and also of grains with pair
/// forces (summed in sfxy, sq) and their accelerations; stops at the first group with a
/// grain it does not handle (a candidate of the intruder), or fewer than
/// eight rows before hi. Returns the row where it stopped (i itself when it did nothing or on
/// the scalar target); max_d2 is raised to the largest squared displacement from (xb, yb) of
/// the grains it moved (drift only). Call it only when vector_enabled() (simd_target.h).
int kick_plain(const PlainKick& k, bool drift, int i, int hi, double& max_d2);

/// @brief The Highway target (HWY_AVX2, HWY_AVX3, HWY_NEON, ...) whose code the dynamic
/// dispatch of these loops calls now, as that code reports it.
std::int64_t dispatched_target();

}  // namespace grainlift::dem::detail
