// What the DEM glue's run (dem_solver.cc) shares with its result (dem_result.cc).
#pragma once

#include "grainlift/dem/dem_output.h"
#include "grainlift/shared/case/case_model.h"

namespace grainlift::dem {

/// The travel the run reached, in grain diameters (dem.travel when it ran all its steps).
double travel_run(const Case& c, const DemOutput& out);

}  // namespace grainlift::dem
