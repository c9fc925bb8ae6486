// The DEM as a grainlift solver: case file in, shared result schema out.
#pragma once

#include "grainlift/dem/dem_config.h"
#include "grainlift/dem/dem_output.h"
#include "grainlift/shared/case/case_model.h"
#include "grainlift/shared/run/run_driver.h"

namespace grainlift::dem {

/// @brief Translate a validated case into the engine configuration.
/// @param threads OpenMP threads for the engine.
DemConfig make_dem_config(const Case& c, int threads);

/// @brief The shared schema's image of one DEM run of @p c: the force series, block means
/// with standard errors, surface stresses (Guillard eq. A4 kernel) and the contact histogram
/// of the samples after the steady start, fields, lid and far field. Also used for runs made
/// elsewhere (lammps_bridge.h).
RunResult dem_result(const Case& c, const DemOutput& out);

/// The "dem" entry of the solver table.
SolverEntry solver_entry();

}  // namespace grainlift::dem
