// The continuum's box from a case (glue, deal.II-free): the FE box on the DEM's domain or the
// symmetric box of continuum.box_half_size, and the sentence that compares the two.
#pragma once

#include <string>

#include "grainlift/continuum/continuum_config.h"
#include "grainlift/shared/case/case_model.h"

namespace grainlift::continuum {

/// The FE box: the case's domain (solver_box) with the far field of continuum.far_field, or
/// the symmetric box of continuum.box_half_size.
void set_box(const Case& c, ContinuumConfig& f);

/// One line on the FE box against the DEM's, for the run's progress and the output's notes.
std::string box_statement(const Case& c, const ContinuumConfig& f);

/// The case-file name of a far field ("open", "periodic", "symmetric_box").
const char* far_field_name(FarField f);

}  // namespace grainlift::continuum
