// Checkpoint bytes (checkpoint.h): little-endian fields written one by one (no struct padding
// in the bytes), each vector preceded by its length, the whole followed by an FNV-1a 64
// checksum. Reading checks every length against the bytes left before it allocates, so a
// truncated or corrupt file is refused, never read past its end.
#include "grainlift/dem/system/checkpoint.h"
#include "system/fnv1a.h"

#include <cstring>
#include <type_traits>

namespace grainlift::dem {

namespace {

constexpr char kMagic[8] = {'G', 'L', 'D', 'E', 'M', 'C', 'K', 'P'};
constexpr std::uint32_t kFormat = 4;  // 4: contacts' slip velocity; 3: no co-moving window

using detail::fnv1a;

class Writer {
 public:
  template <class T>
  void put(T v) {
    static_assert(std::is_arithmetic_v<T>);
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    bytes.insert(bytes.end(), b, b + sizeof(T));
  }
  template <class T>
  void put_vector(const std::vector<T>& v) {
    put<std::uint64_t>(v.size());
    for (const T& x : v) put(x);
  }
  void put_string(const std::string& s) {
    put<std::uint64_t>(s.size());
    bytes.insert(bytes.end(), s.begin(), s.end());
  }
  std::vector<unsigned char> bytes;
};

class Reader {
 public:
  Reader(const unsigned char* p, std::size_t n) : p_(p), end_(p + n) {}
  template <class T>
  T get() {
    static_assert(std::is_arithmetic_v<T>);
    need(sizeof(T));
    T v;
    std::memcpy(&v, p_, sizeof(T));
    p_ += sizeof(T);
    return v;
  }
  /// A length of items of @p item_bytes each, checked against the bytes left.
  std::size_t length(std::size_t item_bytes) {
    const auto n = get<std::uint64_t>();
    if (item_bytes > 0 && n > static_cast<std::uint64_t>(end_ - p_) / item_bytes) {
      throw CheckpointError("corrupt checkpoint: a length of " + std::to_string(n) +
                            " items exceeds the bytes left");
    }
    return static_cast<std::size_t>(n);
  }
  template <class T>
  std::vector<T> get_vector() {
    std::vector<T> v(length(sizeof(T)));
    for (T& x : v) x = get<T>();
    return v;
  }
  std::string get_string() {
    const std::size_t n = length(1);
    std::string s(reinterpret_cast<const char*>(p_), n);
    p_ += n;
    return s;
  }
  bool done() const { return p_ == end_; }

 private:
  void need(std::size_t n) {
    if (static_cast<std::size_t>(end_ - p_) < n) throw CheckpointError("truncated checkpoint");
  }
  const unsigned char* p_;
  const unsigned char* end_;
};

void put_disks(Writer& w, const std::vector<Disk>& d) {
  w.put<std::uint64_t>(d.size());
  for (const Disk& x : d) {
    for (double v : {x.x, x.y, x.r, x.mass, x.vx, x.vy, x.w}) w.put(v);
  }
}

std::vector<Disk> get_disks(Reader& r) {
  std::vector<Disk> d(r.length(7 * sizeof(double)));
  for (Disk& x : d) {
    for (double* v : {&x.x, &x.y, &x.r, &x.mass, &x.vx, &x.vy, &x.w}) *v = r.get<double>();
  }
  return d;
}

void put_system(Writer& w, const SystemSnapshot& s) {
  put_disks(w, s.grains);
  put_disks(w, s.frozen);
  w.put_vector(s.ax);
  w.put_vector(s.ay);
  w.put_vector(s.alpha);
  w.put(s.time);
  w.put(s.steps);
  const Intruder& in = s.intruder;
  w.put<std::uint8_t>(in.present ? 1 : 0);
  for (double v : {in.x, in.y, in.r, in.vx, in.vy, in.omega_target, in.spin_ramp_time,
                   in.x_build, in.y_build, in.t0}) {
    w.put(v);
  }
  w.put_vector(s.pair_i);
  w.put_vector(s.pair_j);
  w.put_vector(s.pair_sx);
  w.put_vector(s.pair_sy);
  w.put_vector(s.ic_grain);
  w.put_vector(s.ic_sx);
  w.put_vector(s.ic_sy);
  w.put<std::uint8_t>(s.has_lid ? 1 : 0);
  const LidState& l = s.lid;
  for (double v : {l.y, l.velocity, l.pressure, l.shear_stress, l.x_shift, l.impulse_x,
                   l.impulse_y}) {
    w.put(v);
  }
  w.put_vector(s.lid_disk_y);
  w.put_vector(s.lid_disk_velocity);
  w.put(s.max_overlap);
  w.put(s.builds);
  w.put(s.steps_on_one);
  w.put(s.steps_on_team);
  w.put(s.sleep_grain_steps);
  w.put(s.wake_builds);
  w.put(s.woken);
}

SystemSnapshot get_system(Reader& r) {
  SystemSnapshot s;
  s.grains = get_disks(r);
  s.frozen = get_disks(r);
  s.ax = r.get_vector<double>();
  s.ay = r.get_vector<double>();
  s.alpha = r.get_vector<double>();
  s.time = r.get<double>();
  s.steps = r.get<std::int64_t>();
  Intruder& in = s.intruder;
  in.present = r.get<std::uint8_t>() != 0;
  for (double* v : {&in.x, &in.y, &in.r, &in.vx, &in.vy, &in.omega_target, &in.spin_ramp_time,
                    &in.x_build, &in.y_build, &in.t0}) {
    *v = r.get<double>();
  }
  s.pair_i = r.get_vector<std::int32_t>();
  s.pair_j = r.get_vector<std::int32_t>();
  s.pair_sx = r.get_vector<double>();
  s.pair_sy = r.get_vector<double>();
  s.ic_grain = r.get_vector<std::int32_t>();
  s.ic_sx = r.get_vector<double>();
  s.ic_sy = r.get_vector<double>();
  s.has_lid = r.get<std::uint8_t>() != 0;
  LidState& l = s.lid;
  for (double* v : {&l.y, &l.velocity, &l.pressure, &l.shear_stress, &l.x_shift, &l.impulse_x,
                    &l.impulse_y}) {
    *v = r.get<double>();
  }
  s.lid_disk_y = r.get_vector<double>();
  s.lid_disk_velocity = r.get_vector<double>();
  s.max_overlap = r.get<double>();
  s.builds = r.get<std::int32_t>();
  s.steps_on_one = r.get<std::int64_t>();
  s.steps_on_team = r.get<std::int64_t>();
  s.sleep_grain_steps = r.get<double>();
  s.wake_builds = r.get<std::int32_t>();
  s.woken = r.get<std::int64_t>();
  // sizes that must agree (the restore indexes with them)
  const std::size_t ng = s.grains.size(), nb = ng + s.frozen.size();
  if (s.ax.size() != ng || s.ay.size() != ng || s.alpha.size() != ng) {
    throw CheckpointError("corrupt checkpoint: accelerations of another number of grains");
  }
  const std::size_t np = s.pair_i.size();
  if (s.pair_j.size() != np || s.pair_sx.size() != np || s.pair_sy.size() != np) {
    throw CheckpointError("corrupt checkpoint: pair histories of unequal lengths");
  }
  for (std::size_t k = 0; k < np; ++k) {
    if (s.pair_i[k] < 0 || std::size_t(s.pair_i[k]) >= ng || s.pair_j[k] < 0 ||
        std::size_t(s.pair_j[k]) >= nb) {
      throw CheckpointError("corrupt checkpoint: a pair of bodies that do not exist");
    }
  }
  const std::size_t nc = s.ic_grain.size();
  if (s.ic_sx.size() != nc || s.ic_sy.size() != nc) {
    throw CheckpointError("corrupt checkpoint: intruder histories of unequal lengths");
  }
  for (std::int32_t g : s.ic_grain) {
    if (g < 0 || std::size_t(g) >= ng) throw CheckpointError("corrupt checkpoint: no such grain");
  }
  return s;
}

void put_output(Writer& w, const DemOutput& o) {
  w.put<std::uint64_t>(o.samples.size());
  for (const IntruderSample& s : o.samples) {
    for (double v : {s.time, s.fx, s.fy, s.torque}) w.put(v);
    w.put<std::int32_t>(s.contacts);
  }
  w.put<std::uint64_t>(o.contacts.size());
  for (const IntruderContact& c : o.contacts) {
    w.put(c.sample);
    for (double v : {c.theta, c.fn, c.ft, c.vt}) w.put(v);
    w.put<std::uint8_t>(c.slipping ? 1 : 0);
  }
  w.put<std::uint64_t>(o.steady_start_index);
  w.put<std::int32_t>(o.grains);
  w.put<std::int32_t>(o.wall_grains);
  w.put(o.achieved_area_fraction);
  w.put(o.collision_time);
  w.put<std::uint8_t>(o.packing_from_cache ? 1 : 0);
  w.put<std::uint64_t>(o.lid.size());
  for (const LidSample& l : o.lid) {
    for (double v : {l.time, l.y, l.pressure}) w.put(v);
  }
  w.put(o.lid_mass);
  w.put(o.lid_damping);
  w.put<std::uint64_t>(o.far_field.size());
  for (const FarFieldSample& f : o.far_field) {
    for (double v : {f.time, f.pressure, f.sxx, f.sxy, f.syy, f.area}) w.put(v);
  }
  w.put(o.far_field_exclusion);
  w.put(o.far_field_half_height);
  w.put(o.bed_max_overlap);
}

DemOutput get_output(Reader& r) {
  DemOutput o;
  o.samples.resize(r.length(4 * sizeof(double) + 4));
  for (IntruderSample& s : o.samples) {
    for (double* v : {&s.time, &s.fx, &s.fy, &s.torque}) *v = r.get<double>();
    s.contacts = r.get<std::int32_t>();
  }
  o.contacts.resize(r.length(4 + 4 * sizeof(double) + 1));
  for (IntruderContact& c : o.contacts) {
    c.sample = r.get<std::int32_t>();
    for (double* v : {&c.theta, &c.fn, &c.ft, &c.vt}) *v = r.get<double>();
    c.slipping = r.get<std::uint8_t>() != 0;
    if (c.sample < 0 || std::size_t(c.sample) >= o.samples.size()) {
      throw CheckpointError("corrupt checkpoint: a contact of a sample that does not exist");
    }
  }
  o.steady_start_index = static_cast<std::size_t>(r.get<std::uint64_t>());
  // a sample index, or "not yet" (all bits set) before the steady state began; the glue
  // counts the averaged samples as samples.size() - steady_start_index
  if (o.steady_start_index > o.samples.size() &&
      o.steady_start_index != static_cast<std::size_t>(-1)) {
    throw CheckpointError("corrupt checkpoint: steady state starts at sample " +
                          std::to_string(o.steady_start_index) + " of " +
                          std::to_string(o.samples.size()));
  }
  o.grains = r.get<std::int32_t>();
  o.wall_grains = r.get<std::int32_t>();
  o.achieved_area_fraction = r.get<double>();
  o.collision_time = r.get<double>();
  o.packing_from_cache = r.get<std::uint8_t>() != 0;
  o.lid.resize(r.length(3 * sizeof(double)));
  for (LidSample& l : o.lid) {
    for (double* v : {&l.time, &l.y, &l.pressure}) *v = r.get<double>();
  }
  o.lid_mass = r.get<double>();
  o.lid_damping = r.get<double>();
  o.far_field.resize(r.length(6 * sizeof(double)));
  for (FarFieldSample& f : o.far_field) {
    for (double* v : {&f.time, &f.pressure, &f.sxx, &f.sxy, &f.syy, &f.area}) *v = r.get<double>();
  }
  o.far_field_exclusion = r.get<double>();
  o.far_field_half_height = r.get<double>();
  o.bed_max_overlap = r.get<double>();
  return o;
}

}  // namespace

std::vector<unsigned char> encode_checkpoint(const RunCheckpoint& c) {
  Writer w;
  w.bytes.assign(kMagic, kMagic + sizeof kMagic);
  w.put(kFormat);
  w.put_string(c.case_tag);
  w.put(c.step);
  w.put(c.planned_steps);
  put_system(w, c.system);
  put_output(w, c.out);
  w.put(c.fields.snapshots);
  for (const auto* v : {&c.fields.gamma, &c.fields.gvx, &c.fields.gvy, &c.fields.gv2,
                        &c.fields.sxx, &c.fields.sxy, &c.fields.syy}) {
    w.put_vector(*v);
  }
  w.put(fnv1a(w.bytes.data(), w.bytes.size()));
  return std::move(w.bytes);
}

RunCheckpoint decode_checkpoint(const std::vector<unsigned char>& bytes) {
  if (bytes.size() < sizeof kMagic + sizeof(std::uint32_t) + sizeof(std::uint64_t) ||
      std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) {
    throw CheckpointError("not a grainlift DEM checkpoint (wrong magic bytes or too short)");
  }
  const std::size_t body = bytes.size() - sizeof(std::uint64_t);
  std::uint64_t stored;
  std::memcpy(&stored, bytes.data() + body, sizeof stored);
  Reader r(bytes.data() + sizeof kMagic, body - sizeof kMagic);
  const auto format = r.get<std::uint32_t>();
  if (format != kFormat) {
    throw CheckpointError("checkpoint format " + std::to_string(format) +
                          ", this grainlift reads " + std::to_string(kFormat));
  }
  if (fnv1a(bytes.data(), body) != stored) {
    throw CheckpointError("corrupt or truncated checkpoint (checksum mismatch)");
  }
  RunCheckpoint c;
  c.case_tag = r.get_string();
  c.step = r.get<std::int64_t>();
  c.planned_steps = r.get<std::int64_t>();
  c.system = get_system(r);
  c.out = get_output(r);
  c.fields.snapshots = r.get<std::int32_t>();
  for (auto* v : {&c.fields.gamma, &c.fields.gvx, &c.fields.gvy, &c.fields.gv2, &c.fields.sxx,
                  &c.fields.sxy, &c.fields.syy}) {
    *v = r.get_vector<double>();
  }
  if (!r.done()) throw CheckpointError("corrupt checkpoint: bytes left after the last field");
  if (c.step < 0 || c.step > c.planned_steps) {
    throw CheckpointError("corrupt checkpoint: step " + std::to_string(c.step) + " of " +
                          std::to_string(c.planned_steps));
  }
  return c;
}

}  // namespace grainlift::dem
