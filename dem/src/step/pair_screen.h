// The pair screen's scalar code (step_kernels.h: screen_pairs), the reference the vector
// loops reproduce bit for bit, and their tail (the pairs after the last whole vector).
#pragma once

#include <cstddef>
#include <cstdint>

#include "grainlift/dem/periodic_box.h"

namespace grainlift::dem::detail {

/// @brief Pairs [k0, k1) one by one: writes each k to out and advances the count only for
/// touching pairs, |x_i - x_j|^2 < (r_i + r_j)^2 (a touching pair is rare and unpredictable,
/// so no branch). The minimum image subtracts l, -l or +0.0 (d - 0.0 is d, d - (-l) is d + l):
/// the bits of PeriodicBox::min_image. One copy per periodicity (no image code along a wall
/// direction). kRs2: (r_i + r_j)^2 read from rs2[k], which has the bits computed here from r.
/// The separations (dx, dy) of the touching pairs go to out_dx, out_dy in the same order.
template <bool kPx, bool kPy, bool kRs2>
inline std::size_t screen_scalar(const PeriodicBox& box, const int* owner, const int* partner,
                                 const double* x, const double* y, const double* r,
                                 const double* rs2, std::int64_t k0, std::int64_t k1,
                                 std::int64_t* out, double* out_dx, double* out_dy) {
  const double lx = box.lx(), ly = box.ly();
  const double hx = 0.5 * lx, hy = 0.5 * ly;
  std::size_t n = 0;
#pragma GCC unroll 2
  for (std::int64_t k = k0; k < k1; ++k) {
    const int i = owner[k], j = partner[k];
    double dx = x[i] - x[j], dy = y[i] - y[j];
    if (kPx) dx -= dx > hx ? lx : (dx < -hx ? -lx : 0.0);
    if (kPy) dy -= dy > hy ? ly : (dy < -hy ? -ly : 0.0);
    double reach;
    if (kRs2) {
      reach = rs2[k];
    } else {
      const double rs = r[i] + r[j];
      reach = rs * rs;
    }
    out[n] = k;
    out_dx[n] = dx;
    out_dy[n] = dy;
    n += dx * dx + dy * dy < reach ? 1 : 0;
  }
  return n;
}

/// @brief screen_scalar() for the periodicity of @p box.
template <bool kRs2>
inline std::size_t screen_scalar_box(const PeriodicBox& box, const int* owner, const int* partner,
                                     const double* x, const double* y, const double* r,
                                     const double* rs2, std::int64_t k0, std::int64_t k1,
                                     std::int64_t* out, double* out_dx, double* out_dy) {
  auto run = [&](auto screen) {
    return screen(box, owner, partner, x, y, r, rs2, k0, k1, out, out_dx, out_dy);
  };
  if (box.periodic_x) {
    return box.periodic_y ? run(screen_scalar<true, true, kRs2>)
                          : run(screen_scalar<true, false, kRs2>);
  }
  return box.periodic_y ? run(screen_scalar<false, true, kRs2>)
                        : run(screen_scalar<false, false, kRs2>);
}

}  // namespace grainlift::dem::detail
