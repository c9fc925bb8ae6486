// The engine of a case (system_setup.h).
#include "grainlift/dem/system/system_setup.h"

namespace grainlift::dem {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

PeriodicBox box_of(const DemConfig& c) {
  PeriodicBox b;
  b.xmin = c.xmin;
  b.xmax = c.xmax;
  b.ymin = c.ymin;
  b.ymax = c.ymax;
  b.periodic_x = c.periodic_x;
  b.periodic_y = c.periodic_y;
  return b;
}

SystemOptions system_options(const DemConfig& c) {
  SystemOptions o;
  o.box = box_of(c);
  o.contact = c.contact;
  o.dt = c.dt;
  o.threads = c.threads;
  o.gravity = c.gravity;
  o.sort_every = c.sort_every;
  return o;
}

std::vector<Disk> grain_disks(const DemConfig& c, const std::vector<double>& x,
                              const std::vector<double>& y, const std::vector<double>& r) {
  std::vector<Disk> g(r.size());
  for (std::size_t n = 0; n < r.size(); ++n) {
    g[n].x = x[n];
    g[n].y = y[n];
    g[n].r = r[n];
    g[n].mass = c.density * kPi * r[n] * r[n];
  }
  return g;
}

std::unique_ptr<DemSystem> system_on_bed(const DemConfig& c, const PackedBed& bed) {
  auto s = std::make_unique<DemSystem>(system_options(c));
  s->set_bodies(grain_disks(c, bed.x, bed.y, bed.r), make_wall_disks(c));
  return s;
}

}  // namespace grainlift::dem
