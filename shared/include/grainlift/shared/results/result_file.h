// Writer and reader of the shared output file <out>/<solver>.h5 (docs/schema.md). This is the
// only code in grainlift that touches HDF5.
#pragma once

#include <string>

#include "grainlift/shared/results/run_result.h"

namespace grainlift {

/// 2: the /derived and /diagnostics groups (files of version 1 are read without them).
inline constexpr int schema_version = 2;

/// @brief Write @p result to @p path atomically (temporary name, then rename).
/// Optional blocks that are empty in @p result are absent from the file.
void write_result(const std::string& path, const RunResult& result);

/// @brief Read a file written by write_result. Throws InputError when the file cannot be
/// opened or is not a grainlift result file.
RunResult read_result(const std::string& path);

/// @brief Write an XDMF sidecar next to the .h5 file so ParaView opens the field grid.
/// Does nothing when the result has no fields. @p h5_name is the .h5 file name relative to
/// the sidecar's folder.
void write_fields_xdmf(const std::string& xmf_path, const std::string& h5_name,
                       const RunResult& result);

}  // namespace grainlift
