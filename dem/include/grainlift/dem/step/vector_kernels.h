// Switch for the vector (AVX-512) loops of the DEM step: the pair screen, the kick and drift,
// Kumar's contact law. On by default where the CPU has AVX-512F, unless the environment
// variable GRAINLIFT_NO_SIMD is set. Off, every loop runs its scalar code; the results are
// the same bits either way (tests/dem/test_simulation.cc checks it).
#pragma once

namespace grainlift::dem {

/// @brief Allow (default) or forbid the vector loops, for every DemSystem from now on.
void set_vector_kernels(bool on);

/// @brief Whether the vector loops run: the CPU has them, the environment allows them and
/// set_vector_kernels(false) was not called.
bool vector_kernels();

}  // namespace grainlift::dem
