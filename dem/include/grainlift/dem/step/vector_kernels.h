// Switch for the vector (AVX-512) loops of the DEM step: the pair screen, the kick and drift,
// Kumar's contact law. On by default where the CPU has AVX-512F; the environment variable
// GRAINLIFT_SIMD=scalar|avx512 chooses (GRAINLIFT_NO_SIMD, the older switch, means scalar).
// Off, every loop runs its scalar code; the results are the same bits either way
// (tests/dem/test_simulation.cc checks it).
#pragma once

#include <string>

namespace grainlift::dem {

/// @brief The target the step's loops use now: "avx512" or "scalar".
std::string simd_target();

/// @brief The targets this build and this CPU can run, for a sentence ("scalar, avx512").
std::string simd_targets();

/// @brief "" when GRAINLIFT_SIMD is unset or names a target this build and CPU run, else the
/// sentence that says so (a run refuses to start: the bits would not be those asked for).
std::string simd_setting_error();

/// @brief Allow (default) or forbid the vector loops, for every DemSystem from now on.
void set_vector_kernels(bool on);

/// @brief Whether the vector loops run: the CPU has them, the environment allows them and
/// set_vector_kernels(false) was not called.
bool vector_kernels();

}  // namespace grainlift::dem
