// A tiny JSON object builder for summary.json and `compare --json`: numbers (NaN/inf become
// null), strings (escaped), nested objects, in insertion order.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace grainlift {

class JsonObject {
 public:
  void add(const std::string& key, double value);
  void add(const std::string& key, long long value);
  void add(const std::string& key, int value) { add(key, static_cast<long long>(value)); }
  void add(const std::string& key, bool value);
  void add(const std::string& key, const std::string& value);
  void add(const std::string& key, const char* value) { add(key, std::string(value)); }
  void add(const std::string& key, const std::optional<double>& value);
  void add(const std::string& key, const JsonObject& value);
  /// Serialised object; @p indent > 0 pretty-prints with that many spaces per level.
  std::string str(int indent = 2, int level = 0) const;
  bool empty() const { return items_.empty(); }

 private:
  // value is raw JSON text, or a nested object
  struct Item {
    std::string key, raw;
    std::vector<JsonObject> nested;  // 0 or 1 element
  };
  std::vector<Item> items_;
};

/// JSON string literal with escapes.
std::string json_quote(const std::string& s);

}  // namespace grainlift
