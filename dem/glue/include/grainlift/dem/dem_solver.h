// The DEM as a grainlift solver: case file in, shared result schema out.
#pragma once

#include "grainlift/dem/dem_config.h"
#include "grainlift/shared/case_model.h"
#include "grainlift/shared/run_driver.h"

namespace grainlift::dem {

/// @brief Translate a validated case into the engine configuration.
/// @param threads OpenMP threads for the engine.
DemConfig make_dem_config(const Case& c, int threads);

/// The "dem" entry of the solver table.
SolverEntry solver_entry();

}  // namespace grainlift::dem
