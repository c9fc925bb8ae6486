// Which SIMD target runs the DEM step's vector loops (step_kernels.cc, contact_law_batch.cc).
// Those files are compiled once per target by Google Highway (foreach_target.h); Highway's
// dynamic dispatch (HWY_DYNAMIC_DISPATCH) calls the code of the target chosen here: the best
// one this CPU runs, or the one GRAINLIFT_SIMD names. "scalar" is not a Highway target but our
// own scalar code, the reference whose bits every vector target reproduces.
#pragma once

#include <string>

// For the files Highway compiles once per target: whether the target being compiled has
// vector lanes of doubles to run the kernels on (not Highway's scalar fallbacks, nor 32-bit
// Arm's NEON). Evaluated where used, inside that target's code.
#define GRAINLIFT_DOUBLE_LANES \
  (HWY_TARGET != HWY_SCALAR && HWY_TARGET != HWY_EMU128 && HWY_HAVE_FLOAT64)

namespace grainlift::dem::detail {

/// @brief Whether the vector loops run: a vector target is chosen (the CPU has one and
/// GRAINLIFT_SIMD does not ask for scalar; chosen at the first call) and
/// set_vector_kernels(false) was not called. When false, every loop runs its scalar code.
bool vector_enabled();

/// @brief The target the environment asks for: GRAINLIFT_SIMD's value, "scalar" when
/// GRAINLIFT_NO_SIMD is set, "auto" when neither is.
std::string requested_simd();

}  // namespace grainlift::dem::detail
