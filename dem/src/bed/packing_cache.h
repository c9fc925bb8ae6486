// The packing cache: prepared beds stored by their key (packing_hash) under
// DemConfig::packing_cache_dir, so that a case's bed is prepared once.
#pragma once

#include <cstdint>
#include <string>

#include "grainlift/dem/bed/packing.h"

namespace grainlift::dem::detail {

/// The bed stored at @p path under key @p hash into @p bed (from_cache set); false when there
/// is none, or it is another bed's or unreadable.
bool load_packing(const std::string& path, std::uint64_t hash, PackedBed& bed);
/// Stores @p bed at @p path under key @p hash (a temporary file renamed into place); a folder
/// that cannot be written is not an error (the cache only saves time).
void save_packing(const std::string& path, std::uint64_t hash, const PackedBed& bed);

}  // namespace grainlift::dem::detail
