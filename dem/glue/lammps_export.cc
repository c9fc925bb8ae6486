// `grainlift export lammps`: a case as a LAMMPS input (lammps_bridge.h, docs/lammps.md).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "grainlift/dem/dem_solver.h"
#include "grainlift/dem/lammps_bridge.h"
#include "grainlift/dem/scenes/simulation.h"
#include "grainlift/shared/results/atomic_file.h"
#include "grainlift/shared/case/case_loader.h"
#include "grainlift/shared/errors.h"
#include "grainlift/shared/run/run_driver.h"

namespace grainlift::dem {
namespace {

/// Shortest of %.15g / %.17g that reads back as @p v.
std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.15g", v);
  if (std::strtod(buf, nullptr) != v) std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

/// Tsuji et al.'s damping prefactor alpha(e) as LAMMPS's `damping tsuji` computes it from the
/// restitution coefficient it is given (pair granular, 29 Sep 2021).
double tsuji_alpha(double e) {
  const double p[] = {1.2728, -4.2783, 11.087, -22.348, 27.467, -18.022, 4.8218};
  double a = 0, x = 1;
  for (double c : p) {
    a += c * x;
    x *= e;
  }
  return a;
}

/// The e to hand LAMMPS's `damping tsuji` so that its prefactor alpha equals Guillard's
/// sqrt(5) |beta(e_case)| (contact_law.h): bisection, alpha decreasing on [0, 1]; NaN when no
/// e in [0, 1] gives it.
double tsuji_input_for(double restitution) {
  const double l = std::log(restitution);
  const double target = std::sqrt(5.0) * std::abs(l) / std::sqrt(l * l + M_PI * M_PI);
  double lo = 0, hi = 1;
  if (!(tsuji_alpha(lo) >= target && tsuji_alpha(hi) <= target)) return std::nan("");
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    (tsuji_alpha(mid) > target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path + ": cannot read");
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

}  // namespace

std::string lammps_unsupported(const Case& cs) {
  if (!(cs.intruder.diameter > 0)) return "no intruder (intruder.diameter = 0)";
  if (!(std::hypot(cs.intruder.velocity[0], cs.intruder.velocity[1]) > 0))
    return "the intruder does not move (intruder.velocity = [0, 0]): drag and lift need V";
  if (cs.domain.lid_pressure > 0)
    return "domain.lid_pressure > 0: grainlift's pressure-controlled lid (one rigid body with "
           "its own mass and damping) has no LAMMPS fix that reproduces it here; use a fixed "
           "top wall or gravity";
  if (cs.intruder.spin_ramp_time > 0)
    return "intruder.spin_ramp_time > 0: the exported intruder spins at omega from the start";
  if (cs.intruder.friction != cs.grains.friction)
    return "intruder.friction differs from grains.friction (the export gives every pair one mu)";
  if (cs.grains.contact.law == "guillard2014" &&
      std::isnan(tsuji_input_for(cs.grains.contact.restitution)))
    return "grains.contact.restitution: no `damping tsuji` input reproduces Guillard's damping";
  const auto& d = cs.domain;
  if (!d.periodic[0] && !(d.wall_left && d.wall_right))
    return "a side of the box that is neither periodic nor walled in x";
  if (!d.periodic[1] && !d.wall_bottom)
    return "no bottom wall and no periodicity in y";
  return {};
}

bool write_lammps_data(const std::string& path, const std::string& title, const DemConfig& c,
                       const PackedBed& bed, const std::vector<Disk>& walls) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return false;
  const std::size_t n = bed.r.size() + walls.size() + 1;
  std::fprintf(f, "%s\n\n%zu atoms\n3 atom types\n\n", title.c_str(), n);
  std::fprintf(f, "%.17g %.17g xlo xhi\n%.17g %.17g ylo yhi\n-0.01 0.01 zlo zhi\n\n", c.xmin,
               c.xmax, c.ymin, c.ymax);
  // the density column is a placeholder: the script sets the masses with set density/disc
  std::fprintf(f, "Atoms # sphere\n\n");
  std::size_t id = 1;
  for (std::size_t k = 0; k < bed.r.size(); ++k)
    std::fprintf(f, "%zu 1 %.17g 1000 %.17g %.17g 0\n", id++, 2 * bed.r[k], bed.x[k], bed.y[k]);
  for (const auto& w : walls)
    std::fprintf(f, "%zu 2 %.17g 1000 %.17g %.17g 0\n", id++, 2 * w.r, w.x, w.y);
  std::fprintf(f, "%zu 3 %.17g 1000 %.17g %.17g 0\n", id, c.intruder_diameter,
               c.intruder_position[0], c.intruder_position[1]);
  return std::fclose(f) == 0;
}

namespace {

/// The script's opening comment: where it comes from, the bed, the run, how to use it.
void add_header(const Case& cs, const DemConfig& c, const LammpsExport& ex, bool bed_from_cache,
                double speed, std::string& s) {
  auto line = [&s](const std::string& l) { s += l + "\n"; };
  line(fmt::format("# grainlift case {} (hash {}), exported by grainlift {} ({})", cs.source.path,
                   cs.source.hash, grainlift_version(), grainlift_git_revision()));
  line(fmt::format("# bed: {} grains, {} frozen wall disks, area fraction {:.6f} (packing {})",
                   ex.grains, ex.walls, ex.area_fraction,
                   bed_from_cache ? "reused from grainlift's cache" : "prepared"));
  line(fmt::format("# {} steps of {} s: {} d of travel at |V| = {} m/s", ex.steps, num(c.dt),
                   num(c.travel), num(speed)));
  line("# Run it here:   lmp -in in.grainlift          (or: mpirun -np N lmp -in in.grainlift)");
  line("# then:          grainlift import lammps THIS_FOLDER --out OUT");
  line("# Types: 1 grains, 2 frozen wall disks, 3 the intruder (the last atom). Every number is");
  line("# the case's; docs/lammps.md maps each and says what differs from grainlift's DEM.");
  line("");
}

/// The pair style of the case's contact law (docs/lammps.md maps each parameter).
void add_pair_style(const ContactParams& contact, std::string& s) {
  auto line = [&s](const std::string& l) { s += l + "\n"; };
  const ContactParams& k = contact;
  if (k.law == ContactLaw::kumar2019) {
    line("# Kumar 2019 eq. (1)-(2): Kn Kt gamma_n gamma_t mu, damping scaled by m_eff (flag 1)");
    line(fmt::format("pair_style      gran/hertz/history {} {} {} {} {} 1", num(k.kn), num(k.kt),
                     num(k.gamma_n), num(k.gamma_t), num(k.friction)));
    line("pair_coeff      * *");
  } else {
    const double nu = k.poisson_ratio;
    line(fmt::format(
        "# Guillard 2014 Table I (E = {} Pa, nu = {}, e = {}): Hertz-Mindlin from E, nu;",
        num(k.youngs_modulus), num(nu), num(k.restitution)));
    line(
        "# `damping tsuji` is handed the e whose alpha is sqrt(5)|beta(e_case)|, and the "
        "tangential");
    line("# damping is sqrt(2(1-nu)/(2-nu)) of the normal one (docs/lammps.md)");
    line("pair_style      granular");
    line(fmt::format("pair_coeff      * * hertz/material {} {} {} tangential mindlin NULL {} {} "
                     "damping tsuji",
                     num(k.youngs_modulus), num(tsuji_input_for(k.restitution)), num(nu),
                     num(std::sqrt(2 * (1 - nu) / (2 - nu))), num(k.friction)));
  }
}

/// The dump of the intruder's contacts: every pair within touching distance in a disk round it
/// (and its periodic images).
void add_contact_dump(const DemConfig& c, double rgrain, std::size_t intruder_id, std::string& s) {
  auto line = [&s](const std::string& l) { s += l + "\n"; };
  const double lx = c.xmax - c.xmin, ly = c.ymax - c.ymin;
  line("# the intruder's contacts: every pair within touching distance in a disk round it (and");
  line("# its periodic images); grainlift import keeps the intruder's own");
  line(fmt::format("variable        xi equal x[{}]", intruder_id));
  line(fmt::format("variable        yi equal y[{}]", intruder_id));
  const double reach = 0.5 * c.intruder_diameter + 2.05 * rgrain;
  std::vector<std::string> names;
  const int nx = c.periodic_x ? 1 : 0, ny = c.periodic_y ? 1 : 0;
  for (int a = -nx; a <= nx; ++a) {
    for (int b = -ny; b <= ny; ++b) {
      const std::string n = fmt::format("near{}", names.size());
      if (a != 0 || b != 0) {
        line(fmt::format("variable        {}x equal v_xi+{}", n, num(a * lx)));
        line(fmt::format("variable        {}y equal v_yi+{}", n, num(b * ly)));
        line(fmt::format("region          {} cylinder z 0 0 {} INF INF move v_{}x v_{}y NULL "
                         "units box",
                         n, num(reach), n, n));
      } else {
        line(fmt::format("region          {} cylinder z 0 0 {} INF INF move v_xi v_yi NULL "
                         "units box",
                         n, num(reach)));
      }
      names.push_back(n);
    }
  }
  if (names.size() == 1) {
    line("region          near union 1 near0");
  } else {
    std::string u;
    for (const auto& n : names) u += " " + n;
    line(fmt::format("region          near union {}{}", names.size(), u));
  }
  line("group           near dynamic all region near every ${every}");
  line("compute         ids near property/local patom1 patom2 cutoff radius");
  line("compute         pairs near pair/local dist fx fy force p1 p2 p4 cutoff radius");
  line(fmt::format("dump            contacts all local ${{every}} {} c_ids[1] c_ids[2] c_pairs[1] "
                   "c_pairs[2] c_pairs[3] c_pairs[4] c_pairs[5] c_pairs[6] c_pairs[7]",
                   kLammpsContacts));
  line("dump_modify     contacts format float %.15g");
}

/// The folder's manifest: the case it was exported from, for `grainlift import lammps`.
void write_manifest(const Case& cs, const LammpsExport& ex, const std::string& dir) {
  std::string manifest =
      "# grainlift export lammps: the case of this folder, for `grainlift import lammps`\n";
  manifest += "case_path " + cs.source.path + "\n";
  manifest += "case_hash " + cs.source.hash + "\n";
  for (const auto& o : cs.source.overrides) manifest += "override " + o + "\n";
  manifest += fmt::format(
      "grains {}\nwalls {}\narea_fraction {}\npacking_from_cache {}\nsteps {}\n", ex.grains,
      ex.walls, num(ex.area_fraction), ex.packing_from_cache ? 1 : 0, ex.steps);
  write_text_atomically(dir + "/" + kExportManifest, manifest);
}

}  // namespace

LammpsExport export_lammps(const Case& cs, const std::string& dir) {
  const std::string why = lammps_unsupported(cs);
  if (!why.empty())
    throw InputError(fmt::format("{}: LAMMPS cannot run this case as grainlift does: {}",
                                 cs.source.path, why));
  const DemConfig c = make_dem_config(cs, 1);
  const PackedBed bed = prepare_packing(packing_config(c));
  const std::vector<Disk> walls = make_wall_disks(c);
  make_directories(dir);

  LammpsExport ex;
  ex.grains = bed.r.size();
  ex.walls = walls.size();
  ex.area_fraction = bed.area_fraction;
  ex.packing_from_cache = bed.from_cache;
  const double speed = std::hypot(c.intruder_velocity[0], c.intruder_velocity[1]);
  ex.steps = travel_steps(c);
  double rmax = 0, rgrain = 0;
  for (double r : bed.r) rgrain = std::max(rgrain, r);
  rmax = rgrain;
  for (const auto& w : walls) rmax = std::max(rmax, w.r);
  const std::size_t intruder_id = ex.grains + ex.walls + 1;

  const std::string data_tmp = temporary_path_for(dir + "/" + kLammpsData);
  if (!write_lammps_data(data_tmp,
                         fmt::format("grainlift case {}, {} grains, Phi = {:.6f}", cs.source.path,
                                     ex.grains, ex.area_fraction),
                         c, bed, walls))
    throw InputError(fmt::format("{}/{}: cannot write", dir, kLammpsData));
  commit_file(data_tmp, dir + "/" + kLammpsData);

  std::string s;
  auto line = [&s](const std::string& l) { s += l + "\n"; };
  add_header(cs, c, ex, bed.from_cache, speed, s);
  line(fmt::format("variable        steps equal {}", ex.steps));
  line(fmt::format("variable        every equal {}", c.sample_every));
  line("");
  line("units           si");
  line("dimension       2");
  auto side = [](bool periodic, bool lo_wall, bool hi_wall) {
    if (periodic) return std::string("p");
    // an open top (a free surface under gravity) grows the box instead of losing grains
    return std::string(lo_wall ? "f" : "m") + (hi_wall ? "f" : "m");
  };
  line(fmt::format("boundary        {} {} p", side(c.periodic_x, c.wall_left, c.wall_right),
                   side(c.periodic_y, c.wall_bottom, c.wall_top)));
  line("atom_style      sphere");
  line("atom_modify     map array");
  line("comm_modify     vel yes");
  line("newton          off");
  line(fmt::format("read_data       {}", kLammpsData));
  line("# disks: m = density pi r^2, I = m r^2 / 2 (nve/sphere disc); the intruder's mass makes");
  line("# m_eff of its contacts the grain's to the last bit (grainlift: a prescribed body)");
  line(fmt::format("set             type 1 density/disc {}", num(c.density)));
  line(fmt::format("set             type 2 density/disc {}", num(c.density)));
  line(fmt::format("set             type 3 density/disc {}", num(c.density * 1e20)));
  line(fmt::format("set             type 3 omega 0.0 0.0 {}", num(c.intruder_omega)));
  line("group           grains type 1");
  line("group           walls type 2");
  line("group           intruder type 3");
  line("");
  add_pair_style(c.contact, s);
  line("");
  line(
      "# skin 0.2 r_max as grainlift's lists; wall disks touch neither each other nor the "
      "intruder");
  line(fmt::format("neighbor        {} bin", num(0.2 * rmax)));
  line("neigh_modify    delay 0 every 1 check yes exclude type 2 2 exclude type 2 3");
  line(fmt::format("timestep        {}", num(c.dt)));
  line("fix             integrate grains nve/sphere disc");
  line("fix             frozen walls freeze");
  line(fmt::format("fix             drive intruder move linear {} {} 0.0",
                   num(c.intruder_velocity[0]), num(c.intruder_velocity[1])));
  line("fix             plane all enforce2d");
  const double g = std::hypot(c.gravity[0], c.gravity[1]);
  if (g > 0)
    line(fmt::format("fix             weight grains gravity {} vector {} {} 0.0", num(g),
                     num(c.gravity[0] / g), num(c.gravity[1] / g)));
  line("");
  line("# force (N/m) and torque (N) of the grains on the intruder at every sample");
  line("compute         fin intruder reduce sum fx fy");
  line("compute         tqa intruder property/atom tqz");
  line("compute         tqin intruder reduce sum c_tqa");
  line("variable        simtime equal time");
  line(fmt::format("fix             samples intruder ave/time ${{every}} 1 ${{every}} v_simtime "
                   "c_fin[1] c_fin[2] c_tqin file {} format \" %.17g\"",
                   kLammpsForces));
  line("");
  add_contact_dump(c, rgrain, intruder_id, s);
  line("");
  line(fmt::format("thermo          {}", std::max<long long>(1, ex.steps / 100)));
  line("thermo_style    custom step atoms ke cpuremain");
  line("run             ${steps}");

  write_text_atomically(dir + "/" + kLammpsScript, s);
  write_text_atomically(dir + "/" + kExportCase, cs.source.text);
  write_manifest(cs, ex, dir);
  return ex;
}

Case exported_case(const std::string& dir) {
  const std::string mpath = dir + "/" + kExportManifest;
  std::ifstream m(mpath);
  if (!m)
    throw InputError(fmt::format("{}: not found: {} is not a folder written by `grainlift export "
                                 "lammps`", mpath, dir));
  std::string path, hash, l;
  std::vector<std::string> overrides;
  while (std::getline(m, l)) {
    const auto sp = l.find(' ');
    if (l.empty() || l[0] == '#' || sp == std::string::npos) continue;
    const std::string key = l.substr(0, sp), value = l.substr(sp + 1);
    if (key == "case_path") path = value;
    else if (key == "case_hash") hash = value;
    else if (key == "override") overrides.push_back(value);
  }
  if (path.empty() || hash.empty())
    throw InputError(mpath + ": no case_path or case_hash line");
  Case c = parse_case(read_text(dir + "/" + kExportCase), path, overrides);
  if (c.source.hash != hash)
    throw InputError(fmt::format("{}/{}: the case's hash is {}, the export's {}: the folder was "
                                 "edited after the export",
                                 dir, kExportCase, c.source.hash, hash));
  return c;
}

}  // namespace grainlift::dem
