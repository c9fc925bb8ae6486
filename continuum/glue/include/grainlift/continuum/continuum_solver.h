// The continuum mu(I) solver as a grainlift solver: case file in, shared result schema out.
// deal.II-free, so the command compiles fast.
#pragma once

#include "grainlift/continuum/continuum_config.h"
#include "grainlift/shared/case/case_model.h"
#include "grainlift/shared/run/run_driver.h"

namespace grainlift::continuum {

/// @brief Translate a validated case into the solver configuration. Throws InputError when
/// the case sets no confining pressure (no gravity and continuum.ambient_pressure = 0).
ContinuumConfig make_continuum_config(const Case& c, const std::string& out_dir);

/// The "fem" entry of the solver table.
SolverEntry solver_entry();

}  // namespace grainlift::continuum
