// The reader of <out>/<solver>.h5 (result_file.h), driven by the schema table (result_schema.h):
// every group and member the table reads back, refused (InputError, naming the object and what
// is accepted) when a required one is missing or the lengths of a group's series disagree.
#include <fmt/format.h>

#include <map>
#include <stdexcept>

#include "grainlift/shared/errors.h"
#include "grainlift/shared/results/result_file.h"
#include "grainlift/shared/results/result_schema.h"
#include "results/hdf5_io.h"

namespace grainlift {
namespace {

using namespace hdf5;

/// Reads value @p name of entry @p e's type from @p obj.
SchemaValue read_value(hid_t obj, const SchemaEntry& e, const char* name) {
  const bool attribute = e.kind == SchemaKind::attribute;
  switch (e.type) {
    case SchemaType::text:
      return attribute ? read_attr_string(obj, name) : read_dataset_string(obj, name);
    case SchemaType::int64:
      if (attribute) return read_attr_int(obj, name);
      break;
    case SchemaType::float64:
      if (attribute) return read_attr_double(obj, name);
      break;
    case SchemaType::float64_array:
      if (!attribute) return read_doubles(obj, name);
      break;
    case SchemaType::none: break;
  }
  throw std::logic_error(fmt::format("schema entry {} has no reader for its type", e.path()));
}

bool in_file(hid_t obj, const SchemaEntry& e) {
  return e.kind == SchemaKind::attribute ? has_attr(obj, e.name) : exists(obj, e.name);
}

/// A dataset read and its number of values, for the checks of lengths.
struct ReadArray {
  const SchemaEntry* entry;
  std::size_t size;
};

/// Refuses arrays of @p group whose lengths disagree with their shapes: one-dimensional ones
/// with the same symbol hold as many values as the first read; two-dimensional ones [a, b]
/// hold len(a) x len(b) (the readers of a file index them together).
void check_lengths(const char* group, const std::vector<ReadArray>& arrays) {
  std::map<std::string, ReadArray> first;  // by symbol
  for (const ReadArray& a : arrays) {
    const std::vector<std::string> dims = shape_symbols(a.entry->shape);
    if (dims.size() == 1) {
      const auto [it, added] = first.emplace(dims[0], a);
      if (!added && a.size != it->second.size)
        throw InputError(fmt::format("/{0}/{1} has {2} values, /{0}/{3} {4} (accepted: the "
                                     "same number)",
                                     group, a.entry->name, a.size, it->second.entry->name,
                                     it->second.size));
    } else if (dims.size() == 2) {
      const auto rows = first.find(dims[0]), cols = first.find(dims[1]);
      if (rows == first.end() || cols == first.end())
        throw std::logic_error(fmt::format("{}: its dimensions are read after it",
                                           a.entry->path()));
      if (a.size != rows->second.size * cols->second.size)
        throw InputError(fmt::format("/{}/{} has {} values (accepted: one per cell, len({}) x "
                                     "len({}) = {} x {})",
                                     group, a.entry->name, a.size, rows->second.entry->name,
                                     cols->second.entry->name, rows->second.size,
                                     cols->second.size));
    }
  }
}

/// The by-name entry of @p group for values of @p kind and @p type, or null.
const SchemaEntry* by_name_entry(const char* group, SchemaKind kind, SchemaType type) {
  for (const SchemaEntry& e : result_schema())
    if (e.by_name() && std::string(e.group) == group && e.kind == kind && e.type == type)
      return &e;
  return nullptr;
}

/// Every attribute of a group of by-name entries, by its HDF5 class (integer, float, string).
void read_named_attributes(hid_t g, const char* group, RunResult& r) {
  std::vector<std::string> names;
  const auto collect = [](hid_t, const char* name, const H5A_info_t*, void* out) -> herr_t {
    static_cast<std::vector<std::string>*>(out)->push_back(name);
    return 0;
  };
  check(H5Aiterate2(g, H5_INDEX_NAME, H5_ITER_INC, nullptr, collect, &names), "H5Aiterate2");
  for (const std::string& name : names) {
    Handle a(H5Aopen(g, name.c_str(), H5P_DEFAULT), H5Aclose);
    if (!a.valid()) throw InputError(fmt::format("unreadable attribute in /{}", group));
    Handle type(H5Aget_type(a), H5Tclose);
    const H5T_class_t cls = H5Tget_class(type);
    const SchemaType t = cls == H5T_INTEGER ? SchemaType::int64
                         : cls == H5T_FLOAT ? SchemaType::float64
                         : cls == H5T_STRING ? SchemaType::text
                                             : SchemaType::none;
    const SchemaEntry* e = by_name_entry(group, SchemaKind::attribute, t);
    if (!e)
      throw InputError(fmt::format("/{} attribute {} has an unknown type", group, name));
    e->set_one(r, name, read_value(g, *e, name.c_str()));
  }
}

/// Every dataset of a group of by-name entries, as its entry's type.
void read_named_datasets(hid_t g, const char* group, RunResult& r) {
  const SchemaEntry* e = by_name_entry(group, SchemaKind::dataset, SchemaType::float64_array);
  if (!e) return;
  H5G_info_t ginfo;
  check(H5Gget_info(g, &ginfo), "H5Gget_info");
  for (hsize_t i = 0; i < ginfo.nlinks; ++i) {
    const ssize_t n = H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0,
                                         H5P_DEFAULT);
    if (n < 0) throw InputError(fmt::format("unreadable dataset in /{}", group));
    std::string name(static_cast<std::size_t>(n), '\0');
    H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size() + 1,
                       H5P_DEFAULT);
    e->set_one(r, name, read_value(g, *e, name.c_str()));
  }
}

/// The members of group row @p group (in table order), then its own check and its lengths.
void read_group(hid_t g, const SchemaEntry& group, RunResult& r) {
  std::vector<ReadArray> arrays;
  bool named = false;
  for (const SchemaEntry& e : result_schema()) {
    if (e.kind == SchemaKind::group || std::string(e.group) != group.name) continue;
    if (e.by_name()) {
      named = true;
      continue;
    }
    if (!e.set || (e.presence != Presence::required && !in_file(g, e))) continue;
    SchemaValue v = read_value(g, e, e.name);
    if (const auto* a = std::get_if<std::vector<double>>(&v)) arrays.push_back({&e, a->size()});
    e.set(r, std::move(v));
  }
  if (named) {
    read_named_attributes(g, group.name, r);
    read_named_datasets(g, group.name, r);
  }
  if (group.check) group.check(r);
  check_lengths(group.name, arrays);
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
  for (const SchemaEntry& e : result_schema()) {
    if (e.kind != SchemaKind::group || !e.set) continue;
    if (e.presence != Presence::required && !exists(file, e.name)) continue;
    Handle g = open_group(file, e.name);
    e.set(r, SchemaValue{});
    read_group(g, e, r);
  }
  return r;
}

}  // namespace

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

}  // namespace grainlift
