// Writes a benchmark bed (same packing as dem_throughput) as a LAMMPS data file for
// bench/lammps/bed.in: type 1 grains, type 2 frozen wall disks, type 3 the intruder.
//   dem_export_lammps_bed <phi> <file.data>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "bench_beds.h"
#include "grainlift/dem/packing.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s <phi: 0.82, 0.35 or 0.86> <file.data>\n", argv[0]);
    return 2;
  }
  namespace gd = grainlift::dem;
  const gd::DemConfig c = grainlift::bench::bed_config(std::atof(argv[1]));
  const gd::PackedBed bed = gd::prepare_packing(c);
  const auto walls = gd::make_wall_disks(c);
  std::FILE* f = std::fopen(argv[2], "w");
  if (!f) return 1;
  const std::size_t n = bed.r.size() + walls.size() + 1;
  std::fprintf(f, "grainlift bed Phi = %.4f\n\n%zu atoms\n3 atom types\n\n", bed.area_fraction, n);
  std::fprintf(f, "%.10g %.10g xlo xhi\n%.10g %.10g ylo yhi\n-0.01 0.01 zlo zhi\n\nAtoms # sphere\n\n",
               c.xmin, c.xmax, c.ymin, c.ymax);
  // columns: id type diameter density x y z; density is mass per volume of the sphere in
  // LAMMPS; bed.in resets it with "set ... density/disc" to Kumar's 20 kg/m^2.
  std::size_t id = 1;
  for (std::size_t k = 0; k < bed.r.size(); ++k) {
    std::fprintf(f, "%zu 1 %.12g 1000 %.12g %.12g 0\n", id++, 2 * bed.r[k], bed.x[k], bed.y[k]);
  }
  for (const auto& w : walls) {
    std::fprintf(f, "%zu 2 %.12g 1000 %.12g %.12g 0\n", id++, 2 * w.r, w.x, w.y);
  }
  std::fprintf(f, "%zu 3 %.12g 1000 %.12g %.12g 0\n", id, c.intruder_diameter,
               c.intruder_position[0], c.intruder_position[1]);
  std::fclose(f);
  std::printf("%zu grains, %zu wall disks written to %s\n", bed.r.size(), walls.size(), argv[2]);
  return 0;
}
