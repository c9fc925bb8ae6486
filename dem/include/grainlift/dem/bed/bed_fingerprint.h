// The structure of a prepared bed at rest, before the intruder moves (issue 17, docs/dem-model.md
// "Bed fingerprint"): how many contacts, how many rattlers, how the gaps to the nearest
// neighbour are distributed, the contact fabric, and the area fraction across the box and
// around the intruder. A pure kernel over positions and radii; the glue writes it as /bed.
#pragma once

#include <vector>

#include "grainlift/dem/dem_config.h"
#include "grainlift/dem/bed/packing.h"

namespace grainlift::dem {

struct BedFingerprint {
  /// touching neighbours (grains and wall disks: overlap > 0) per mobile grain
  double contacts_per_grain = 0;
  /// mobile grains with fewer than 2 contacts (none can carry a load in 2D with friction)
  double rattler_fraction = 0;
  /// fabric <n n> over grain-grain contacts (trace 1; 0.5, 0, 0.5 when isotropic); 0 without
  /// contacts
  double fabric_xx = 0, fabric_xy = 0, fabric_yy = 0;
  /// surface gap to the nearest neighbour (grain or wall disk) of each mobile grain, in mean
  /// diameters (negative: overlap): bin edges (gap_edges, n + 1; gaps beyond the last edge
  /// count in the last bin, below the first in the first) and the fraction of grains per bin
  std::vector<double> gap_edges, gap_fraction;
  double mean_gap = 0;  ///< mean of those gaps, mean diameters
  /// area fraction (grain area by centre) in horizontal bands of about one mean diameter across
  /// the grains' region: band centres (m) and values
  std::vector<double> band_y, band_area_fraction;
  /// the same in rings one mean diameter wide round the intruder's starting position, from
  /// its surface out to 10 d: ring mid-radii (m) and values (the ring's area outside the box
  /// and walls is not counted)
  std::vector<double> ring_r, ring_area_fraction;
};

/// @brief The fingerprint of @p bed with the wall disks @p walls in the box of @p cfg.
BedFingerprint bed_fingerprint(const DemConfig& cfg, const PackedBed& bed,
                               const std::vector<Disk>& walls);

}  // namespace grainlift::dem
