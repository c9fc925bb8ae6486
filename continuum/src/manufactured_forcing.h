// Internal: the body force of a manufactured solution, -div sigma of an exact stress field by
// central differences, shared by the verification drivers (verification.cc,
// fluidity/coupled_verification.cc). Includes deal.II.
#pragma once

#include <deal.II/base/tensor.h>

#include <functional>

#include "flow_problem.h"

namespace grainlift::continuum::internal {

/// f = -div sigma at @p x, each derivative a central difference of step 1e-5 (error ~1e-10 for
/// the smooth fields of the drivers).
inline Vec2 minus_divergence(const std::function<dealii::Tensor<2, dim>(const Point2&)>& sigma,
                             const Point2& x) {
  const double h = 1e-5;
  Vec2 f;
  for (unsigned int j = 0; j < dim; ++j) {
    Point2 xp = x, xm = x;
    xp[j] += h;
    xm[j] -= h;
    const dealii::Tensor<2, dim> ds = (sigma(xp) - sigma(xm)) / (2 * h);
    for (unsigned int i = 0; i < dim; ++i) f[i] -= ds[i][j];
  }
  return f;
}

}  // namespace grainlift::continuum::internal
