// The schema table as text (`grainlift schema`) and as the Markdown of docs/schema.md, and the
// small helpers of SchemaEntry (result_schema.h).
#include <fmt/format.h>

#include "grainlift/shared/results/result_schema.h"

namespace grainlift {
namespace {

const char* kind_name(SchemaKind k) {
  switch (k) {
    case SchemaKind::group: return "group";
    case SchemaKind::attribute: return "attribute";
    case SchemaKind::dataset: return "dataset";
  }
  return "?";
}

const char* type_name(SchemaType t) {
  switch (t) {
    case SchemaType::none: return "-";
    case SchemaType::text: return "string";
    case SchemaType::int64: return "int64";
    case SchemaType::float64: return "float64";
    case SchemaType::float64_array: return "float64";
  }
  return "?";
}

const char* presence_name(Presence p) {
  switch (p) {
    case Presence::required: return "required";
    case Presence::optional: return "optional";
    case Presence::defaulted: return "defaulted";
  }
  return "?";
}

std::string or_dash(const char* s) { return s[0] ? s : "-"; }

/// @p s with the characters that end a Markdown table cell escaped.
std::string cell(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '|') out += '\\';
    out += c;
  }
  return out;
}

}  // namespace

std::string SchemaEntry::path() const {
  const std::string parent = group[0] ? fmt::format("/{}", group) : std::string();
  return kind == SchemaKind::attribute && !by_name() ? fmt::format("{}/@{}", parent, name)
                                                     : fmt::format("{}/{}", parent, name);
}

bool SchemaEntry::by_name() const { return name[0] == '*' && name[1] == '\0'; }

std::vector<std::string> shape_symbols(const std::string& shape) {
  std::vector<std::string> out;
  if (shape.size() < 2 || shape.front() != '[') return out;
  std::size_t start = 1;
  for (;;) {
    const std::size_t end = shape.find_first_of(",]", start);
    if (end == std::string::npos) break;
    std::size_t a = start, b = end;
    while (a < b && shape[a] == ' ') ++a;
    while (b > a && shape[b - 1] == ' ') --b;
    out.push_back(shape.substr(a, b - a));
    if (shape[end] == ']') break;
    start = end + 1;
  }
  return out;
}

std::string schema_markdown() {
  std::string out =
      "| path | kind | type | shape | unit | presence | solvers | content |\n"
      "|---|---|---|---|---|---|---|---|\n";
  for (const SchemaEntry& e : result_schema())
    out += fmt::format("| `{}` | {} | {} | {} | {} | {} | {} | {} |\n", e.path(),
                       kind_name(e.kind), type_name(e.type),
                       e.kind == SchemaKind::group ? "-" : cell(e.shape), cell(or_dash(e.unit)),
                       presence_name(e.presence), e.solvers, cell(e.description));
  return out;
}

std::string schema_text() {
  std::string out = fmt::format("{:34} {:9} {:7} {:13} {:7} {:9} {:8} {}\n", "path", "kind",
                                "type", "shape", "unit", "presence", "solvers", "content");
  for (const SchemaEntry& e : result_schema()) {
    std::string line = fmt::format("{:34} {:9} {:7} {:13} {:7} {:9} {:8} {}", e.path(),
                                   kind_name(e.kind), type_name(e.type),
                                   e.kind == SchemaKind::group ? "-" : e.shape, or_dash(e.unit),
                                   presence_name(e.presence), e.solvers, e.description);
    line.erase(line.find_last_not_of(' ') + 1);
    out += line + "\n";
  }
  return out;
}

}  // namespace grainlift
