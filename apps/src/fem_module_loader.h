// The continuum module (continuum/glue/include/grainlift/continuum/fem_module.h), loaded on
// first use so that the commands that do not solve the continuum start without deal.II.
#pragma once

#include "grainlift/continuum/fem_module.h"

namespace grainlift::app {

/// The module, loaded on the first call: from the folder beside the command that an
/// installation or the build tree gives it (lib/grainlift/ next to bin/), else from the build
/// tree it was built in. Throws RunError naming the paths tried and the loader's reason when
/// it cannot be loaded or is of another version.
const continuum::FemModule& fem_module();

/// The module when it has been loaded, else null (nothing is loaded).
const continuum::FemModule* fem_module_if_loaded();

/// True when this process was started by an MPI launcher (mpirun, mpiexec, srun): its ranks
/// must all enter MPI at start, whatever they are going to run.
bool started_by_mpi_launcher();

}  // namespace grainlift::app
