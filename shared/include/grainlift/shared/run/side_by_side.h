// Independent pieces of work (the solvers of `grainlift run`, shear-cell points, creeping-layer
// seeds) on a few threads at once, their results reported in order.
#pragma once

#include <cstddef>
#include <functional>

namespace grainlift {

/// @brief Calls @p run(k) for each k in [0, n) once, on min(@p workers, n) threads at once
/// (this thread among them: with other threads, it runs the last piece, k = n - 1, first; on
/// its own, every piece in order), and @p report(k) in increasing k, one at a time, each as
/// soon as the runs 0..k have ended; no report past a run that threw. After every run has
/// ended, the exception of the first run (by k) that threw is rethrown.
void side_by_side(std::size_t n, int workers, const std::function<void(std::size_t)>& run,
                  const std::function<void(std::size_t)>& report);

}  // namespace grainlift
