// A prepared bed as a LAMMPS data file (atom_style sphere), written once for the benchmark beds
// (export_lammps_bed.cc) and a case's bed (export_lammps_case.cc): type 1 grains, type 2 frozen
// wall disks, type 3 the intruder. Columns: id type diameter density x y z; the density is a
// placeholder, the inputs set the masses with "set ... density/disc".
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "grainlift/dem/dem_config.h"
#include "grainlift/dem/packing.h"

namespace grainlift::bench {

/// @brief Write @p bed, @p walls and the intruder of @p c to @p path under the title line
/// @p title. Returns false when the file cannot be written.
inline bool write_lammps_data(const std::string& path, const std::string& title,
                              const dem::DemConfig& c, const dem::PackedBed& bed,
                              const std::vector<dem::Disk>& walls) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return false;
  const std::size_t n = bed.r.size() + walls.size() + 1;
  std::fprintf(f, "%s\n\n%zu atoms\n3 atom types\n\n", title.c_str(), n);
  std::fprintf(f, "%.17g %.17g xlo xhi\n%.17g %.17g ylo yhi\n-0.01 0.01 zlo zhi\n\n", c.xmin,
               c.xmax, c.ymin, c.ymax);
  std::fprintf(f, "Atoms # sphere\n\n");
  std::size_t id = 1;
  for (std::size_t k = 0; k < bed.r.size(); ++k) {
    std::fprintf(f, "%zu 1 %.17g 1000 %.17g %.17g 0\n", id++, 2 * bed.r[k], bed.x[k], bed.y[k]);
  }
  for (const auto& w : walls) {
    std::fprintf(f, "%zu 2 %.17g 1000 %.17g %.17g 0\n", id++, 2 * w.r, w.x, w.y);
  }
  std::fprintf(f, "%zu 3 %.17g 1000 %.17g %.17g 0\n", id, c.intruder_diameter,
               c.intruder_position[0], c.intruder_position[1]);
  return std::fclose(f) == 0;
}

}  // namespace grainlift::bench
