// Writes the bed of a case (the packing `grainlift run` uses, from the same cache) as a LAMMPS
// data file for bench/lammps/production.in, and prints the LAMMPS variables that input needs,
// one "-var name value" line each ("#" lines are notes). Types: 1 grains, 2 frozen wall
// disks, 3 the intruder at its starting position.
//   dem_export_lammps_case CASE OUT.data [--set key=value ...]
// Exit 2 on bad arguments, a bad case, or a case production.in cannot reproduce.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "grainlift/dem/dem_config.h"
#include "grainlift/dem/dem_solver.h"
#include "grainlift/dem/errors.h"
#include "grainlift/dem/bed/packing.h"
#include "grainlift/dem/scenes/simulation.h"
#include "grainlift/shared/case/case_loader.h"
#include "grainlift/shared/errors.h"
#include "grainlift/dem/lammps_bridge.h"

namespace {

namespace gd = grainlift::dem;

constexpr int kBadInput = 2;

int usage(const char* argv0) {
  std::fprintf(stderr, "usage: %s CASE OUT.data [--set key=value ...]\n", argv0);
  return kBadInput;
}

/// Why production.in cannot run this configuration the way grainlift does ("" when it can).
std::string unsupported(const gd::DemConfig& c) {
  if (c.contact.law != gd::ContactLaw::kumar2019)
    return "grains.contact.law is not kumar2019 (only Kumar's law maps onto gran/hertz/history)";
  if (c.lid_pressure > 0) return "domain.lid_pressure > 0 (a pressure-controlled lid)";
  if (c.gravity[0] != 0 || c.gravity[1] != 0) return "scene gravity is not zero";
  if (c.periodic_y) return "the domain is periodic in y (production.in is p f p)";
  if (!c.periodic_x) return "the domain is not periodic in x (production.in is p f p)";
  if (c.wall_left || c.wall_right) return "side walls (left/right)";
  if (!c.wall_bottom || !c.wall_top) return "the bed needs both bottom and top walls";
  if (c.contact.intruder_friction != c.contact.friction)
    return "intruder.friction differs from grains.friction (one mu for every pair in LAMMPS)";
  if (c.spin_ramp_time > 0) return "intruder.spin_ramp_time > 0 (LAMMPS spins at once)";
  if (!(c.intruder_diameter > 0)) return "no intruder (intruder.diameter = 0)";
  if (!(std::hypot(c.intruder_velocity[0], c.intruder_velocity[1]) > 0))
    return "the intruder does not move";
  return {};
}

/// "-var name value" with the shortest of %.15g / %.17g that reads back as v.
void var(const char* name, double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.15g", v);
  if (std::strtod(buf, nullptr) != v) std::snprintf(buf, sizeof buf, "%.17g", v);
  std::printf("-var %s %s\n", name, buf);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return usage(argv[0]);
  const std::string case_path = argv[1], out_path = argv[2];
  if (case_path.rfind("--", 0) == 0 || out_path.rfind("--", 0) == 0) return usage(argv[0]);
  std::vector<std::string> overrides;
  for (int i = 3; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--set" && i + 1 < argc) {
      overrides.emplace_back(argv[++i]);
    } else if (a.rfind("--set=", 0) == 0) {
      overrides.push_back(a.substr(6));
    } else {
      std::fprintf(stderr, "%s: unexpected argument '%s'\n", argv[0], a.c_str());
      return usage(argv[0]);
    }
  }

  try {
    const grainlift::Case cs = grainlift::load_case(case_path, overrides);
    const gd::DemConfig c = gd::make_dem_config(cs, 1);
    const std::string why = unsupported(c);
    if (!why.empty()) {
      std::fprintf(stderr, "%s: %s: LAMMPS cannot reproduce this case: %s\n", argv[0],
                   case_path.c_str(), why.c_str());
      return kBadInput;
    }
    const gd::PackedBed bed = gd::prepare_packing(c);
    const auto walls = gd::make_wall_disks(c);

    if (!grainlift::dem::write_lammps_data(
            out_path,
            "grainlift case " + case_path + ", Phi = " + std::to_string(bed.area_fraction), c, bed,
            walls)) {
      std::fprintf(stderr, "%s: cannot write %s\n", argv[0], out_path.c_str());
      return kBadInput;
    }
    double rmax = 0;
    for (double r : bed.r) rmax = std::max(rmax, r);
    for (const auto& w : walls) rmax = std::max(rmax, w.r);

    // the step count and steady start as run_simulation computes them
    const double d = c.grain_diameter;
    const double speed = std::hypot(c.intruder_velocity[0], c.intruder_velocity[1]);
    const long long steps = gd::travel_steps(c);
    std::printf("# grains %zu (walls %zu), area fraction %.4f, packing %s\n", bed.r.size(),
                walls.size(), bed.area_fraction, bed.from_cache ? "reused from cache" : "prepared");
    std::printf("-var data %s\n", out_path.c_str());
    var("vx", c.intruder_velocity[0]);
    var("vy", c.intruder_velocity[1]);
    var("omega", c.intruder_omega);
    var("dt", c.dt);
    std::printf("-var steps %lld\n", steps);
    var("density", c.density);
    var("kn", c.contact.kn);
    var("kt", c.contact.kt);
    var("gamma_n", c.contact.gamma_n);
    var("gamma_t", c.contact.gamma_t);
    var("mu", c.contact.friction);
    var("mu_intruder", c.contact.intruder_friction);
    var("skin", 0.2 * rmax);
    std::printf("-var every %d\n", c.sample_every);
    // not used by LAMMPS: the steady start (s) and block count of grainlift's means
    var("t_steady", c.steady_travel * d / speed);
    std::printf("-var blocks %d\n", cs.output.blocks);
    return 0;
  } catch (const grainlift::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return kBadInput;
  } catch (const gd::ConfigError& e) {
    std::fprintf(stderr, "%s: %s\n", case_path.c_str(), e.what());
    return kBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", argv[0], e.what());
    return 1;
  }
}
