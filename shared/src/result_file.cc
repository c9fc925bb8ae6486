#include "grainlift/shared/result_file.h"

#include <fmt/format.h>
#include <hdf5.h>

#include <cstdio>
#include <cstring>
#include <functional>

#include "grainlift/shared/atomic_file.h"
#include "grainlift/shared/derived_quantities.h"
#include "grainlift/shared/errors.h"

namespace grainlift {
namespace {

/// Owns one HDF5 identifier and closes it with the matching function.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = -1; }
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  operator hid_t() const { return id_; }
  bool valid() const { return id_ >= 0; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

void check(herr_t status, const std::string& what) {
  if (status < 0) throw RunError("HDF5: " + what + " failed");
}

/// Every /geometry attribute and the Geometry member it holds (one list for writer and reader).
const std::pair<const char*, double Geometry::*> geometry_fields[] = {
    {"intruder_diameter", &Geometry::intruder_diameter},
    {"intruder_x", &Geometry::intruder_x},
    {"intruder_y", &Geometry::intruder_y},
    {"grain_diameter", &Geometry::grain_diameter},
    {"domain_xmin", &Geometry::domain_xmin},
    {"domain_xmax", &Geometry::domain_xmax},
    {"domain_ymin", &Geometry::domain_ymin},
    {"domain_ymax", &Geometry::domain_ymax},
    {"velocity_x", &Geometry::velocity_x},
    {"velocity_y", &Geometry::velocity_y},
    {"omega", &Geometry::omega},
    {"gravity_x", &Geometry::gravity_x},
    {"gravity_y", &Geometry::gravity_y},
    {"bulk_density", &Geometry::bulk_density},
    {"pressure_scale", &Geometry::pressure_scale},
    {"reference_gravity", &Geometry::reference_gravity},
    {"equivalent_depth", &Geometry::equivalent_depth},
};
/// Attributes of geometry_fields added after schema 2 was first written: absent = 0.
bool optional_geometry_field(const std::string& name) {
  return name == "reference_gravity" || name == "equivalent_depth";
}

// ---- writing ---------------------------------------------------------------------------------
Handle make_group(hid_t parent, const char* name) {
  Handle g(H5Gcreate2(parent, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  if (!g.valid()) throw RunError(fmt::format("HDF5: cannot create group {}", name));
  return g;
}

/// A fixed-length string type of @p size bytes; grainlift writes UTF-8, a reader converts a
/// file's ASCII strings only to an ASCII memory type (HDF5 converts within one character set).
Handle string_type(std::size_t size, H5T_cset_t cset = H5T_CSET_UTF8) {
  Handle t(H5Tcopy(H5T_C_S1), H5Tclose);
  check(H5Tset_size(t, size == 0 ? 1 : size), "H5Tset_size");
  check(H5Tset_cset(t, cset), "H5Tset_cset");
  check(H5Tset_strpad(t, H5T_STR_NULLPAD), "H5Tset_strpad");
  return t;
}

void attr_string(hid_t obj, const char* name, const std::string& value) {
  Handle type = string_type(value.size());
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle a(H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!a.valid()) throw RunError(fmt::format("HDF5: cannot create attribute {}", name));
  const std::string padded = value.empty() ? std::string(1, '\0') : value;
  check(H5Awrite(a, type, padded.data()), "H5Awrite");
}

template <typename T>
void attr_number(hid_t obj, const char* name, T value) {
  const hid_t type = std::is_floating_point<T>::value ? H5T_NATIVE_DOUBLE : H5T_NATIVE_LLONG;
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle a(H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!a.valid()) throw RunError(fmt::format("HDF5: cannot create attribute {}", name));
  if constexpr (std::is_floating_point<T>::value) {
    const double v = value;
    check(H5Awrite(a, type, &v), "H5Awrite");
  } else {
    const long long v = value;
    check(H5Awrite(a, type, &v), "H5Awrite");
  }
}

void dataset_string(hid_t parent, const char* name, const std::string& value) {
  Handle type = string_type(value.size());
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle d(H5Dcreate2(parent, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
           H5Dclose);
  if (!d.valid()) throw RunError(fmt::format("HDF5: cannot create dataset {}", name));
  const std::string padded = value.empty() ? std::string(1, '\0') : value;
  check(H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, padded.data()), "H5Dwrite");
}

/// 1D (ny == 0) or 2D [ny][nx] dataset of doubles with a "units" attribute.
void dataset_doubles(hid_t parent, const char* name, const std::vector<double>& v,
                     const char* units, std::size_t ny = 0, std::size_t nx = 0) {
  hsize_t dims[2] = {ny ? ny : v.size(), nx};
  if (ny && ny * nx != v.size())
    throw RunError(fmt::format("HDF5: dataset {} has {} values, expected {} x {}", name,
                               v.size(), ny, nx));
  Handle space(H5Screate_simple(ny ? 2 : 1, dims, nullptr), H5Sclose);
  Handle d(H5Dcreate2(parent, name, H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
           H5Dclose);
  if (!d.valid()) throw RunError(fmt::format("HDF5: cannot create dataset {}", name));
  if (!v.empty()) check(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()),
                        "H5Dwrite");
  attr_string(d, "units", units);
}

void write_body(hid_t file, const RunResult& r) {
  attr_string(file, "schema", "grainlift");
  attr_number(file, "schema_version", static_cast<long long>(schema_version));
  attr_string(file, "solver", r.meta.solver);
  {
    Handle g = make_group(file, "metadata");
    attr_string(g, "solver", r.meta.solver);
    attr_string(g, "grainlift_version", r.meta.grainlift_version);
    attr_string(g, "git_revision", r.meta.git_revision);
    attr_number(g, "threads", static_cast<long long>(r.meta.threads));
    attr_number(g, "wall_seconds", r.meta.wall_seconds);
    attr_string(g, "created_utc", r.meta.created_utc);
    attr_string(g, "notes", r.meta.notes);
    attr_number(g, "partial", static_cast<long long>(r.meta.partial ? 1 : 0));
  }
  {
    Handle g = make_group(file, "case");
    dataset_string(g, "text", r.meta.case_text);
    dataset_string(g, "overrides", r.meta.case_overrides);
    attr_string(g, "hash", r.meta.case_hash);
    attr_string(g, "hash_algorithm", "fnv1a64(text + \"\\n--\\n\" + overrides)");
    attr_string(g, "path", r.meta.case_path);
  }
  {
    Handle g = make_group(file, "geometry");
    for (const auto& [name, member] : geometry_fields) attr_number(g, name, r.geometry.*member);
  }
  if (r.forces) {
    const ForceSeries& f = *r.forces;
    Handle g = make_group(file, "forces");
    dataset_doubles(g, "time", f.time, "s");
    dataset_doubles(g, "fx", f.fx, "N/m");
    dataset_doubles(g, "fy", f.fy, "N/m");
    dataset_doubles(g, "torque", f.torque, "N");
    if (!f.contacts.empty()) dataset_doubles(g, "contacts", f.contacts, "1");
  }
  if (r.lid) {
    const LidSeries& l = *r.lid;
    Handle g = make_group(file, "lid");
    dataset_doubles(g, "time", l.time, "s");
    dataset_doubles(g, "y", l.y, "m");
    dataset_doubles(g, "pressure", l.pressure, "Pa");
    attr_number(g, "target", l.target);
    attr_number(g, "mean", l.mean);
    if (l.mean_stderr) attr_number(g, "mean_stderr", *l.mean_stderr);
    attr_number(g, "mass", l.mass);
    attr_number(g, "damping", l.damping);
  }
  if (r.far_field) {
    const FarFieldSeries& ff = *r.far_field;
    Handle g = make_group(file, "far_field");
    dataset_doubles(g, "time", ff.time, "s");
    dataset_doubles(g, "pressure", ff.pressure, "Pa");
    dataset_doubles(g, "stress_xx", ff.stress_xx, "Pa");
    dataset_doubles(g, "stress_xy", ff.stress_xy, "Pa");
    dataset_doubles(g, "stress_yy", ff.stress_yy, "Pa");
    attr_number(g, "mean", ff.mean);
    if (ff.mean_stderr) attr_number(g, "mean_stderr", *ff.mean_stderr);
    attr_number(g, "exclusion", ff.exclusion);
    attr_number(g, "half_height", ff.half_height);
  }
  if (r.bed) {
    const BedStructure& b = *r.bed;
    Handle g = make_group(file, "bed");
    attr_number(g, "contacts_per_grain", b.contacts_per_grain);
    attr_number(g, "rattler_fraction", b.rattler_fraction);
    attr_number(g, "fabric_xx", b.fabric_xx);
    attr_number(g, "fabric_xy", b.fabric_xy);
    attr_number(g, "fabric_yy", b.fabric_yy);
    attr_number(g, "mean_gap", b.mean_gap);
    dataset_doubles(g, "gap_edges", b.gap_edges, "1");
    dataset_doubles(g, "gap_fraction", b.gap_fraction, "1");
    dataset_doubles(g, "band_y", b.band_y, "m");
    dataset_doubles(g, "band_area_fraction", b.band_area_fraction, "1");
    dataset_doubles(g, "ring_r", b.ring_r, "m");
    dataset_doubles(g, "ring_area_fraction", b.ring_area_fraction, "1");
  }
  if (r.means) {
    const MeanForces& m = *r.means;
    Handle g = make_group(file, "means");
    attr_number(g, "drag", m.drag);
    attr_number(g, "lift", m.lift);
    attr_number(g, "torque", m.torque);
    if (m.drag_stderr) attr_number(g, "drag_stderr", *m.drag_stderr);
    if (m.lift_stderr) attr_number(g, "lift_stderr", *m.lift_stderr);
    if (m.torque_stderr) attr_number(g, "torque_stderr", *m.torque_stderr);
    if (m.contacts) attr_number(g, "contacts", *m.contacts);
    attr_number(g, "samples", static_cast<long long>(m.samples));
    attr_number(g, "blocks", static_cast<long long>(m.blocks));
  }
  if (r.surface) {
    const SurfaceDistribution& s = *r.surface;
    Handle g = make_group(file, "surface");
    dataset_doubles(g, "theta", s.theta, "rad");
    dataset_doubles(g, "sigma_n", s.sigma_n, "Pa");
    dataset_doubles(g, "sigma_t", s.sigma_t, "Pa");
    attr_number(g, "kernel_width_deg", s.kernel_width_deg);
    if (s.sigma_n_pointwise) dataset_doubles(g, "sigma_n_pointwise", *s.sigma_n_pointwise, "Pa");
    if (s.sigma_t_pointwise) dataset_doubles(g, "sigma_t_pointwise", *s.sigma_t_pointwise, "Pa");
    if (s.sigma_n_stderr) dataset_doubles(g, "sigma_n_stderr", *s.sigma_n_stderr, "Pa");
    if (s.sigma_t_stderr) dataset_doubles(g, "sigma_t_stderr", *s.sigma_t_stderr, "Pa");
  }
  if (r.histogram) {
    const SurfaceHistogram& h = *r.histogram;
    Handle g = make_group(file, "histogram");
    dataset_doubles(g, "theta_lo", h.theta_lo, "rad");
    dataset_doubles(g, "theta_hi", h.theta_hi, "rad");
    dataset_doubles(g, "contact_count", h.contact_count, "1");
    dataset_doubles(g, "normal_force", h.normal_force, "N/m");
    dataset_doubles(g, "tangential_force", h.tangential_force, "N/m");
    dataset_doubles(g, "slip_fraction", h.slip_fraction, "1");
  }
  {
    // derived quantities, computed by derive() (derived_quantities.h), for scripts to read
    const DerivedQuantities q = derive(r);
    Handle g = make_group(file, "derived");
    attr_number(g, "spin_ratio", q.spin_ratio);
    if (q.lift_over_drag) attr_number(g, "lift_over_drag", *q.lift_over_drag);
    if (q.buoyancy) attr_number(g, "buoyancy", *q.buoyancy);
    if (q.lift_over_buoyancy) attr_number(g, "lift_over_buoyancy", *q.lift_over_buoyancy);
    if (q.drag_coefficient) attr_number(g, "drag_coefficient", *q.drag_coefficient);
    if (!q.sigma_n_symmetric.empty()) {
      dataset_doubles(g, "sigma_n_symmetric", q.sigma_n_symmetric, "Pa");
      dataset_doubles(g, "sigma_n_antisymmetric", q.sigma_n_antisymmetric, "Pa");
      dataset_doubles(g, "sigma_t_symmetric", q.sigma_t_symmetric, "Pa");
      dataset_doubles(g, "sigma_t_antisymmetric", q.sigma_t_antisymmetric, "Pa");
    }
  }
  if (!r.diagnostics.empty()) {
    const Diagnostics& d = r.diagnostics;
    Handle g = make_group(file, "diagnostics");
    for (const auto& [name, v] : d.counts) attr_number(g, name.c_str(), v);
    for (const auto& [name, v] : d.values) attr_number(g, name.c_str(), v);
    for (const auto& [name, v] : d.texts) attr_string(g, name.c_str(), v);
    for (const auto& [name, v] : d.series) dataset_doubles(g, name.c_str(), v, "1");
  }
  if (r.fields) {
    const FieldGrid& fg = *r.fields;
    Handle g = make_group(file, "fields");
    dataset_doubles(g, "x", fg.x, "m");
    dataset_doubles(g, "y", fg.y, "m");
    const std::size_t ny = fg.y.size(), nx = fg.x.size();
    auto put = [&](const char* name, const std::optional<std::vector<double>>& v,
                   const char* units) {
      if (v) dataset_doubles(g, name, *v, units, ny, nx);
    };
    put("velocity_x", fg.velocity_x, "m/s");
    put("velocity_y", fg.velocity_y, "m/s");
    put("pressure", fg.pressure, "Pa");
    put("stress_xx", fg.stress_xx, "Pa");
    put("stress_xy", fg.stress_xy, "Pa");
    put("stress_yy", fg.stress_yy, "Pa");
    put("area_fraction", fg.area_fraction, "1");
    put("granular_temperature", fg.granular_temperature, "m^2/s^2");
  }
}

// ---- reading ---------------------------------------------------------------------------------
// Every read checks what the file declares before it allocates or reads: a file is refused
// (InputError, naming the object and what is accepted) rather than read past a buffer or
// allocated for data it does not hold.

/// The most values a dataset may declare: 2^27 doubles (1 GiB), far above any run's series.
constexpr hssize_t max_dataset_values = hssize_t(1) << 27;
/// The longest string an attribute or dataset may declare (a case file's text is a few kB).
constexpr std::size_t max_string_bytes = std::size_t(1) << 24;

bool exists(hid_t parent, const char* name) { return H5Lexists(parent, name, H5P_DEFAULT) > 0; }
bool has_attr(hid_t obj, const char* name) { return H5Aexists(obj, name) > 0; }

/// Where @p obj is in the file ("/metadata"), for messages.
std::string name_of(hid_t obj) {
  const ssize_t n = H5Iget_name(obj, nullptr, 0);
  if (n <= 0) return "?";
  std::string s(static_cast<std::size_t>(n), '\0');
  H5Iget_name(obj, s.data(), s.size() + 1);
  return s;
}

/// Refuses an attribute or dataset that is not a single value of the expected kind: a
/// fixed-length string (@p text) or an integer or floating-point number.
void require_single(hid_t type, hid_t space, bool text, const std::string& what) {
  const H5T_class_t cls = H5Tget_class(type);
  const bool kind_ok = text ? cls == H5T_STRING && H5Tis_variable_str(type) == 0
                            : cls == H5T_INTEGER || cls == H5T_FLOAT;
  const char* accepted = text ? "one fixed-length string" : "one integer or floating-point number";
  if (!kind_ok) throw InputError(fmt::format("{} has another type (accepted: {})", what, accepted));
  const hssize_t n = H5Sget_simple_extent_type(space) == H5S_NULL
                         ? 0
                         : H5Sget_simple_extent_npoints(space);
  if (n != 1)
    throw InputError(fmt::format("{} holds {} values (accepted: {})", what, n, accepted));
  if (text && H5Tget_size(type) > max_string_bytes)
    throw InputError(fmt::format("{} declares a string of {} bytes (accepted: at most {})", what,
                                 H5Tget_size(type), max_string_bytes));
}

Handle open_attr(hid_t obj, const char* name) {
  Handle a(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose);
  if (!a.valid()) throw InputError(fmt::format("missing attribute {} of {}", name, name_of(obj)));
  return a;
}

std::string read_attr_string(hid_t obj, const char* name) {
  if (!has_attr(obj, name)) return {};
  Handle a = open_attr(obj, name);
  Handle type(H5Aget_type(a), H5Tclose);
  Handle space(H5Aget_space(a), H5Sclose);
  require_single(type, space, true, fmt::format("attribute {} of {}", name, name_of(obj)));
  const std::size_t n = H5Tget_size(type);
  std::string s(n, '\0');
  Handle mem = string_type(n, H5Tget_cset(type));
  check(H5Aread(a, mem, s.data()), "H5Aread");
  s.resize(std::strlen(s.c_str()));
  return s;
}
template <typename T>
T read_attr_number(hid_t obj, const char* name, hid_t mem_type) {
  Handle a = open_attr(obj, name);
  Handle type(H5Aget_type(a), H5Tclose);
  Handle space(H5Aget_space(a), H5Sclose);
  require_single(type, space, false, fmt::format("attribute {} of {}", name, name_of(obj)));
  T v = 0;
  check(H5Aread(a, mem_type, &v), "H5Aread");
  return v;
}
double read_attr_double(hid_t obj, const char* name) {
  return read_attr_number<double>(obj, name, H5T_NATIVE_DOUBLE);
}
long long read_attr_int(hid_t obj, const char* name) {
  return read_attr_number<long long>(obj, name, H5T_NATIVE_LLONG);
}
std::optional<double> read_attr_optional(hid_t obj, const char* name) {
  if (!has_attr(obj, name)) return std::nullopt;
  return read_attr_double(obj, name);
}

Handle open_dataset(hid_t parent, const char* name) {
  Handle d(H5Dopen2(parent, name, H5P_DEFAULT), H5Dclose);
  if (!d.valid())
    throw InputError(fmt::format("missing dataset {} in {}", name, name_of(parent)));
  return d;
}

/// Refuses a dataset that declares more bytes than it stores (nothing written, or a size
/// edited): the reader would allocate for data the file does not hold. Compressed datasets
/// store less by design and are left to the limits on their declared size.
void require_stored(hid_t d, hssize_t values, std::size_t value_bytes, const std::string& what) {
  Handle dcpl(H5Dget_create_plist(d), H5Pclose);
  if (!dcpl.valid() || H5Pget_nfilters(dcpl) != 0) return;
  const hsize_t stored = H5Dget_storage_size(d);
  const hsize_t declared = hsize_t(values) * value_bytes;
  if (stored < declared)
    throw InputError(fmt::format("{} declares {} values ({} bytes) but stores {} bytes", what,
                                 values, declared, stored));
}

std::string read_dataset_string(hid_t parent, const char* name) {
  if (!exists(parent, name)) return {};
  Handle d = open_dataset(parent, name);
  Handle type(H5Dget_type(d), H5Tclose);
  Handle space(H5Dget_space(d), H5Sclose);
  const std::string what = fmt::format("dataset {}", name_of(d));
  require_single(type, space, true, what);
  const std::size_t n = H5Tget_size(type);
  require_stored(d, 1, n, what);
  std::string s(n, '\0');
  Handle mem = string_type(n, H5Tget_cset(type));
  check(H5Dread(d, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, s.data()), "H5Dread");
  s.resize(std::strlen(s.c_str()));
  return s;
}
std::vector<double> read_doubles(hid_t parent, const char* name) {
  Handle d = open_dataset(parent, name);
  Handle type(H5Dget_type(d), H5Tclose);
  Handle space(H5Dget_space(d), H5Sclose);
  const std::string what = fmt::format("dataset {}", name_of(d));
  const H5T_class_t cls = H5Tget_class(type);
  if (cls != H5T_INTEGER && cls != H5T_FLOAT)
    throw InputError(fmt::format("{} has another type (accepted: integer or floating-point "
                                 "numbers)",
                                 what));
  const hssize_t n = H5Sget_simple_extent_type(space) == H5S_NULL
                         ? 0
                         : H5Sget_simple_extent_npoints(space);
  if (n < 0 || n > max_dataset_values)
    throw InputError(
        fmt::format("{} declares {} values (accepted: 0 to {})", what, n, max_dataset_values));
  require_stored(d, n, H5Tget_size(type), what);
  std::vector<double> v(static_cast<std::size_t>(n));
  if (n > 0)
    check(H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), "H5Dread");
  return v;
}
std::optional<std::vector<double>> read_optional(hid_t parent, const char* name) {
  if (!exists(parent, name)) return std::nullopt;
  return read_doubles(parent, name);
}

/// Every attribute of /diagnostics by its HDF5 class (integer, float, string), every dataset as
/// a series.
void read_diagnostics(hid_t g, Diagnostics& d) {
  std::vector<std::string> names;
  const auto collect = [](hid_t, const char* name, const H5A_info_t*, void* out) -> herr_t {
    static_cast<std::vector<std::string>*>(out)->push_back(name);
    return 0;
  };
  check(H5Aiterate2(g, H5_INDEX_NAME, H5_ITER_INC, nullptr, collect, &names), "H5Aiterate2");
  for (const std::string& name : names) {
    Handle a(H5Aopen(g, name.c_str(), H5P_DEFAULT), H5Aclose);
    if (!a.valid()) throw InputError("unreadable attribute in /diagnostics");
    Handle type(H5Aget_type(a), H5Tclose);
    switch (H5Tget_class(type)) {
      case H5T_INTEGER: d.counts[name] = read_attr_int(g, name.c_str()); break;
      case H5T_FLOAT: d.values[name] = read_attr_double(g, name.c_str()); break;
      case H5T_STRING: d.texts[name] = read_attr_string(g, name.c_str()); break;
      default: throw InputError(fmt::format("/diagnostics attribute {} has an unknown type", name));
    }
  }
  H5G_info_t ginfo;
  check(H5Gget_info(g, &ginfo), "H5Gget_info");
  for (hsize_t i = 0; i < ginfo.nlinks; ++i) {
    const ssize_t n = H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0,
                                         H5P_DEFAULT);
    if (n < 0) throw InputError("unreadable dataset in /diagnostics");
    std::string name(static_cast<std::size_t>(n), '\0');
    H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size() + 1,
                       H5P_DEFAULT);
    d.series[name] = read_doubles(g, name.c_str());
  }
}

/// Group @p name of the root; InputError when it is missing or not a group.
Handle open_group(hid_t file, const char* name) {
  Handle g(H5Gopen2(file, name, H5P_DEFAULT), H5Gclose);
  if (!g.valid()) throw InputError(fmt::format("missing group /{}", name));
  return g;
}

/// Refuses a series of group @p group whose length differs from that of its first series: the
/// readers of a file (compare, summaries, scripts) index them together.
void require_length(const char* group, const char* name, const std::vector<double>& v,
                    const char* first_name, const std::vector<double>& first) {
  if (v.size() != first.size())
    throw InputError(fmt::format("/{0}/{1} has {2} values, /{0}/{3} {4} (accepted: the same "
                                 "number)",
                                 group, name, v.size(), first_name, first.size()));
}
void require_length(const char* group, const char* name,
                    const std::optional<std::vector<double>>& v, const char* first_name,
                    const std::vector<double>& first) {
  if (v) require_length(group, name, *v, first_name, first);
}

RunResult read_body(hid_t file) {
  RunResult r;
  if (read_attr_string(file, "schema") != "grainlift")
    throw InputError("not a grainlift result file (no schema = \"grainlift\" attribute)");
  const long long version = read_attr_int(file, "schema_version");
  if (version > schema_version)
    throw InputError(fmt::format("schema_version {} is newer than this grainlift reads ({})",
                                 version, schema_version));
  if (version < 1)
    throw InputError(fmt::format("schema_version {} (accepted: 1 to {})", version, schema_version));
  {
    Handle g = open_group(file, "metadata");
    r.meta.solver = read_attr_string(g, "solver");
    r.meta.grainlift_version = read_attr_string(g, "grainlift_version");
    r.meta.git_revision = read_attr_string(g, "git_revision");
    r.meta.threads = int(read_attr_int(g, "threads"));
    r.meta.wall_seconds = read_attr_double(g, "wall_seconds");
    r.meta.created_utc = read_attr_string(g, "created_utc");
    r.meta.notes = read_attr_string(g, "notes");
    r.meta.partial = has_attr(g, "partial") && read_attr_int(g, "partial") != 0;
  }
  {
    Handle g = open_group(file, "case");
    r.meta.case_text = read_dataset_string(g, "text");
    r.meta.case_overrides = read_dataset_string(g, "overrides");
    r.meta.case_hash = read_attr_string(g, "hash");
    r.meta.case_path = read_attr_string(g, "path");
  }
  {
    Handle g = open_group(file, "geometry");
    for (const auto& [name, member] : geometry_fields)
      if (!optional_geometry_field(name) || H5Aexists(g, name) > 0)
        r.geometry.*member = read_attr_double(g, name);
  }
  if (exists(file, "forces")) {
    Handle g = open_group(file, "forces");
    ForceSeries f;
    f.time = read_doubles(g, "time");
    f.fx = read_doubles(g, "fx");
    f.fy = read_doubles(g, "fy");
    f.torque = read_doubles(g, "torque");
    if (exists(g, "contacts")) f.contacts = read_doubles(g, "contacts");
    require_length("forces", "fx", f.fx, "time", f.time);
    require_length("forces", "fy", f.fy, "time", f.time);
    require_length("forces", "torque", f.torque, "time", f.time);
    if (!f.contacts.empty()) require_length("forces", "contacts", f.contacts, "time", f.time);
    r.forces = std::move(f);
  }
  if (exists(file, "lid")) {
    Handle g = open_group(file, "lid");
    LidSeries l;
    l.time = read_doubles(g, "time");
    l.y = read_doubles(g, "y");
    l.pressure = read_doubles(g, "pressure");
    l.target = read_attr_double(g, "target");
    l.mean = read_attr_double(g, "mean");
    l.mean_stderr = read_attr_optional(g, "mean_stderr");
    l.mass = read_attr_double(g, "mass");
    l.damping = read_attr_double(g, "damping");
    require_length("lid", "y", l.y, "time", l.time);
    require_length("lid", "pressure", l.pressure, "time", l.time);
    r.lid = std::move(l);
  }
  if (exists(file, "far_field")) {
    Handle g = open_group(file, "far_field");
    FarFieldSeries ff;
    ff.time = read_doubles(g, "time");
    ff.pressure = read_doubles(g, "pressure");
    ff.stress_xx = read_doubles(g, "stress_xx");
    ff.stress_xy = read_doubles(g, "stress_xy");
    ff.stress_yy = read_doubles(g, "stress_yy");
    ff.mean = read_attr_double(g, "mean");
    ff.mean_stderr = read_attr_optional(g, "mean_stderr");
    ff.exclusion = read_attr_double(g, "exclusion");
    ff.half_height = read_attr_double(g, "half_height");
    for (const auto& [name, v] : {std::pair{"pressure", &ff.pressure},
                                  {"stress_xx", &ff.stress_xx},
                                  {"stress_xy", &ff.stress_xy},
                                  {"stress_yy", &ff.stress_yy}})
      require_length("far_field", name, *v, "time", ff.time);
    r.far_field = std::move(ff);
  }
  if (exists(file, "bed")) {
    Handle g = open_group(file, "bed");
    BedStructure b;
    b.contacts_per_grain = read_attr_double(g, "contacts_per_grain");
    b.rattler_fraction = read_attr_double(g, "rattler_fraction");
    b.fabric_xx = read_attr_double(g, "fabric_xx");
    b.fabric_xy = read_attr_double(g, "fabric_xy");
    b.fabric_yy = read_attr_double(g, "fabric_yy");
    b.mean_gap = read_attr_double(g, "mean_gap");
    b.gap_edges = read_doubles(g, "gap_edges");
    b.gap_fraction = read_doubles(g, "gap_fraction");
    b.band_y = read_doubles(g, "band_y");
    b.band_area_fraction = read_doubles(g, "band_area_fraction");
    b.ring_r = read_doubles(g, "ring_r");
    b.ring_area_fraction = read_doubles(g, "ring_area_fraction");
    if (b.gap_edges.size() != b.gap_fraction.size() + 1)
      throw InputError(fmt::format("/bed/gap_edges holds {} values, /bed/gap_fraction {} "
                                   "(accepted: one edge more than bins)", b.gap_edges.size(),
                                   b.gap_fraction.size()));
    require_length("bed", "band_area_fraction", b.band_area_fraction, "band_y", b.band_y);
    require_length("bed", "ring_area_fraction", b.ring_area_fraction, "ring_r", b.ring_r);
    r.bed = std::move(b);
  }
  if (exists(file, "diagnostics")) {
    Handle g = open_group(file, "diagnostics");
    read_diagnostics(g, r.diagnostics);
  }
  if (exists(file, "means")) {
    Handle g = open_group(file, "means");
    MeanForces m;
    m.drag = read_attr_double(g, "drag");
    m.lift = read_attr_double(g, "lift");
    m.torque = read_attr_double(g, "torque");
    m.drag_stderr = read_attr_optional(g, "drag_stderr");
    m.lift_stderr = read_attr_optional(g, "lift_stderr");
    m.torque_stderr = read_attr_optional(g, "torque_stderr");
    m.contacts = read_attr_optional(g, "contacts");
    m.samples = read_attr_int(g, "samples");
    m.blocks = read_attr_int(g, "blocks");
    r.means = m;
  }
  if (exists(file, "surface")) {
    Handle g = open_group(file, "surface");
    SurfaceDistribution s;
    s.theta = read_doubles(g, "theta");
    s.sigma_n = read_doubles(g, "sigma_n");
    s.sigma_t = read_doubles(g, "sigma_t");
    s.kernel_width_deg = read_attr_double(g, "kernel_width_deg");
    if (exists(g, "sigma_n_pointwise")) s.sigma_n_pointwise = read_doubles(g, "sigma_n_pointwise");
    if (exists(g, "sigma_t_pointwise")) s.sigma_t_pointwise = read_doubles(g, "sigma_t_pointwise");
    if (exists(g, "sigma_n_stderr")) s.sigma_n_stderr = read_doubles(g, "sigma_n_stderr");
    if (exists(g, "sigma_t_stderr")) s.sigma_t_stderr = read_doubles(g, "sigma_t_stderr");
    require_length("surface", "sigma_n", s.sigma_n, "theta", s.theta);
    require_length("surface", "sigma_t", s.sigma_t, "theta", s.theta);
    require_length("surface", "sigma_n_pointwise", s.sigma_n_pointwise, "theta", s.theta);
    require_length("surface", "sigma_t_pointwise", s.sigma_t_pointwise, "theta", s.theta);
    require_length("surface", "sigma_n_stderr", s.sigma_n_stderr, "theta", s.theta);
    require_length("surface", "sigma_t_stderr", s.sigma_t_stderr, "theta", s.theta);
    r.surface = std::move(s);
  }
  if (exists(file, "histogram")) {
    Handle g = open_group(file, "histogram");
    SurfaceHistogram h;
    h.theta_lo = read_doubles(g, "theta_lo");
    h.theta_hi = read_doubles(g, "theta_hi");
    h.contact_count = read_doubles(g, "contact_count");
    h.normal_force = read_doubles(g, "normal_force");
    h.tangential_force = read_doubles(g, "tangential_force");
    h.slip_fraction = read_doubles(g, "slip_fraction");
    for (const auto& [name, v] : {std::pair{"theta_hi", &h.theta_hi},
                                  {"contact_count", &h.contact_count},
                                  {"normal_force", &h.normal_force},
                                  {"tangential_force", &h.tangential_force},
                                  {"slip_fraction", &h.slip_fraction}})
      require_length("histogram", name, *v, "theta_lo", h.theta_lo);
    r.histogram = std::move(h);
  }
  if (exists(file, "fields")) {
    Handle g = open_group(file, "fields");
    FieldGrid f;
    f.x = read_doubles(g, "x");
    f.y = read_doubles(g, "y");
    f.velocity_x = read_optional(g, "velocity_x");
    f.velocity_y = read_optional(g, "velocity_y");
    f.pressure = read_optional(g, "pressure");
    f.stress_xx = read_optional(g, "stress_xx");
    f.stress_xy = read_optional(g, "stress_xy");
    f.stress_yy = read_optional(g, "stress_yy");
    f.area_fraction = read_optional(g, "area_fraction");
    f.granular_temperature = read_optional(g, "granular_temperature");
    // every field holds one value per cell: ny rows of nx (row-major, y the slow index)
    const std::size_t cells = f.x.size() * f.y.size();
    for (const auto& [name, v] :
         {std::pair{"velocity_x", &f.velocity_x}, {"velocity_y", &f.velocity_y},
          {"pressure", &f.pressure}, {"stress_xx", &f.stress_xx}, {"stress_xy", &f.stress_xy},
          {"stress_yy", &f.stress_yy}, {"area_fraction", &f.area_fraction},
          {"granular_temperature", &f.granular_temperature}})
      if (*v && (*v)->size() != cells)
        throw InputError(fmt::format("/fields/{} has {} values (accepted: one per cell, "
                                     "len(y) x len(x) = {} x {})",
                                     name, (*v)->size(), f.y.size(), f.x.size()));
    r.fields = std::move(f);
  }
  return r;
}

/// HDF5 prints its error stack to stderr by default; grainlift reports errors itself.
void silence_hdf5() {
  static const bool done = [] {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)done;
}

}  // namespace

void write_result(const std::string& path, const RunResult& result) {
  silence_hdf5();
  const std::string tmp = temporary_path_for(path);
  {
    Handle file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
    if (!file.valid()) throw InputError(fmt::format("{}: cannot create the file", path));
    try {
      write_body(file, result);
    } catch (...) {
      std::remove(tmp.c_str());
      throw;
    }
    if (H5Fflush(file, H5F_SCOPE_GLOBAL) < 0) {
      std::remove(tmp.c_str());
      throw RunError(fmt::format("{}: flushing the file failed", path));
    }
  }
  commit_file(tmp, path);
}

RunResult read_result(const std::string& path) {
  silence_hdf5();
  Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file.valid()) throw InputError(fmt::format("{}: cannot open as an HDF5 file", path));
  try {
    return read_body(file);
  } catch (const std::exception& e) {
    throw InputError(fmt::format("{}: {}", path, e.what()));
  }
}

void write_fields_xdmf(const std::string& xmf_path, const std::string& h5_name,
                       const RunResult& r) {
  if (!r.fields || r.fields->x.size() < 2 || r.fields->y.size() < 2) return;
  const FieldGrid& f = *r.fields;
  const std::size_t nx = f.x.size(), ny = f.y.size();
  const double dx = f.x[1] - f.x[0], dy = f.y[1] - f.y[0];
  // Cell-centred data on a co-rectilinear grid: nodes at the cell corners.
  std::string attrs;
  auto add = [&](const char* name, const std::optional<std::vector<double>>& v) {
    if (!v) return;
    attrs += fmt::format(
        "      <Attribute Name=\"{0}\" AttributeType=\"Scalar\" Center=\"Cell\">\n"
        "        <DataItem Dimensions=\"{1} {2}\" NumberType=\"Float\" Precision=\"8\" "
        "Format=\"HDF\">{3}:/fields/{0}</DataItem>\n      </Attribute>\n",
        name, ny, nx, h5_name);
  };
  add("velocity_x", f.velocity_x);
  add("velocity_y", f.velocity_y);
  add("pressure", f.pressure);
  add("stress_xx", f.stress_xx);
  add("stress_xy", f.stress_xy);
  add("stress_yy", f.stress_yy);
  add("area_fraction", f.area_fraction);
  add("granular_temperature", f.granular_temperature);
  const std::string text = fmt::format(
      "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n"
      "    <Grid Name=\"{0} fields (intruder frame)\" GridType=\"Uniform\">\n"
      "      <Topology TopologyType=\"2DCoRectMesh\" Dimensions=\"{1} {2}\"/>\n"
      "      <Geometry GeometryType=\"ORIGIN_DXDY\">\n"
      "        <DataItem Dimensions=\"2\" NumberType=\"Float\" Format=\"XML\">{3} {4}</DataItem>\n"
      "        <DataItem Dimensions=\"2\" NumberType=\"Float\" Format=\"XML\">{5} {6}</DataItem>\n"
      "      </Geometry>\n{7}    </Grid>\n  </Domain>\n</Xdmf>\n",
      r.meta.solver, ny + 1, nx + 1, f.y[0] - 0.5 * dy, f.x[0] - 0.5 * dx, dy, dx, attrs);
  write_text_atomically(xmf_path, text);
}

}  // namespace grainlift
