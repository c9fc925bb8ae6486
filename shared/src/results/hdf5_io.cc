// The HDF5 primitives of the result file (hdf5_io.h): one attribute, dataset or group at a time,
// every read checked against what the file declares.
#include "results/hdf5_io.h"

#include <fmt/format.h>

#include <cstring>

#include "grainlift/shared/errors.h"

namespace grainlift::hdf5 {

void check(herr_t status, const std::string& what) {
  if (status < 0) throw RunError("HDF5: " + what + " failed");
}

Handle make_group(hid_t parent, const char* name) {
  Handle g(H5Gcreate2(parent, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  if (!g.valid()) throw RunError(fmt::format("HDF5: cannot create group {}", name));
  return g;
}

Handle string_type(std::size_t size, H5T_cset_t cset) {
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

namespace {
/// One scalar attribute of memory and file type @p type holding *@p value.
void attr_scalar(hid_t obj, const char* name, hid_t type, const void* value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle a(H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!a.valid()) throw RunError(fmt::format("HDF5: cannot create attribute {}", name));
  check(H5Awrite(a, type, value), "H5Awrite");
}
}  // namespace

void attr_number(hid_t obj, const char* name, double value) {
  attr_scalar(obj, name, H5T_NATIVE_DOUBLE, &value);
}
void attr_number(hid_t obj, const char* name, long long value) {
  attr_scalar(obj, name, H5T_NATIVE_LLONG, &value);
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

void dataset_doubles(hid_t parent, const char* name, const std::vector<double>& v,
                     const char* units, std::size_t ny, std::size_t nx) {
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

// Every read checks what the file declares before it allocates or reads: a file is refused
// (InputError, naming the object and what is accepted) rather than read past a buffer or
// allocated for data it does not hold.

bool exists(hid_t parent, const char* name) { return H5Lexists(parent, name, H5P_DEFAULT) > 0; }
bool has_attr(hid_t obj, const char* name) { return H5Aexists(obj, name) > 0; }

std::string name_of(hid_t obj) {
  const ssize_t n = H5Iget_name(obj, nullptr, 0);
  if (n <= 0) return "?";
  std::string s(static_cast<std::size_t>(n), '\0');
  H5Iget_name(obj, s.data(), s.size() + 1);
  return s;
}

namespace {

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

}  // namespace

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

namespace {

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

}  // namespace

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

namespace {

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

}  // namespace

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

Handle open_group(hid_t file, const char* name) {
  Handle g(H5Gopen2(file, name, H5P_DEFAULT), H5Gclose);
  if (!g.valid()) throw InputError(fmt::format("missing group /{}", name));
  return g;
}

void silence_hdf5() {
  static const bool done = [] {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)done;
}

}  // namespace grainlift::hdf5
