#include "grainlift/shared/results/json_writer.h"

#include <fmt/format.h>

#include <cmath>

namespace grainlift {

std::string json_quote(const std::string& s) {
  std::string out = "\"";
  for (unsigned char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (c < 0x20) out += fmt::format("\\u{:04x}", c);
        else out += char(c);
    }
  }
  return out + "\"";
}

void JsonObject::add(const std::string& key, double value) {
  items_.push_back({key, std::isfinite(value) ? fmt::format("{:.17g}", value) : "null", {}});
}
void JsonObject::add(const std::string& key, long long value) {
  items_.push_back({key, fmt::format("{}", value), {}});
}
void JsonObject::add(const std::string& key, bool value) {
  items_.push_back({key, value ? "true" : "false", {}});
}
void JsonObject::add(const std::string& key, const std::string& value) {
  items_.push_back({key, json_quote(value), {}});
}
void JsonObject::add(const std::string& key, const std::optional<double>& value) {
  if (value) add(key, *value);
  else items_.push_back({key, "null", {}});
}
void JsonObject::add(const std::string& key, const JsonObject& value) {
  items_.push_back({key, "", {value}});
}

std::string JsonObject::str(int indent, int level) const {
  if (items_.empty()) return "{}";
  const std::string nl = indent > 0 ? "\n" : "";
  const std::string pad(std::size_t(indent * (level + 1)), ' ');
  const std::string close_pad(std::size_t(indent * level), ' ');
  std::string s = "{" + nl;
  for (std::size_t i = 0; i < items_.size(); ++i) {
    const auto& it = items_[i];
    s += pad + json_quote(it.key) + (indent > 0 ? ": " : ":");
    s += it.nested.empty() ? it.raw : it.nested[0].str(indent, level + 1);
    s += (i + 1 < items_.size() ? "," : "") + nl;
  }
  return s + close_pad + "}";
}

}  // namespace grainlift
