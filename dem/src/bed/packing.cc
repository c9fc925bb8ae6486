// Bed preparation (Kumar 2019 Sec. II, with a faster compression, see docs/dem-model.md):
//   Phi < 0.5            random sequential insertion at full size (no overlap);
//   Phi > 0.78           insertion at reduced radii (Phi_0 = 0.3), then frictionless radius
//                        growth to the target (a soft compression replacing slow wall motion);
//   0.5 <= Phi <= 0.78   the same to Phi = 0.78, then random removal of grains.
// Each bed is relaxed (intruder at rest, friction on, extra viscous drag) until the mean
// kinetic energy per grain falls below relax_ke_per_grain.
#include "grainlift/dem/bed/packing.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <fstream>
#include <numeric>
#include <random>
#include <sstream>
#include <tuple>
#include <utility>

#include "grainlift/dem/errors.h"
#include "grainlift/shared/machine/memory.h"
#include "grainlift/dem/system/system_setup.h"
#include "bed/packing_cache.h"
#include "step/row_order.h"
#include "system/fnv1a.h"

namespace grainlift::dem {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInsertPhi = 0.3;       // area fraction of the reduced-radius insertion
constexpr double kGrowthPerStep = 2e-5;  // radius growth per step, in mean diameters
constexpr long kMaxRelaxSteps = 400000;
// area fraction of the full-size insertion of the wall compression (random sequential
// insertion of these disks jams near 0.55)
constexpr double kWallInsertPhi = 0.45;
// The frictionless relaxation after the radius growth stops at max(relax_ke, this) (J per grain):
// it only has to let the compressed packing find a force balance. Below it, a frictionless bed
// under gravity keeps creeping and its kinetic energy decays ~10 times slower than with friction
// (docs/dem-model.md); the frictional relaxation then goes down to relax_ke.
constexpr double kFrictionlessRelaxKe = 1e-9;

double frictionless_relax_ke(const DemConfig& c) {
  return std::max(c.relax_ke_per_grain, kFrictionlessRelaxKe);
}

double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

struct Region {
  double x0, x1, y0, y1;
};

Region grain_region(const DemConfig& c) {
  const double d = c.grain_diameter;
  return {c.xmin + (c.wall_left ? d : 0.0), c.xmax - (c.wall_right ? d : 0.0),
          c.ymin + (c.wall_bottom ? d : 0.0), c.ymax - (c.wall_top ? d : 0.0)};
}

/// Random sequential insertion of disks of radii r (in the given order) with no overlap
/// with each other, the intruder or the walls. Returns false when a disk found no place.
bool insert_randomly(const DemConfig& c, const std::vector<double>& r, std::mt19937_64& rng,
                     std::vector<double>& x, std::vector<double>& y) {
  const PeriodicBox box = box_of(c);
  const Region reg = grain_region(c);
  const double rmax = *std::max_element(r.begin(), r.end());
  const double cell = 2 * rmax;
  const int ncx = std::max(1, static_cast<int>((c.xmax - c.xmin) / cell));
  const int ncy = std::max(1, static_cast<int>((c.ymax - c.ymin) / cell));
  const double hx = (c.xmax - c.xmin) / ncx, hy = (c.ymax - c.ymin) / ncy;
  std::vector<std::vector<int>> cells(static_cast<std::size_t>(ncx) * ncy);
  const double ix = c.intruder_position[0], iy = c.intruder_position[1];
  const double ir = 0.5 * c.intruder_diameter;
  x.assign(r.size(), 0.0);
  y.assign(r.size(), 0.0);
  for (std::size_t n = 0; n < r.size(); ++n) {
    const double rn = r[n];
    bool placed = false;
    for (int attempt = 0; attempt < 20000 && !placed; ++attempt) {
      const double px = c.periodic_x && !c.wall_left && !c.wall_right
                            ? c.xmin + uniform01(rng) * (c.xmax - c.xmin)
                            : reg.x0 + rn + uniform01(rng) * (reg.x1 - reg.x0 - 2 * rn);
      const double py = c.periodic_y && !c.wall_bottom && !c.wall_top
                            ? c.ymin + uniform01(rng) * (c.ymax - c.ymin)
                            : reg.y0 + rn + uniform01(rng) * (reg.y1 - reg.y0 - 2 * rn);
      double dx = px - ix, dy = py - iy;
      box.min_image(dx, dy);
      if (ir > 0 && dx * dx + dy * dy < (ir + rn) * (ir + rn)) continue;  // D = 0: no intruder
      const int cx = std::min(ncx - 1, std::max(0, static_cast<int>((px - c.xmin) / hx)));
      const int cy = std::min(ncy - 1, std::max(0, static_cast<int>((py - c.ymin) / hy)));
      bool free = true;
      for (int oy = -1; oy <= 1 && free; ++oy) {
        int ky = cy + oy;
        if (ky < 0 || ky >= ncy) {
          if (!c.periodic_y) continue;
          ky = (ky + ncy) % ncy;
        }
        for (int ox = -1; ox <= 1 && free; ++ox) {
          int kx = cx + ox;
          if (kx < 0 || kx >= ncx) {
            if (!c.periodic_x) continue;
            kx = (kx + ncx) % ncx;
          }
          for (int m : cells[static_cast<std::size_t>(ky) * ncx + kx]) {
            double ex = px - x[m], ey = py - y[m];
            box.min_image(ex, ey);
            if (ex * ex + ey * ey < (rn + r[m]) * (rn + r[m])) {
              free = false;
              break;
            }
          }
        }
      }
      if (!free) continue;
      x[n] = px;
      y[n] = py;
      cells[static_cast<std::size_t>(cy) * ncx + cx].push_back(static_cast<int>(n));
      placed = true;
    }
    if (!placed) return false;
  }
  return true;
}

/// Run with drag until the mean kinetic energy per grain is below ke_per_grain (J).
void relax(DemSystem& s, double ke_per_grain, double damping_rate) {
  s.set_background_damping(damping_rate);
  const int n = std::max(1, s.grains());
  for (long k = 0; k < kMaxRelaxSteps; ++k) {
    s.step();
    if (k % 100 == 99 && s.kinetic_energy() / n < ke_per_grain) break;
  }
}

void read_back(const DemSystem& s, std::vector<double>& x, std::vector<double>& y,
               std::vector<double>& r) {
  const auto& p = s.particles();
  x.assign(p.x.begin(), p.x.begin() + s.grains());
  y.assign(p.y.begin(), p.y.begin() + s.grains());
  r.assign(p.r.begin(), p.r.begin() + s.grains());
}

/// Reorders the grains (x, y, r together) into rows of cells one diameter wide, bottom row
/// first, x order within a row: the memory order the neighbour list and the threads' slabs
/// of rows want (docs/dem-model.md).
void sort_into_rows(const DemConfig& c, std::vector<double>& x, std::vector<double>& y,
                    std::vector<double>& r) {
  const std::vector<int> order = detail::rows_of_cells_order(
      x.data(), y.data(), static_cast<int>(r.size()), c.xmin, c.xmax - c.xmin, c.ymin,
      c.grain_diameter);
  for (std::vector<double>* v : {&x, &y, &r}) {
    std::vector<double> sorted(v->size());
    for (std::size_t k = 0; k < order.size(); ++k)
      sorted[k] = (*v)[static_cast<std::size_t>(order[k])];
    v->swap(sorted);
  }
}

/// Kumar 2019 Sec. II's dense bed: the grains (radii @p r, full size) inserted at random in a
/// box taller than @p c's, at area fraction kWallInsertPhi, then both walls close at
/// c.compression_speed each, symmetrically about the box's centre line, to their places in
/// @p c while the bed relaxes (frictionless: with friction a bed closed to Phi 0.8 jams, 3
/// contacts per grain and 40x the drag, where Kumar's D ~ V0^2 with D_0 ~ 0 says theirs did
/// not; the preparation's drag; the intruder at rest). Returns the positions in @p x, @p y;
/// @p r comes back in the grains' new order (sorted into rows after the insertion).
void compress_with_wall(const DemConfig& c, std::vector<double>& r, std::mt19937_64& rng,
                        std::vector<double>& x, std::vector<double>& y,
                        const std::function<void(double)>& report) {
  if (!c.wall_top || !c.wall_bottom || c.periodic_y || c.wall_left || c.wall_right)
    throw ConfigError("dem.preparation = \"wall_compression\" closes the bottom and top walls: "
                      "it needs both, no side walls and a box not periodic in y");
  if (!(c.compression_speed > 0)) throw ConfigError("compression_speed must be > 0");
  double grains_area = 0;
  for (double v : r) grains_area += kPi * v * v;
  DemConfig tall = c;
  const double width = grain_region(c).x1 - grain_region(c).x0;
  const double extra = (grains_area / kWallInsertPhi - accessible_area(c)) / width;
  tall.ymin = c.ymin - 0.5 * std::max(0.0, extra);
  tall.ymax = c.ymax + 0.5 * std::max(0.0, extra);
  if (!insert_randomly(tall, r, rng, x, y)) {
    std::ostringstream m;
    m << "random insertion of " << r.size() << " grains at full size failed in the "
      << "compression box (area fraction " << kWallInsertPhi << ")";
    throw ConfigError(m.str());
  }
  // Grains in rows, as in a prepared bed: in insertion order neighbours lie anywhere in
  // memory and every pair crosses the threads' slabs.
  sort_into_rows(tall, x, y, r);
  DemSystem s(system_options(tall));
  const std::vector<Disk> walls = make_wall_disks(tall);
  s.set_bodies(grain_disks(c, x, y, r), walls);
  if (c.intruder_diameter > 0)
    s.set_intruder(c.intruder_position[0], c.intruder_position[1], 0.5 * c.intruder_diameter, 0,
                   0, 0, 0);
  s.set_friction(0, 0);
  // With the drag, a grain pushed by a wall stops within ~v/rate (1 mm at 0.2 m/s): the walls
  // build dense layers while the centre keeps the insertion's area fraction (a channel along
  // the intruder's path, docs/results-kumar2019.md section 7); without it the pushed grains
  // carry the compression inwards.
  s.set_background_damping(c.compression_drag ? 1.0 / (2000.0 * c.dt) : 0.0);
  // the bottom and top rows of wall disks, as indices among all bodies (grains first)
  const auto [b0, b1] = wall_row(walls, tall.ymin + 0.5 * c.grain_diameter);
  const auto [t0, t1] = wall_row(walls, tall.ymax - 0.5 * c.grain_diameter);
  const double drop = tall.ymax - c.ymax;
  const long steps =
      std::max(1L, static_cast<long>(std::ceil(drop / (c.compression_speed * c.dt))));
  const double dy = drop / static_cast<double>(steps);
  // a move before every step: the first here, the others inside advance() (same bits)
  for (const auto& [lo, hi, sign] : {std::tuple{b0, b1, 1.0}, std::tuple{t0, t1, -1.0}}) {
    s.move_frozen(s.grains() + lo, s.grains() + hi, 0.0, sign * dy, 0.0, sign * dy / c.dt);
    s.drive_frozen(s.grains() + lo, s.grains() + hi, 0.0, sign * dy, 0.0, sign * dy / c.dt,
                   steps - 1);
  }
  const long chunk = std::max(1L, steps / 20);
  for (long k = 0; k < steps; k += chunk) {
    report(0.6 * static_cast<double>(k) / steps);
    s.advance(std::min(chunk, steps - k));
  }
  std::vector<double> rr;
  read_back(s, x, y, rr);
}

void hash_bytes(std::uint64_t& h, const void* data, std::size_t n) {
  h = detail::fnv1a(data, n, h);
}
template <class T>
void hash_value(std::uint64_t& h, T v) {
  hash_bytes(h, &v, sizeof(v));
}

/// Soft compression: frictionless radius growth by the factor @p growth with drag (rate
/// @p damping), then the exact radii @p r put back and the bed relaxed without friction;
/// the grains' centres into @p x, @p y. Reports progress up to 0.6.
void grow_radii(const DemConfig& c, DemSystem& s, const std::vector<Disk>& walls,
                const std::vector<double>& r, double growth, double damping,
                const std::function<void(double)>& report, std::vector<double>& x,
                std::vector<double>& y) {
  s.set_friction(0, 0);
  s.set_background_damping(damping);
  const long steps =
      std::max(1000L, static_cast<long>(std::ceil((growth - 1.0) * 0.5 / kGrowthPerStep)));
  const double f = std::pow(growth, 1.0 / static_cast<double>(steps));
  for (long k = 0; k < steps; ++k) {
    s.scale_grain_radii(f);
    s.step();
    if (k % std::max(1L, steps / 20) == 0) report(0.6 * k / steps);
  }
  std::vector<double> rr;
  read_back(s, x, y, rr);
  s.set_bodies(grain_disks(c, x, y, r), walls);  // exact final radii
  s.set_friction(0, 0);
  relax(s, frictionless_relax_ke(c), damping);
  s.set_friction(c.contact.friction, c.contact.intruder_friction);
}

/// Random removal of grains (a shuffled order) until their total area is at most
/// @p target_area (m^2); the kept grains in their order into @p x, @p y, @p r.
void remove_down_to(double target_area, std::mt19937_64& rng,
                    std::vector<double>& x, std::vector<double>& y, std::vector<double>& r) {
  std::vector<std::size_t> order(r.size());
  std::iota(order.begin(), order.end(), 0);
  for (std::size_t k = order.size(); k > 1; --k) {
    std::swap(order[k - 1], order[static_cast<std::size_t>(uniform01(rng) * k) % k]);
  }
  double total = 0;
  for (double v : r) total += kPi * v * v;
  std::vector<char> keep(r.size(), 1);
  for (std::size_t k = 0; k < order.size() && total > target_area; ++k) {
    keep[order[k]] = 0;
    total -= kPi * r[order[k]] * r[order[k]];
  }
  std::vector<double> x2, y2, r2;
  for (std::size_t n = 0; n < r.size(); ++n) {
    if (keep[n]) {
      x2.push_back(x[n]);
      y2.push_back(y[n]);
      r2.push_back(r[n]);
    }
  }
  x = std::move(x2);
  y = std::move(y2);
  r = std::move(r2);
}

/// Measured with `grainlift run cases/demo/demo.toml --solver dem` at grains.diameter 0.005 and
/// 0.0025 (15,000 and 61,000 grains, packed without the cache): the peak resident memory grows
/// by 590-720 bytes per grain over the program's own; twice that is asked for.
constexpr double kBedBytesPerGrain = 1500;

/// Refuses a bed that cannot fit in what the process may still take (RunFailure, exit 1),
/// before any of it is allocated.
void check_bed_memory(long grains) {
  const std::string shortfall =
      memory_shortfall("the bed of " + std::to_string(grains) + " grains (1.5 kB per grain)",
                       kBedBytesPerGrain * grains);
  if (!shortfall.empty())
    throw RunFailure("not enough memory: " + shortfall +
                     "; ways out: a smaller domain, larger grains, or a machine with more "
                     "memory");
}

}  // namespace

double accessible_area(const DemConfig& c) {
  const Region reg = grain_region(c);
  const double ri = 0.5 * c.intruder_diameter;
  return (reg.x1 - reg.x0) * (reg.y1 - reg.y0) - kPi * ri * ri;
}

std::vector<Disk> make_wall_disks(const DemConfig& c) {
  std::vector<Disk> w;
  const double d = c.grain_diameter, r = 0.5 * d;
  auto row = [&](double x0, double x1, double y, bool along_x) {
    const int n = std::max(1, static_cast<int>(std::lround((x1 - x0) / d)));
    const double h = (x1 - x0) / n;
    for (int k = 0; k < n; ++k) {
      Disk disk;
      disk.r = r;
      const double s = x0 + (k + 0.5) * h;
      disk.x = along_x ? s : y;
      disk.y = along_x ? y : s;
      w.push_back(disk);
    }
  };
  if (c.wall_bottom) row(c.xmin, c.xmax, c.ymin + r, true);
  if (c.wall_top) row(c.xmin, c.xmax, c.ymax - r, true);
  const double y0 = c.ymin + (c.wall_bottom ? d : 0.0), y1 = c.ymax - (c.wall_top ? d : 0.0);
  if (c.wall_left) row(y0, y1, c.xmin + r, false);
  if (c.wall_right) row(y0, y1, c.xmax - r, false);
  return w;
}

std::pair<int, int> wall_row(const std::vector<Disk>& walls, double y) {
  int first = -1, last = -1;
  for (int k = 0; k < static_cast<int>(walls.size()); ++k) {
    if (walls[k].y != y) continue;
    if (first < 0) first = k;
    last = k + 1;
  }
  return {first, last};
}

std::uint64_t packing_hash(const DemConfig& c) {
  std::uint64_t h = detail::kFnvOffset;
  const char version[] = "grainlift-dem-packing-v2";
  hash_bytes(h, version, sizeof version);
  for (double v : {c.xmin, c.xmax, c.ymin, c.ymax, c.gravity[0], c.gravity[1], c.grain_diameter,
                   c.polydispersity, c.density, c.area_fraction, c.contact.kn, c.contact.kt,
                   c.contact.gamma_n, c.contact.gamma_t, c.contact.youngs_modulus,
                   c.contact.poisson_ratio, c.contact.restitution, c.contact.friction,
                   c.contact.intruder_friction, c.intruder_diameter, c.intruder_position[0],
                   c.intruder_position[1], c.dt, c.relax_ke_per_grain}) {
    hash_value(h, v);
  }
  for (bool b : {c.periodic_x, c.periodic_y, c.wall_bottom, c.wall_top, c.wall_left,
                 c.wall_right}) {
    hash_value(h, static_cast<unsigned char>(b));
  }
  hash_value(h, static_cast<int>(c.contact.law));
  hash_value(h, c.seed);
  // radius-growth beds keep the key they had before the choice existed
  if (c.preparation == Preparation::wall_compression) {
    const char stage[] = "wall-compression-both-walls-frictionless-rows";
    hash_bytes(h, stage, sizeof stage);
    hash_value(h, c.compression_speed);
    if (!c.compression_drag) {  // beds closed under the drag keep their key
      const char free[] = "no-drag";
      hash_bytes(h, free, sizeof free);
    }
  }
  // Beds made with relax_ke >= kFrictionlessRelaxKe keep their key (their preparation did not
  // change); below it the frictionless stage stops earlier than it used to: a new key.
  if (frictionless_relax_ke(c) != c.relax_ke_per_grain) {
    const char stage[] = "frictionless-relax-ke";
    hash_bytes(h, stage, sizeof stage);
    hash_value(h, frictionless_relax_ke(c));
  }
  return h;
}

std::string packing_cache_path(const DemConfig& c) {
  if (c.packing_cache_dir.empty()) return {};
  char name[32];
  std::snprintf(name, sizeof name, "%016llx.bin",
                static_cast<unsigned long long>(packing_hash(c)));
  return (std::filesystem::path(c.packing_cache_dir) / name).string();
}

PackedBed prepare_packing(const DemConfig& c, const ProgressCallback& progress) {
  const std::string cache = packing_cache_path(c);
  const std::uint64_t hash = packing_hash(c);
  PackedBed bed;
  if (!cache.empty()) {
    const detail::CacheRead read = detail::load_packing(cache, hash, bed);
    if (read.found) return bed;
    bed.cache_note = read.note;
  }

  const double phi = c.area_fraction;
  if (!(phi > 0 && phi <= 0.9)) {
    std::ostringstream m;
    m << "area_fraction = " << phi << " is outside the range the packing can make, (0, 0.9]";
    throw ConfigError(m.str());
  }
  const double area = accessible_area(c);
  const double d = c.grain_diameter, p = c.polydispersity;
  const double mean_area = 0.25 * kPi * d * d * (1 + p * p / 3);
  const double phi_pack = phi < 0.5 ? phi : std::max(phi, 0.78);
  const long n_pack = std::lround(phi_pack * area / mean_area);
  if (n_pack < 1) throw ConfigError("the box holds no grain at this area fraction");
  check_bed_memory(n_pack);
  std::mt19937_64 rng(c.seed);
  std::vector<double> r(n_pack);
  for (auto& v : r) v = 0.5 * d * (1 + p * (2 * uniform01(rng) - 1));
  auto report = [&](double f) {
    if (progress) progress(f, "packing");
  };
  report(0);

  std::vector<double> x, y;
  const bool direct = phi_pack < 0.4;
  const bool closing_wall = !direct && c.preparation == Preparation::wall_compression;
  if (closing_wall) {
    compress_with_wall(c, r, rng, x, y, report);
  }
  const double shrink = direct ? 1.0 : std::sqrt(kInsertPhi / phi_pack);
  std::vector<double> r_ins(r);
  for (auto& v : r_ins) v *= shrink;
  if (!closing_wall && !insert_randomly(c, r_ins, rng, x, y)) {
    std::ostringstream m;
    m << "random insertion of " << n_pack << " grains failed (area fraction "
      << phi_pack * shrink * shrink << " in an accessible area of " << area << " m^2)";
    throw ConfigError(m.str());
  }

  DemSystem s(system_options(c));
  const std::vector<Disk> walls = make_wall_disks(c);
  s.set_bodies(grain_disks(c, x, y, closing_wall ? r : r_ins), walls);
  if (c.intruder_diameter > 0) {  // 0: a bed without an intruder (the shear cell)
    s.set_intruder(c.intruder_position[0], c.intruder_position[1], 0.5 * c.intruder_diameter, 0,
                   0, 0, 0);
  }
  // Drag rate ~ the lowest collective frequencies of the bed: stronger drag over-damps them
  // and relaxation slows down (1/(200 dt) was 7x slower than 1/(2000 dt) at Phi 0.82).
  const double damping = 1.0 / (2000.0 * c.dt);
  if (closing_wall) {
    // the compressed bed finds its force balance without friction, as after a radius growth
    s.set_friction(0, 0);
    relax(s, frictionless_relax_ke(c), damping);
    s.set_friction(c.contact.friction, c.contact.intruder_friction);
  } else if (!direct) {
    grow_radii(c, s, walls, r, 1.0 / shrink, damping, report, x, y);
  }
  report(0.7);
  relax(s, c.relax_ke_per_grain, damping);
  read_back(s, x, y, r);

  if (phi < phi_pack) {
    remove_down_to(phi * area, rng, x, y, r);
    s.set_bodies(grain_disks(c, x, y, r), walls);
    relax(s, c.relax_ke_per_grain, damping);
    read_back(s, x, y, r);
  }
  report(0.95);

  sort_into_rows(c, x, y, r);
  bed.x = std::move(x);
  bed.y = std::move(y);
  bed.r = std::move(r);
  double total = 0;
  for (double v : bed.r) total += kPi * v * v;
  bed.area_fraction = total / area;
  if (!cache.empty()) {
    const std::string note = detail::save_packing(cache, hash, bed);
    if (!note.empty()) bed.cache_note += (bed.cache_note.empty() ? "" : "; ") + note;
  }
  report(1);
  return bed;
}

}  // namespace grainlift::dem
