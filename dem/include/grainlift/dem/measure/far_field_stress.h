// The stress the bed actually has away from the intruder: contact plus kinetic stress averaged
// over a horizontal strip at the intruder's height, with a disk around the intruder and the
// layers next to the walls left out. Under gravity that is the lithostatic pressure at the
// intruder's depth (the strip is centred on it); with a lid, the confinement. Reads the
// system, never changes it.
#pragma once

#include "grainlift/dem/dem_config.h"
#include "grainlift/dem/dem_output.h"

namespace grainlift::dem {

class DemSystem;

/// Where the far field is measured (m): the strip |y - y_intruder| < half_height, outside the
/// disk of radius exclusion around the intruder, at least wall_margin from the centres of the
/// wall disks (the lid's where it has moved).
struct FarFieldRegion {
  double exclusion = 0;
  double half_height = 0;
  double wall_margin = 0;
  /// @brief The default region of a case: exclusion 3 D (outside the jammed front and wake of
  /// Kumar's Fig. 7), half height 1.5 D, wall margin 2 d.
  static FarFieldRegion of(const DemConfig& cfg);
};

/// @brief The far-field stress of the current state of @p s (its per-pair forces must be stored:
/// DemSystem::set_store_pair_forces(true)). Contacts count where the midpoint of their branch
/// vector lies in the region, grains where their centre does:
///   sigma = -(1/A) [ sum_contacts f (x) l + sum_grains m v' (x) v' ],
/// f the force on the grain, l its branch vector from the partner's centre, v' the grain's
/// velocity minus the region's mean, A the region's area (tension positive, as the fields);
/// pressure p = -(sigma_xx + sigma_yy) / 2. A region of zero area gives NaN.
FarFieldSample far_field_stress(const DemSystem& s, const DemConfig& cfg,
                                const FarFieldRegion& region);

}  // namespace grainlift::dem
