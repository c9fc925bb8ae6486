// The structure-aware input of the result-file fuzz target: a little program of operations that
// builds an HDF5 file with the HDF5 C API, so that mutations change what the file holds
// (groups, datasets, attributes, their types, shapes and values) rather than the bytes of
// libhdf5's own format, which read_result does not parse and grainlift cannot fix.
//
// Input: one byte of file flags, then operations until the input ends (at most max_ops):
//   flags: bit 0 latest file format, bit 1 attributes in dense storage, bit 2 creation order
//          tracked (iteration order of /diagnostics)
//   op % 6 = 0 GROUP name     open or create group `name` in the current group; it becomes
//                             the current group (the root is the first)
//            1 UP             back to the parent group
//            2 ATTR name value   attribute of the current group
//            3 DATASET name value  dataset in the current group; it becomes the last dataset
//            4 DATTR name value  attribute of the last dataset (of the group if none)
//            5 LINK name text  soft link `name` to the path `text` (may dangle)
//   name:  a byte b; b < 255 picks schema_names()[b % size], 255 is followed by a literal
//          (length byte, then the characters)
//   value: kind byte (value_kinds below); for strings a size byte (0: the text's length) and
//          a flags byte (padding, character set); a space byte (scalar, null, simple) with, for
//          simple, a rank byte and one byte per dimension (dim_of: 0-247 as they are, 248-255
//          huge); a layout byte (datasets only); a fill byte: 0 ramp (strings: text_table
//          entry), 1 one byte per element into special_values(), 2 raw bytes of the file type
//          (strings: a literal), 3 nothing written (fill values only)
// Both the builder (build_result_file) and the encoder of existing files (describe_file, for
// seeds) are here, so the seeds stay in step with the format.
#pragma once

#include <hdf5.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace grainlift::fuzz {

/// Every name docs/schema.md uses (groups, datasets, attributes), and a few it does not.
inline const std::vector<std::string>& schema_names() {
  static const std::vector<std::string> names = {
      // groups
      "metadata", "case", "geometry", "forces", "lid", "far_field", "means", "surface",
      "histogram", "derived", "diagnostics", "fields",
      // / and /metadata
      "schema", "schema_version", "solver", "grainlift_version", "git_revision", "threads",
      "wall_seconds", "created_utc", "notes", "partial",
      // /case
      "text", "overrides", "hash", "hash_algorithm", "path",
      // /geometry
      "intruder_diameter", "intruder_x", "intruder_y", "grain_diameter", "domain_xmin",
      "domain_xmax", "domain_ymin", "domain_ymax", "velocity_x", "velocity_y", "omega",
      "gravity_x", "gravity_y", "bulk_density", "pressure_scale", "reference_gravity",
      "equivalent_depth",
      // /forces, /lid, /far_field
      "time", "fx", "fy", "torque", "contacts", "y", "pressure", "target", "mean",
      "mean_stderr", "mass", "damping", "stress_xx", "stress_xy", "stress_yy", "exclusion",
      "half_height",
      // /means
      "drag", "lift", "drag_stderr", "lift_stderr", "torque_stderr", "samples", "blocks",
      // /surface
      "theta", "sigma_n", "sigma_t", "kernel_width_deg", "sigma_n_pointwise",
      "sigma_t_pointwise", "sigma_n_stderr", "sigma_t_stderr",
      // /histogram
      "theta_lo", "theta_hi", "contact_count", "normal_force", "tangential_force",
      "slip_fraction",
      // /fields
      "x", "area_fraction", "granular_temperature",
      // /derived, /diagnostics, datasets' attribute
      "units", "spin_ratio", "lift_over_drag", "buoyancy", "drag_coefficient",
      "sigma_n_symmetric", "drag_mesh_error", "residual_history", "converged", "linear_solver",
      "extra",
      // /bed (appended: the indices above are those of the corpus files)
      "bed", "contacts_per_grain", "rattler_fraction", "fabric_xx", "fabric_xy", "fabric_yy",
      "mean_gap", "gap_edges", "gap_fraction", "band_y", "band_area_fraction", "ring_r",
      "ring_area_fraction"};
  return names;
}

/// Texts a string value can take by index (fill 0).
inline const std::vector<std::string>& text_table() {
  static const std::vector<std::string> t = {"grainlift", "dem", "fem", "", "m", "Pa", "1", "s",
                                             "N/m", "direct"};
  return t;
}

/// Values a number can take by index (fill 1): the edges a reader must survive.
inline double special_value(std::uint8_t i) {
  static const double v[] = {0.0,
                             1.0,
                             -1.0,
                             0.5,
                             2.0,
                             3.14159265358979323846,
                             std::numeric_limits<double>::quiet_NaN(),
                             std::numeric_limits<double>::infinity(),
                             -std::numeric_limits<double>::infinity(),
                             std::numeric_limits<double>::max(),
                             -std::numeric_limits<double>::max(),
                             std::numeric_limits<double>::denorm_min(),
                             -0.0,
                             1e-300,
                             1e20,
                             -1e20,
                             2147483648.0,
                             9.3e18,
                             100.0,
                             24.0};
  return v[i % (sizeof v / sizeof v[0])];
}

enum ValueKind : std::uint8_t {
  f64le, f64be, f32le, i64le, i32le, u8, fixed_string, vlen_string, compound, array_f64,
  value_kinds
};

inline constexpr int max_ops = 512;
inline constexpr std::size_t max_written_elements = 4096;  ///< larger spaces stay unwritten

/// Dimension of a dimension byte: 0-247 as they are, then sizes no file should declare.
inline hsize_t dim_of(std::uint8_t b) {
  static const hsize_t huge[8] = {4097, hsize_t(1) << 16, hsize_t(1) << 24, hsize_t(1) << 31,
                                  hsize_t(1) << 32, hsize_t(1) << 40, hsize_t(1) << 52,
                                  hsize_t(1) << 62};
  return b < 248 ? b : huge[b - 248];
}

// ---- building -----------------------------------------------------------------------------

class InputBytes {
 public:
  InputBytes(const std::uint8_t* p, std::size_t n) : p_(p), end_(p + n) {}
  bool more() const { return p_ < end_; }
  std::uint8_t u8() { return p_ < end_ ? *p_++ : 0; }
  /// @p n bytes, zeros past the end of the input.
  std::vector<unsigned char> take(std::size_t n) {
    std::vector<unsigned char> b(n, 0);
    const std::size_t k = std::min<std::size_t>(n, static_cast<std::size_t>(end_ - p_));
    if (k) std::memcpy(b.data(), p_, k);
    p_ += k;
    return b;
  }
  std::string literal() {
    const std::size_t n = u8();
    const std::vector<unsigned char> b = take(n);
    return std::string(b.begin(), b.end());
  }
  std::string name() {
    const std::uint8_t b = u8();
    if (b == 255) return literal();
    return schema_names()[b % schema_names().size()];
  }

 private:
  const std::uint8_t* p_;
  const std::uint8_t* end_;
};

/// One value (type, space, data) read from the input, then created as an attribute or dataset.
struct ValueSpec {
  std::uint8_t kind = f64le;
  std::uint8_t string_size = 0, string_flags = 0;
  bool null_space = false, scalar = true;
  std::vector<hsize_t> dims;
  std::uint8_t layout = 0, fill = 3;
  std::vector<std::uint8_t> picks;    // fill 1
  std::vector<unsigned char> raw;     // fill 2, numbers
  std::string text;                   // fill 0, 1 and 2 of strings
  double ramp_a = 0, ramp_b = 1;      // fill 0, numbers

  /// elements of the space (0 for null; saturates)
  std::size_t elements() const {
    if (null_space) return 0;
    std::size_t n = 1;
    for (hsize_t d : dims) {
      if (d == 0) return 0;
      if (n > std::numeric_limits<std::size_t>::max() / d)
        return std::numeric_limits<std::size_t>::max();
      n *= static_cast<std::size_t>(d);
    }
    return n;
  }
  bool is_string() const { return kind == fixed_string || kind == vlen_string; }
  bool is_integer() const { return kind == i64le || kind == i32le || kind == u8; }
};

inline hid_t file_type_of(const ValueSpec& v) {
  switch (v.kind) {
    case f64le: return H5Tcopy(H5T_IEEE_F64LE);
    case f64be: return H5Tcopy(H5T_IEEE_F64BE);
    case f32le: return H5Tcopy(H5T_IEEE_F32LE);
    case i64le: return H5Tcopy(H5T_STD_I64LE);
    case i32le: return H5Tcopy(H5T_STD_I32LE);
    case u8: return H5Tcopy(H5T_STD_U8LE);
    case fixed_string:
    case vlen_string: {
      const hid_t t = H5Tcopy(H5T_C_S1);
      if (v.kind == vlen_string)
        H5Tset_size(t, H5T_VARIABLE);
      else
        H5Tset_size(t, v.string_size ? v.string_size : std::max<std::size_t>(1, v.text.size()));
      H5Tset_strpad(t, std::array<H5T_str_t, 3>{H5T_STR_NULLPAD, H5T_STR_NULLTERM,
                                                H5T_STR_SPACEPAD}[v.string_flags % 3]);
      H5Tset_cset(t, (v.string_flags / 3) % 2 ? H5T_CSET_UTF8 : H5T_CSET_ASCII);
      return t;
    }
    case compound: {
      const hid_t t = H5Tcreate(H5T_COMPOUND, 16);
      H5Tinsert(t, "a", 0, H5T_IEEE_F64LE);
      H5Tinsert(t, "b", 8, H5T_STD_I64LE);
      return t;
    }
    default: {
      const hsize_t two = 2;
      return H5Tarray_create2(H5T_IEEE_F64LE, 1, &two);
    }
  }
}

inline ValueSpec read_value(InputBytes& in, bool dataset) {
  ValueSpec v;
  v.kind = in.u8() % value_kinds;
  if (v.is_string()) {
    v.string_size = in.u8();
    v.string_flags = in.u8();
  }
  const std::uint8_t space = in.u8() % 4;
  v.null_space = space == 1;
  v.scalar = space == 0;
  if (space >= 2) {
    const int rank = 1 + in.u8() % 3;
    for (int k = 0; k < rank; ++k) v.dims.push_back(dim_of(in.u8()));
  }
  if (dataset) v.layout = in.u8() % 3;
  v.fill = in.u8() % 4;
  const std::size_t n = std::min(v.elements(), max_written_elements + 1);
  if (n > max_written_elements) v.fill = 3;
  if (v.is_string()) {
    if (v.fill == 0) v.text = text_table()[in.u8() % text_table().size()];
    if (v.fill == 1 || v.fill == 2) v.text = in.literal();
  } else if (v.fill == 0) {
    v.ramp_a = special_value(in.u8());
    v.ramp_b = special_value(in.u8());
  } else if (v.fill == 1) {
    for (std::size_t k = 0; k < n; ++k) v.picks.push_back(in.u8());
  } else if (v.fill == 2) {
    const hid_t t = file_type_of(v);
    v.raw = in.take(n * H5Tget_size(t));
    H5Tclose(t);
  }
  return v;
}

/// Creates the value as attribute (@p dataset false) or dataset @p name of @p where.
/// Returns the dataset (to be closed by the caller) or -1.
inline hid_t create_value(hid_t where, const std::string& name, const ValueSpec& v,
                          bool dataset, hid_t ocpl) {
  const hid_t type = file_type_of(v);
  hid_t space;
  if (v.null_space)
    space = H5Screate(H5S_NULL);
  else if (v.scalar)
    space = H5Screate(H5S_SCALAR);
  else
    space = H5Screate_simple(int(v.dims.size()), v.dims.data(), nullptr);
  hid_t obj = -1;
  const std::size_t n = v.elements();
  if (dataset) {
    hid_t dcpl = H5Pcopy(ocpl);
    // a space too large to write, and any other when asked, is chunked (nothing allocated
    // until written); compact keeps the data in the object header
    const bool chunked = v.layout == 1 || n > max_written_elements;
    if (chunked && !v.scalar && !v.null_space) {
      std::vector<hsize_t> chunk(v.dims.size()), maxdims(v.dims.size(), H5S_UNLIMITED);
      for (std::size_t k = 0; k < v.dims.size(); ++k)
        chunk[k] = std::max<hsize_t>(1, std::min<hsize_t>(v.dims[k], 16));
      H5Sset_extent_simple(space, int(v.dims.size()), v.dims.data(), maxdims.data());
      H5Pset_chunk(dcpl, int(chunk.size()), chunk.data());
    } else if (v.layout == 2) {
      H5Pset_layout(dcpl, H5D_COMPACT);
    }
    obj = H5Dcreate2(where, name.c_str(), type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    H5Pclose(dcpl);
  } else if (n <= max_written_elements) {
    // an attribute has no chunked layout: libhdf5 allocates its whole space at creation (an
    // abort under ASan for a huge one, in the builder, not the reader), so larger attribute
    // spaces are not built
    obj = H5Acreate2(where, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
  }
  if (obj >= 0 && v.fill != 3 && n > 0 && n <= max_written_elements) {
    auto write = [&](hid_t mem, const void* buf) {
      if (dataset)
        H5Dwrite(obj, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf);
      else
        H5Awrite(obj, mem, buf);
    };
    if (v.kind == vlen_string) {
      std::vector<const char*> p(n, v.text.c_str());
      write(type, p.data());
    } else if (v.kind == fixed_string) {
      const std::size_t size = H5Tget_size(type);
      std::vector<char> buf(n * size, '\0');
      for (std::size_t k = 0; k < buf.size(); ++k)
        if (v.fill == 2 ? k < v.text.size() : k % size < v.text.size())
          buf[k] = v.fill == 2 ? v.text[k] : v.text[k % size];
      write(type, buf.data());
    } else if (v.fill == 2) {
      write(type, v.raw.data());
    } else if (v.kind == compound || v.kind == array_f64) {
      std::vector<double> d(2 * n);
      for (std::size_t k = 0; k < d.size(); ++k)
        d[k] = v.fill == 0 ? v.ramp_a + double(k) * v.ramp_b : special_value(v.picks[k / 2]);
      if (v.kind == array_f64) {
        write(type, d.data());
      } else {
        // {double, int64}: the second member from the same numbers, saturated
        std::vector<unsigned char> buf(16 * n);
        for (std::size_t k = 0; k < n; ++k) {
          const double b = d[2 * k + 1];
          const long long i =
              std::isfinite(b) && std::abs(b) < 9e18 ? static_cast<long long>(b) : 0;
          std::memcpy(&buf[16 * k], &d[2 * k], 8);
          std::memcpy(&buf[16 * k + 8], &i, 8);
        }
        write(type, buf.data());
      }
    } else {
      std::vector<double> d(n);
      for (std::size_t k = 0; k < n; ++k)
        d[k] = v.fill == 0 ? v.ramp_a + double(k) * v.ramp_b : special_value(v.picks[k]);
      if (v.is_integer()) {
        std::vector<long long> i(n);
        for (std::size_t k = 0; k < n; ++k)
          i[k] = std::isfinite(d[k]) && std::abs(d[k]) < 9e18 ? static_cast<long long>(d[k])
                                                             : (d[k] < 0 ? -1 : 1) * (1LL << 62);
        write(H5T_NATIVE_LLONG, i.data());
      } else {
        write(H5T_NATIVE_DOUBLE, d.data());
      }
    }
  }
  if (!dataset && obj >= 0) H5Aclose(obj), obj = -1;
  H5Sclose(space);
  H5Tclose(type);
  return obj;
}

/// @brief Builds the HDF5 file that the input @p data describes at @p path (replacing it).
/// Operations HDF5 refuses (a name that exists, an attribute too large) are skipped.
inline void build_result_file(const std::uint8_t* data, std::size_t size,
                              const std::string& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  InputBytes in(data, size);
  const std::uint8_t flags = in.u8();
  const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  if (flags & 1) H5Pset_libver_bounds(fapl, H5F_LIBVER_LATEST, H5F_LIBVER_LATEST);
  const hid_t fcpl = H5Pcreate(H5P_FILE_CREATE);
  const hid_t gcpl = H5Pcreate(H5P_GROUP_CREATE);
  const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  for (hid_t p : {fcpl, gcpl, dcpl}) {
    if (flags & 2) H5Pset_attr_phase_change(p, 0, 0);
    if (flags & 4) H5Pset_attr_creation_order(p, H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED);
  }
  if (flags & 4) {
    H5Pset_link_creation_order(fcpl, H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED);
    H5Pset_link_creation_order(gcpl, H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED);
  }
  const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, fcpl, fapl);
  if (file < 0) {
    for (hid_t p : {fapl, fcpl, gcpl, dcpl}) H5Pclose(p);
    return;
  }
  std::vector<hid_t> groups{file};  // groups.back() is the current group
  hid_t last = -1;
  for (int op = 0; op < max_ops && in.more(); ++op) {
    switch (in.u8() % 6) {
      case 0: {
        const std::string name = in.name();
        hid_t g = -1;
        if (H5Lexists(groups.back(), name.c_str(), H5P_DEFAULT) > 0)
          g = H5Gopen2(groups.back(), name.c_str(), H5P_DEFAULT);
        else
          g = H5Gcreate2(groups.back(), name.c_str(), H5P_DEFAULT, gcpl, H5P_DEFAULT);
        if (g >= 0) groups.push_back(g);
        break;
      }
      case 1:
        if (groups.size() > 1) {
          H5Gclose(groups.back());
          groups.pop_back();
        }
        break;
      case 2: {
        const std::string name = in.name();
        const ValueSpec v = read_value(in, false);
        create_value(groups.back(), name, v, false, dcpl);
        break;
      }
      case 3: {
        const std::string name = in.name();
        const ValueSpec v = read_value(in, true);
        const hid_t d = create_value(groups.back(), name, v, true, dcpl);
        if (d >= 0) {
          if (last >= 0) H5Dclose(last);
          last = d;
        }
        break;
      }
      case 4: {
        const std::string name = in.name();
        const ValueSpec v = read_value(in, false);
        create_value(last >= 0 ? last : groups.back(), name, v, false, dcpl);
        break;
      }
      default: {
        const std::string name = in.name();
        const std::string target = in.literal();
        H5Lcreate_soft(target.c_str(), groups.back(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT);
        break;
      }
    }
  }
  if (last >= 0) H5Dclose(last);
  for (std::size_t k = groups.size(); k-- > 1;) H5Gclose(groups[k]);
  H5Fclose(file);
  for (hid_t p : {fapl, fcpl, gcpl, dcpl}) H5Pclose(p);
}

// ---- describing an existing file (seeds) --------------------------------------------------

/// Writes the operations of the format above.
class OpWriter {
 public:
  std::vector<std::uint8_t> bytes;
  void u8(std::uint8_t b) { bytes.push_back(b); }
  void name(const std::string& n) {
    const auto& names = schema_names();
    const auto it = std::find(names.begin(), names.end(), n);
    if (it != names.end()) {
      u8(static_cast<std::uint8_t>(it - names.begin()));
    } else {
      u8(255);
      literal(n);
    }
  }
  void literal(const std::string& s) {
    const std::size_t n = std::min<std::size_t>(s.size(), 255);
    u8(static_cast<std::uint8_t>(n));
    bytes.insert(bytes.end(), s.begin(), s.begin() + n);
  }
};

/// Encodes the type, space and data of attribute or dataset @p obj. Kinds the format has no
/// word for are written as an unwritten f64 of the same space.
inline void describe_value(OpWriter& w, hid_t obj, bool dataset) {
  const hid_t type = dataset ? H5Dget_type(obj) : H5Aget_type(obj);
  const hid_t space = dataset ? H5Dget_space(obj) : H5Aget_space(obj);
  const H5T_class_t cls = H5Tget_class(type);
  const std::size_t size = H5Tget_size(type);
  std::uint8_t kind = f64le;
  bool known = true;
  if (cls == H5T_FLOAT)
    kind = size == 4 ? f32le : H5Tget_order(type) == H5T_ORDER_BE ? f64be : f64le;
  else if (cls == H5T_INTEGER)
    kind = size == 8 ? i64le : size == 4 ? i32le : u8;
  else if (cls == H5T_STRING)
    kind = H5Tis_variable_str(type) > 0 ? vlen_string : fixed_string;
  else
    known = false;
  w.u8(kind);
  if (kind == fixed_string || kind == vlen_string) {
    w.u8(kind == fixed_string && size < 256 ? static_cast<std::uint8_t>(size) : 0);
    const int pad = H5Tget_strpad(type) == H5T_STR_NULLPAD ? 0
                    : H5Tget_strpad(type) == H5T_STR_NULLTERM ? 1
                                                              : 2;
    w.u8(static_cast<std::uint8_t>(pad + 3 * (H5Tget_cset(type) == H5T_CSET_UTF8)));
  }
  const H5S_class_t sc = H5Sget_simple_extent_type(space);
  std::size_t n = 1;
  if (sc == H5S_NULL) {
    w.u8(1);
    n = 0;
  } else if (sc == H5S_SCALAR) {
    w.u8(0);
  } else {
    hsize_t dims[H5S_MAX_RANK];
    const int rank = std::min(3, H5Sget_simple_extent_dims(space, dims, nullptr));
    w.u8(2);
    w.u8(static_cast<std::uint8_t>(std::max(rank, 1) - 1));
    for (int k = 0; k < std::max(rank, 1); ++k) {
      const hsize_t d = rank > 0 ? std::min<hsize_t>(dims[k], 247) : 0;
      w.u8(static_cast<std::uint8_t>(d));
      n *= d;
    }
    if (rank == 0) n = 0;
  }
  if (dataset) w.u8(0);  // contiguous
  const hssize_t stored = H5Sget_simple_extent_npoints(space);
  if (!known || n == 0 || n > max_written_elements || hssize_t(n) != stored) {
    w.u8(3);  // nothing written
  } else if (kind == vlen_string) {
    w.u8(1);
    std::vector<char*> p(n, nullptr);
    const herr_t ok = dataset ? H5Dread(obj, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, p.data())
                              : H5Aread(obj, type, p.data());
    w.literal(ok >= 0 && p[0] ? p[0] : "");
    if (ok >= 0) H5Dvlen_reclaim(type, space, H5P_DEFAULT, p.data());
  } else {
    std::vector<unsigned char> buf(n * size);
    const herr_t ok = dataset ? H5Dread(obj, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data())
                              : H5Aread(obj, type, buf.data());
    if (kind == fixed_string) {
      w.u8(1);
      std::string s(buf.begin(), buf.end());
      if (n == 1) s.resize(std::strlen(s.c_str()));
      w.literal(ok >= 0 ? s : "");
    } else {
      w.u8(2);
      w.bytes.insert(w.bytes.end(), buf.begin(), buf.end());
    }
  }
  H5Sclose(space);
  H5Tclose(type);
}

inline void describe_attributes(OpWriter& w, hid_t obj, std::uint8_t op) {
  H5O_info_t info;
  if (H5Oget_info2(obj, &info, H5O_INFO_NUM_ATTRS) < 0) return;
  for (hsize_t k = 0; k < info.num_attrs; ++k) {
    const hid_t a = H5Aopen_by_idx(obj, ".", H5_INDEX_NAME, H5_ITER_INC, k, H5P_DEFAULT,
                                   H5P_DEFAULT);
    if (a < 0) continue;
    char name[256] = {0};
    H5Aget_name(a, sizeof name, name);
    w.u8(op);
    w.name(name);
    describe_value(w, a, false);
    H5Aclose(a);
  }
}

inline void describe_group(OpWriter& w, hid_t g) {
  describe_attributes(w, g, 2);
  H5G_info_t info;
  if (H5Gget_info(g, &info) < 0) return;
  for (hsize_t k = 0; k < info.nlinks; ++k) {
    char name[256] = {0};
    H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof name, H5P_DEFAULT);
    H5O_info_t oi;
    if (H5Oget_info_by_name2(g, name, &oi, H5O_INFO_BASIC, H5P_DEFAULT) < 0) continue;
    if (oi.type == H5O_TYPE_GROUP) {
      const hid_t sub = H5Gopen2(g, name, H5P_DEFAULT);
      w.u8(0);
      w.name(name);
      describe_group(w, sub);
      w.u8(1);
      H5Gclose(sub);
    } else if (oi.type == H5O_TYPE_DATASET) {
      const hid_t d = H5Dopen2(g, name, H5P_DEFAULT);
      w.u8(3);
      w.name(name);
      describe_value(w, d, true);
      describe_attributes(w, d, 4);
      H5Dclose(d);
    }
  }
}

/// @brief The operations that rebuild the file at @p path (empty when it cannot be opened).
inline std::vector<std::uint8_t> describe_file(const std::string& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return {};
  OpWriter w;
  w.u8(0);  // flags
  const hid_t root = H5Gopen2(f, "/", H5P_DEFAULT);
  describe_group(w, root);
  H5Gclose(root);
  H5Fclose(f);
  return w.bytes;
}

}  // namespace grainlift::fuzz
