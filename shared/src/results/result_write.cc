// The writer of <out>/<solver>.h5 and its XDMF sidecar (result_file.h), both driven by the schema
// table (result_schema.h): every entry present in the result is written, in the table's order.
#include <fmt/format.h>

#include <cstdio>
#include <map>
#include <vector>
#include <stdexcept>

#include "grainlift/shared/results/atomic_file.h"
#include "grainlift/shared/results/derived_quantities.h"
#include "grainlift/shared/errors.h"
#include "grainlift/shared/results/result_file.h"
#include "grainlift/shared/results/result_schema.h"
#include "results/hdf5_io.h"

namespace grainlift {
namespace {

using namespace hdf5;

/// The group that holds the field grid (the XDMF sidecar's source).
constexpr const char* field_group = "fields";

/// Lengths of a group's one-dimensional datasets by shape symbol ("nx"), for its 2D datasets.
using Lengths = std::map<std::string, std::size_t>;

/// Writes value @p v of entry @p e under @p name in @p obj.
void write_value(hid_t obj, const SchemaEntry& e, const char* name, const SchemaValue& v,
                 Lengths& lengths) {
  const bool attribute = e.kind == SchemaKind::attribute;
  if (const auto* s = std::get_if<std::string>(&v)) {
    if (attribute) attr_string(obj, name, *s);
    else dataset_string(obj, name, *s);
  } else if (const auto* i = std::get_if<long long>(&v); i && attribute) {
    attr_number(obj, name, *i);
  } else if (const auto* x = std::get_if<double>(&v); x && attribute) {
    attr_number(obj, name, *x);
  } else if (const auto* a = std::get_if<std::vector<double>>(&v); a && !attribute) {
    const std::vector<std::string> dims = shape_symbols(e.shape);
    if (dims.size() == 2) {
      dataset_doubles(obj, name, *a, e.unit, lengths[dims[0]], lengths[dims[1]]);
    } else {
      dataset_doubles(obj, name, *a, e.unit);
      if (dims.size() == 1) lengths[dims[0]] = a->size();
    }
  } else {
    throw std::logic_error(fmt::format("schema entry {} has no writer for its value",
                                       e.path()));
  }
}

/// Every member entry of group @p group (root: "") present in @p view, in table order.
void write_members(hid_t obj, const char* group, const ResultView& view) {
  Lengths lengths;
  for (const SchemaEntry& e : result_schema()) {
    if (e.kind == SchemaKind::group || std::string(e.group) != group) continue;
    if (e.by_name()) {
      for (const auto& [name, v] : e.get_all(view.result))
        write_value(obj, e, name.c_str(), v, lengths);
      continue;
    }
    const SchemaValue v = e.get(view);
    if (!std::holds_alternative<std::monostate>(v)) write_value(obj, e, e.name, v, lengths);
  }
}

void write_body(hid_t file, const RunResult& r) {
  const DerivedQuantities derived = derive(r);
  const ResultView view{r, derived};
  write_members(file, "", view);
  for (const SchemaEntry& e : result_schema()) {
    if (e.kind != SchemaKind::group || std::holds_alternative<std::monostate>(e.get(view)))
      continue;
    Handle g = make_group(file, e.name);
    write_members(g, e.name, view);
  }
}

/// The coordinates entry of shape "[@p symbol]" in the field group.
const SchemaEntry& coordinate_entry(const std::string& symbol) {
  for (const SchemaEntry& e : result_schema())
    if (std::string(e.group) == field_group && shape_symbols(e.shape) ==
                                                   std::vector<std::string>{symbol})
      return e;
  throw std::logic_error(fmt::format("the schema has no /{} coordinate [{}]", field_group,
                                     symbol));
}

}  // namespace

void write_result(const std::string& path, const RunResult& result) {
  silence_hdf5();
  // The file is built in memory (HDF5's core driver, no backing store) and its image written
  // by write_bytes_atomically: HDF5 itself never writes to the disk, so a full disk or a
  // read-only folder is one clear error there, and no HDF5 file is left open with unwritten
  // data for the library's exit handler to flush (which crashed on a full disk).
  std::vector<unsigned char> image;
  {
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    check(H5Pset_fapl_core(fapl, 1 << 20, false), "H5Pset_fapl_core");
    Handle file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl), H5Fclose);
    if (!file.valid()) throw RunError(fmt::format("{}: HDF5 cannot create the file", path));
    write_body(file, result);
    check(H5Fflush(file, H5F_SCOPE_GLOBAL), "H5Fflush");
    const ssize_t size = H5Fget_file_image(file, nullptr, 0);
    if (size <= 0) throw RunError(fmt::format("{}: HDF5 gave no file image", path));
    image.resize(static_cast<std::size_t>(size));
    if (H5Fget_file_image(file, image.data(), image.size()) != size)
      throw RunError(fmt::format("{}: HDF5 gave a short file image", path));
  }
  write_bytes_atomically(path, image.data(), image.size());
}

void write_fields_xdmf(const std::string& xmf_path, const std::string& h5_name,
                       const RunResult& r) {
  if (!r.fields) return;
  const DerivedQuantities none;  // the field grid does not use derived quantities
  const ResultView view{r, none};
  // Every two-dimensional dataset of the field group: a cell attribute of one [ny, nx] grid.
  std::vector<const SchemaEntry*> cells;
  for (const SchemaEntry& e : result_schema())
    if (std::string(e.group) == field_group && shape_symbols(e.shape).size() == 2)
      cells.push_back(&e);
  if (cells.empty()) return;
  const std::vector<std::string> dims = shape_symbols(cells.front()->shape);
  const auto y = std::get<std::vector<double>>(coordinate_entry(dims[0]).get(view));
  const auto x = std::get<std::vector<double>>(coordinate_entry(dims[1]).get(view));
  if (x.size() < 2 || y.size() < 2) return;
  const std::size_t nx = x.size(), ny = y.size();
  const double dx = x[1] - x[0], dy = y[1] - y[0];
  // Cell-centred data on a co-rectilinear grid: nodes at the cell corners.
  std::string attrs;
  for (const SchemaEntry* e : cells) {
    if (std::holds_alternative<std::monostate>(e->get(view))) continue;
    attrs += fmt::format(
        "      <Attribute Name=\"{0}\" AttributeType=\"Scalar\" Center=\"Cell\">\n"
        "        <DataItem Dimensions=\"{1} {2}\" NumberType=\"Float\" Precision=\"8\" "
        "Format=\"HDF\">{3}:/{4}/{0}</DataItem>\n      </Attribute>\n",
        e->name, ny, nx, h5_name, field_group);
  }
  const std::string text = fmt::format(
      "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n"
      "    <Grid Name=\"{0} fields (intruder frame)\" GridType=\"Uniform\">\n"
      "      <Topology TopologyType=\"2DCoRectMesh\" Dimensions=\"{1} {2}\"/>\n"
      "      <Geometry GeometryType=\"ORIGIN_DXDY\">\n"
      "        <DataItem Dimensions=\"2\" NumberType=\"Float\" Format=\"XML\">{3} {4}</DataItem>\n"
      "        <DataItem Dimensions=\"2\" NumberType=\"Float\" Format=\"XML\">{5} {6}</DataItem>\n"
      "      </Geometry>\n{7}    </Grid>\n  </Domain>\n</Xdmf>\n",
      r.meta.solver, ny + 1, nx + 1, y[0] - 0.5 * dy, x[0] - 0.5 * dx, dy, dx, attrs);
  write_text_atomically(xmf_path, text);
}

}  // namespace grainlift
