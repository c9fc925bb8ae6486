// `grainlift import lammps`: the outputs of an exported in.grainlift read back as a DEM result
// (lammps_bridge.h, docs/lammps.md).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "grainlift/dem/dem_output.h"
#include "grainlift/dem/dem_solver.h"
#include "grainlift/dem/lammps_bridge.h"
#include "grainlift/dem/scenes/simulation.h"
#include "grainlift/shared/errors.h"

namespace grainlift::dem {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// A problem on the last line of a file: a LAMMPS run stopped while writing it. The reader
/// keeps what came before (the import is then partial).
struct Truncated : InputError {
  using InputError::InputError;
};

/// Reads a file line by line, naming file and line in every error.
class LineReader {
 public:
  explicit LineReader(std::string path) : path_(std::move(path)), in_(path_) {
    if (!in_)
      throw InputError(fmt::format("{}: not found (run the exported in.grainlift in LAMMPS there "
                                   "first: lmp -in {})", path_, kLammpsScript));
  }
  bool next(std::string& l) {
    if (!std::getline(in_, l)) return false;
    ++line_;
    return true;
  }
  /// Throws Truncated for a problem on the file's last line (or past it), else InputError.
  [[noreturn]] void fail(const std::string& what) {
    const std::string m = fmt::format("{}:{}: {}", path_, line_, what);
    if (in_.peek() == std::char_traits<char>::eof()) throw Truncated(m);
    throw InputError(m);
  }
  /// The whitespace-separated numbers of @p l; exactly @p n of them, all finite.
  std::vector<double> numbers(const std::string& l, std::size_t n) {
    std::istringstream s(l);
    std::vector<double> v;
    std::string w;
    while (s >> w) {
      char* end = nullptr;
      const double x = std::strtod(w.c_str(), &end);
      if (end == w.c_str() || *end != '\0' || !std::isfinite(x))
        fail(fmt::format("'{}' is not a finite number", w));
      v.push_back(x);
    }
    if (v.size() != n) fail(fmt::format("{} values, expected {}", v.size(), n));
    return v;
  }

 private:
  std::string path_;
  std::ifstream in_;
  long long line_ = 0;
};

/// One row of forces.txt: the force and torque of the grains on the intruder at a step.
struct ForceRow {
  long long step = 0;
  double time = 0, fx = 0, fy = 0, torque = 0;
};

/// forces.txt; a last line cut short is left out and described in @p tail.
std::vector<ForceRow> read_forces(const std::string& path, std::string& tail) {
  LineReader r(path);
  std::vector<ForceRow> rows;
  std::string l;
  try {
    while (r.next(l)) {
      if (l.empty() || l[0] == '#') continue;
      const auto v = r.numbers(l, 5);
      ForceRow f{static_cast<long long>(v[0]), v[1], v[2], v[3], v[4]};
      if (!rows.empty() && f.step <= rows.back().step) r.fail("steps are not increasing");
      rows.push_back(f);
    }
  } catch (const Truncated& t) {
    tail = t.what();
  }
  return rows;
}

/// The intruder's contacts of one dumped step, in DemOutput's convention.
using StepContacts = std::vector<IntruderContact>;

/// contacts.dump: for each step, the pairs within touching distance in the disk round the
/// intruder: atom ids 1 and 2, distance, the normal force on atom 1 (fx, fy) and its signed
/// magnitude F (so that (fx, fy) / F is the unit vector from atom 2 to atom 1), the
/// tangential force on atom 1 and its magnitude (LAMMPS 2021's pair/local has no separation
/// vector). The intruder's pairs (id @p intruder) with a force become contacts.
std::map<long long, StepContacts> read_contacts(const std::string& path, long long intruder,
                                                double mu, std::string& tail) {
  LineReader r(path);
  std::map<long long, StepContacts> out;
  std::string l;
  long long step = -1;
  try {
    while (r.next(l)) {
      step = -1;
      if (l.rfind("ITEM: TIMESTEP", 0) != 0) r.fail("expected 'ITEM: TIMESTEP'");
      if (!r.next(l)) r.fail("truncated after ITEM: TIMESTEP");
      step = static_cast<long long>(r.numbers(l, 1)[0]);
      if (!r.next(l) || l.rfind("ITEM: NUMBER OF ENTRIES", 0) != 0)
        r.fail("expected 'ITEM: NUMBER OF ENTRIES'");
      if (!r.next(l)) r.fail("truncated");
      const double count = r.numbers(l, 1)[0];
      if (count < 0 || count > 1e8) r.fail("implausible entry count");
      if (!r.next(l) || l.rfind("ITEM: BOX BOUNDS", 0) != 0) r.fail("expected 'ITEM: BOX BOUNDS'");
      for (int k = 0; k < 3; ++k)
        if (!r.next(l)) r.fail("truncated box bounds");
      if (!r.next(l) || l.rfind("ITEM: ENTRIES", 0) != 0) r.fail("expected 'ITEM: ENTRIES'");
      StepContacts& cs = out[step];
      for (long long e = 0; e < static_cast<long long>(count); ++e) {
        if (!r.next(l)) r.fail("truncated: fewer entries than announced");
        const auto v = r.numbers(l, 9);
        const long long a = static_cast<long long>(v[0]), b = static_cast<long long>(v[1]);
        if (a != intruder && b != intruder) continue;
        const double fnormal = v[5], fshear = v[8];
        // a pair within the cut-off without a normal force carries no force at all (|F_t| is
        // capped by mu |F_n|) and has no direction in the dump
        if (fnormal == 0) continue;
        // force on atom a; the intruder's is its opposite when the intruder is b
        const double sign = a == intruder ? 1.0 : -1.0;
        const double Fx = sign * (v[3] + v[6]), Fy = sign * (v[4] + v[7]);
        // unit normal from the intruder to the grain: -(x_a - x_b)/|.| when a is the intruder
        const double nx = -sign * v[3] / fnormal, ny = -sign * v[4] / fnormal;
        IntruderContact c;
        c.theta = std::atan2(ny, nx);
        if (c.theta <= -kPi) c.theta = kPi;
        c.fn = -(Fx * nx + Fy * ny);
        c.ft = -Fx * ny + Fy * nx;
        c.vt = std::numeric_limits<double>::quiet_NaN();  // no velocities in the dump
        c.slipping = mu > 0 && fshear >= mu * std::abs(fnormal) * (1 - 1e-9);
        cs.push_back(c);
      }
    }
  } catch (const Truncated& t) {
    if (step >= 0) out.erase(step);  // the block cut short
    tail = t.what();
  }
  return out;
}

/// "Loop time of T on P procs for N steps" of a LAMMPS log: T, P, N (zeros when absent).
struct LoopTime {
  double seconds = 0;
  long long procs = 0, steps = 0;
};
LoopTime read_loop_time(const std::string& path) {
  LoopTime t;
  std::ifstream f(path);
  std::string l;
  while (std::getline(f, l)) {
    if (l.rfind("Loop time of ", 0) != 0) continue;
    std::istringstream s(l.substr(13));
    std::string on, procs, f1, steps;
    s >> t.seconds >> on >> t.procs >> procs >> f1 >> t.steps;
  }
  return t;
}


}  // namespace

RunResult import_lammps(const Case& c, const std::string& dir) {
  const DemConfig cfg = make_dem_config(c, 1);
  // the exported bed: the same packing (the cache, or prepared again from the same seed), its
  // counts (the intruder is the atom after the grains and wall disks) and its structure
  const PackedBed bed = prepare_packing(packing_config(cfg));
  const std::vector<Disk> walls = make_wall_disks(cfg);
  const long long intruder = static_cast<long long>(bed.r.size() + walls.size()) + 1;
  std::string forces_tail, contacts_tail;
  std::vector<ForceRow> rows = read_forces(dir + "/" + kLammpsForces, forces_tail);
  const auto contacts =
      read_contacts(dir + "/" + kLammpsContacts, intruder, cfg.contact.friction, contacts_tail);
  // a run stopped while writing: the samples up to the last step both files hold in full
  if (!contacts_tail.empty()) {
    const long long last = contacts.empty() ? 0 : contacts.rbegin()->first;
    while (!rows.empty() && rows.back().step > last) rows.pop_back();
  }

  DemOutput out;
  out.grains = static_cast<int>(bed.r.size());
  out.wall_grains = static_cast<int>(walls.size());
  out.planned_steps = travel_steps(cfg);
  out.achieved_area_fraction = bed.area_fraction;
  out.packing_from_cache = bed.from_cache;
  out.bed = bed_fingerprint(cfg, bed, walls);
  const double speed = std::hypot(cfg.intruder_velocity[0], cfg.intruder_velocity[1]);
  const double steady_time = cfg.steady_travel * cfg.grain_diameter / speed;
  out.steady_start_index = static_cast<std::size_t>(-1);
  // the sum of the dumped contact forces against LAMMPS's own force on the intruder, summed
  // over the samples: sum |difference| / sum |F| (pair/local re-evaluates each contact with
  // the velocities at the end of the step, the force was computed with those of mid-step)
  double mismatch = 0, force_scale = 0;
  long long missing = 0;
  for (const ForceRow& f : rows) {
    if (f.step <= 0) continue;  // grainlift's first sample is after the first interval
    const std::size_t index = out.samples.size();
    IntruderSample s;
    s.time = f.time;
    s.fx = f.fx;
    s.fy = f.fy;
    s.torque = f.torque;
    const auto it = contacts.find(f.step);
    if (it == contacts.end()) {
      ++missing;
    } else {
      s.contacts = static_cast<int>(it->second.size());
      double sx = 0, sy = 0;
      for (const IntruderContact& ct : it->second) {
        const double nx = std::cos(ct.theta), ny = std::sin(ct.theta);
        sx += -ct.fn * nx - ct.ft * ny;
        sy += -ct.fn * ny + ct.ft * nx;
      }
      mismatch += std::hypot(sx - f.fx, sy - f.fy);
    }
    force_scale += std::hypot(f.fx, f.fy);
    out.samples.push_back(s);
    if (out.steady_start_index == static_cast<std::size_t>(-1) &&
        f.time >= steady_time * (1 - 1e-12))
      out.steady_start_index = index;
    if (index >= out.steady_start_index && it != contacts.end()) {
      for (IntruderContact ct : it->second) {
        ct.sample = static_cast<std::int32_t>(index);
        out.contacts.push_back(ct);
      }
    }
  }
  if (out.samples.empty())
    throw InputError(fmt::format("{}/{}: no samples after step 0 (did the LAMMPS run finish?)",
                                 dir, kLammpsForces));
  if (out.steady_start_index == static_cast<std::size_t>(-1))
    out.steady_start_index = out.samples.size();
  out.steps = rows.back().step;
  const LoopTime loop = read_loop_time(dir + "/" + kLammpsLog);

  RunResult r = dem_result(c, out);
  const double relative = force_scale > 0 ? mismatch / force_scale : 0.0;
  r.meta.notes += fmt::format(
      "; imported from LAMMPS ({}): {} of {} steps, loop time {:.6g} s on {} processes; "
      "the dumped contact forces sum to LAMMPS's force on the intruder within {:.2g} (sum over "
      "samples of |difference| / |F|)",
      dir, out.steps, out.planned_steps, loop.seconds, loop.procs, relative);
  if (out.steps < out.planned_steps) r.meta.partial = true;
  if (missing > 0)
    r.meta.notes += fmt::format("; WARNING: {} samples have no contact dump", missing);
  for (const std::string& tail : {forces_tail, contacts_tail}) {
    if (tail.empty()) continue;
    r.meta.partial = true;
    r.meta.notes += fmt::format(
        "; the LAMMPS output ends mid-write: read up to its last complete sample ({})", tail);
  }
  r.diagnostics.values["lammps_loop_seconds"] = loop.seconds;
  r.diagnostics.values["lammps_contact_force_mismatch"] = relative;
  r.diagnostics.counts["lammps_processes"] = loop.procs;
  r.diagnostics.counts["planned_steps"] = out.planned_steps;
  r.diagnostics.texts["imported_from"] = "lammps";
  return r;
}

}  // namespace grainlift::dem
