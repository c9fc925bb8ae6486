// The schema of the output file <out>/<solver>.h5 as one table: every group, attribute and
// dataset with its unit, shape, presence, the solvers that write it and where it lives in a
// RunResult. The writer, the reader, the XDMF sidecar and `grainlift schema` (docs/schema.md)
// all loop over this table; adding a dataset is adding one entry to result_schema.cc.
#pragma once

#include <functional>
#include <string>
#include <variant>
#include <vector>

#include "grainlift/shared/results/derived_quantities.h"
#include "grainlift/shared/results/run_result.h"

namespace grainlift {

/// What an entry is in the file.
enum class SchemaKind { group, attribute, dataset };

/// The value type of an attribute or dataset (groups: none).
enum class SchemaType { none, text, int64, float64, float64_array };

/// When an entry is in the file.
enum class Presence {
  required,   ///< always written with its group; a file without it is refused
  optional,   ///< written only when the run has it; absent in the file = absent in memory
  defaulted,  ///< always written; absent in older files, read as 0 or empty
};

/// One value of the file in memory: absent (monostate), an integer, a number, a text or an
/// array of numbers (row-major for a two-dimensional shape).
using SchemaValue =
    std::variant<std::monostate, long long, double, std::string, std::vector<double>>;

/// What the writer writes: a result and the quantities derived from it (/derived).
struct ResultView {
  const RunResult& result;
  const DerivedQuantities& derived;
};

/// One row of the schema table.
struct SchemaEntry {
  const char* group;        ///< "" for the root; a group row's own parent is ""
  const char* name;         ///< "*": any name (by-name entries such as /diagnostics)
  SchemaKind kind;
  SchemaType type;
  const char* unit;         ///< written as the "units" attribute of a numeric dataset
  /// "scalar", or dimensions named by symbols: "[n_samples]", "[ny, nx]". Within a group,
  /// one-dimensional datasets with the same symbol hold the same number of values, and a
  /// two-dimensional one holds the product of its symbols' lengths.
  const char* shape;
  Presence presence;
  const char* solvers;      ///< "dem", "fem" or "dem, fem"
  const char* description;  ///< one line for docs/schema.md
  /// The value in @p view, monostate when absent. A group row yields 1 when the group is
  /// present. Null only for by-name entries.
  std::function<SchemaValue(const ResultView& view)> get;
  /// Stores a value read from a file (a group row: makes the block present). Null when the
  /// entry is not read back (constants, /derived, whose values follow from the rest).
  std::function<void(RunResult& r, SchemaValue&& value)> set;
  /// By-name entries (name "*"): every (name, value) of the run, in the order written ...
  std::function<std::vector<std::pair<std::string, SchemaValue>>(const RunResult& r)> get_all;
  /// ... and the store of one read back.
  std::function<void(RunResult& r, const std::string& name, SchemaValue&& value)> set_one;
  /// Group rows: a rule across the group's entries beyond equal lengths, checked after they are
  /// read; throws InputError. Null when there is none.
  std::function<void(const RunResult& r)> check;

  /// The entry's path in the file ("/forces/fx", "/diagnostics/*", "/forces").
  std::string path() const;
  /// Whether the entry takes any name (by-name).
  bool by_name() const;
};

/// @brief Every entry of the file, groups before their members, in the order written.
const std::vector<SchemaEntry>& result_schema();

/// @brief The table as the Markdown of docs/schema.md (between its schema markers).
std::string schema_markdown();

/// @brief The table as plain text, one line per entry (`grainlift schema`).
std::string schema_text();

/// @brief The names of a shape's dimensions: "[ny, nx]" gives {"ny", "nx"}, "scalar" none.
std::vector<std::string> shape_symbols(const std::string& shape);

}  // namespace grainlift
