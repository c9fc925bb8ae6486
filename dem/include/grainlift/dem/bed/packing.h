// Preparation of the granular bed (Kumar 2019 Sec. II): random insertion, soft compression
// by radius growth, random removal, relaxation; cached on disk by a hash of the inputs.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "grainlift/dem/dem_config.h"
#include "grainlift/dem/system/dem_system.h"

namespace grainlift::dem {

/// A prepared bed: grain centres and radii (m), grains in a spatially sorted order.
struct PackedBed {
  std::vector<double> x, y, r;
  double area_fraction = 0;  ///< sum of grain areas / accessible area
  bool from_cache = false;
  /// Why a cache entry for this bed was not used (damaged, foreign, older format: removed and
  /// rebuilt) or could not be stored (a full or read-only cache folder), or "".
  std::string cache_note;
};

/// @brief Area (m^2) open to grains: the box minus the wall strips (one mean diameter per
/// wall) minus the intruder disk (none when intruder_diameter = 0). Phi = sum of grain areas /
/// this area.
double accessible_area(const DemConfig& cfg);

/// @brief Frozen wall disks of the mean diameter, centres d/2 inside each walled box edge,
/// evenly spaced (spacing closest to d that tiles the edge).
std::vector<Disk> make_wall_disks(const DemConfig& cfg);

/// @brief The run [first, last) of @p walls (make_wall_disks, which puts each row in one run)
/// whose centres are at height @p y; {-1, -1} when there is none.
std::pair<int, int> wall_row(const std::vector<Disk>& walls, double y);

/// @brief FNV-1a 64 hash of every packing-relevant field of cfg (and the seed).
std::uint64_t packing_hash(const DemConfig& cfg);

/// @brief Path of the cache file for cfg ("" when cfg.packing_cache_dir is empty).
std::string packing_cache_path(const DemConfig& cfg);

/// @brief Prepare the bed for cfg, or load it from packing_cache_dir when it was saved before.
/// cfg.intruder_diameter = 0 prepares a bed without an intruder.
/// Throws ConfigError when the bed cannot be made (e.g. Phi out of range).
PackedBed prepare_packing(const DemConfig& cfg, const ProgressCallback& progress = {});

}  // namespace grainlift::dem
