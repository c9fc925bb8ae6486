// The packing cache: prepared beds stored by their key (packing_hash) under
// DemConfig::packing_cache_dir, so that a case's bed is prepared once.
#pragma once

#include <cstdint>
#include <string>

#include "grainlift/dem/bed/packing.h"

namespace grainlift::dem::detail {

/// What reading a cache entry gave: the bed, or none; and why an entry there was not used.
struct CacheRead {
  bool found = false;
  std::string note;  ///< "" or "packing cache: PATH is damaged (...): removed, the bed rebuilt"
};
/// The bed stored at @p path under key @p hash into @p bed (from_cache set). An entry of an
/// older format, foreign, truncated, of another key or whose checksum fails is removed and
/// reported in the note; no file: not found, no note.
CacheRead load_packing(const std::string& path, std::uint64_t hash, PackedBed& bed);
/// Stores @p bed at @p path under key @p hash (a temporary file renamed into place); a folder
/// that cannot be written (full, read-only) is not an error (the cache only saves time): the
/// previous entry is kept, no temporary file is left, and the returned note says why ("" when
/// it was stored).
std::string save_packing(const std::string& path, std::uint64_t hash, const PackedBed& bed);

}  // namespace grainlift::dem::detail
