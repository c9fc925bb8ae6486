// Writes a benchmark bed (same packing as dem_throughput) as a LAMMPS data file for
// bench/lammps/bed.in: type 1 grains, type 2 frozen wall disks, type 3 the intruder.
//   dem_export_lammps_bed <phi> <file.data>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "bench_beds.h"
#include "grainlift/dem/bed/packing.h"
#include "grainlift/dem/lammps_bridge.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s <phi: 0.82, 0.35 or 0.86> <file.data>\n", argv[0]);
    return 2;
  }
  namespace gd = grainlift::dem;
  const gd::DemConfig c = grainlift::bench::bed_config(std::atof(argv[1]));
  const gd::PackedBed bed = gd::prepare_packing(c);
  const auto walls = gd::make_wall_disks(c);
  char title[64];
  std::snprintf(title, sizeof title, "grainlift bed Phi = %.4f", bed.area_fraction);
  if (!grainlift::dem::write_lammps_data(argv[2], title, c, bed, walls)) return 1;
  std::printf("%zu grains, %zu wall disks written to %s\n", bed.r.size(), walls.size(), argv[2]);
  return 0;
}
