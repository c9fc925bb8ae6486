// The LAMMPS bridge (docs/lammps.md). Export: a case's prepared bed (the packing `grainlift
// run` uses, from the same cache) and its scene as a LAMMPS input script and data file, the
// contact law mapped parameter by parameter. Import: what that script writes (the force on
// the intruder per sample, its contacts) read back into the shared schema through the DEM's
// own post-processing, so that compare, report and the continuum work on it unchanged.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "grainlift/dem/dem_config.h"
#include "grainlift/dem/bed/packing.h"
#include "grainlift/shared/case/case_model.h"
#include "grainlift/shared/results/run_result.h"

namespace grainlift::dem {

/// The files of an exported folder.
inline constexpr const char* kLammpsScript = "in.grainlift";
inline constexpr const char* kLammpsData = "bed.data";
inline constexpr const char* kLammpsForces = "forces.txt";
inline constexpr const char* kLammpsContacts = "contacts.dump";
inline constexpr const char* kLammpsLog = "log.lammps";
inline constexpr const char* kExportCase = "case.toml";
inline constexpr const char* kExportManifest = "export.txt";

/// @brief Why LAMMPS cannot run @p c the way grainlift does ("" when it can).
std::string lammps_unsupported(const Case& c);

/// @brief Write @p bed, @p walls and the intruder of @p cfg as a LAMMPS data file (atom_style
/// sphere; type 1 grains, 2 frozen wall disks, 3 the intruder, which is the last atom) under
/// the title line @p title. Returns false when the file cannot be written.
bool write_lammps_data(const std::string& path, const std::string& title, const DemConfig& cfg,
                       const PackedBed& bed, const std::vector<Disk>& walls);

/// What export_lammps wrote.
struct LammpsExport {
  std::size_t grains = 0, walls = 0;
  double area_fraction = 0;
  bool packing_from_cache = false;
  long long steps = 0;  ///< steps of the whole travel
};

/// @brief Prepare (or reuse) the bed of @p c and write <dir>/in.grainlift, bed.data,
/// case.toml (the case verbatim) and export.txt (its path and overrides). Throws InputError
/// for a case LAMMPS cannot reproduce (lammps_unsupported) or a folder that cannot be written.
LammpsExport export_lammps(const Case& c, const std::string& dir);

/// @brief The case an exported folder was made from (case.toml with export.txt's overrides);
/// throws InputError when the folder is not an export or the case has changed.
Case exported_case(const std::string& dir);

/// @brief The outputs of in.grainlift in @p dir (forces.txt, contacts.dump, log.lammps) as the
/// DEM result of @p c: forces, block means, surface stresses and histograms by the DEM's
/// post-processing. Throws InputError for missing or malformed files.
RunResult import_lammps(const Case& c, const std::string& dir);

}  // namespace grainlift::dem
