// Switch for the vector loops of the DEM step: the pair screen, the kick and drift, Kumar's
// contact law. One Google Highway source compiled for every SIMD target of the build (AVX2,
// AVX-512, NEON, SVE, ...), the target chosen at run time: by default the best this CPU runs;
// the environment variable GRAINLIFT_SIMD=scalar|avx2|avx512|... chooses (GRAINLIFT_NO_SIMD,
// the older switch, means scalar). Off, every loop runs its scalar code; the results are the
// same bits on every target (tests/dem/test_simulation.cc checks it).
#pragma once

#include <string>
#include <vector>

namespace grainlift::dem {

/// @brief The target the step's loops use now: "scalar", "avx2", "avx512", "neon", ...
std::string simd_target();

/// @brief The targets this build and this CPU can run, for a sentence ("scalar, avx2,
/// avx512"), with those the build has and the CPU lacks in parentheses.
std::string simd_targets();

/// @brief The names of the targets this build and this CPU can run, "scalar" first, then from
/// the least to the most capable.
std::vector<std::string> runnable_simd_targets();

/// @brief "" when GRAINLIFT_SIMD is unset or names a target this build and CPU run, else the
/// sentence that says so (a run refuses to start: the bits would not be those asked for).
std::string simd_setting_error();

/// @brief Allow (default) or forbid the vector loops, for every DemSystem from now on.
void set_vector_kernels(bool on);

/// @brief Whether the vector loops run: the CPU has them, the environment allows them and
/// set_vector_kernels(false) was not called.
bool vector_kernels();

/// @brief Use target @p name (one of runnable_simd_targets()) from now on instead of the one
/// the environment chose, for tests and benchmarks; call it while no step runs. Returns false,
/// changing nothing, when this build or CPU cannot run it.
bool set_simd_target(const std::string& name);

}  // namespace grainlift::dem
