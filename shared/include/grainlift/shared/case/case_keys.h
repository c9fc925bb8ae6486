// The registry of every key a case file may hold: type, unit, default, accepted range and a
// one-line description. The loader validates against it; `grainlift keys` prints it and
// docs/case-format.md is generated from it, so the three never disagree.
#pragma once

#include <string>
#include <vector>

namespace grainlift {

enum class KeyType { real, integer, boolean, text, vec2, bool2, text_list };

struct KeySpec {
  std::string path;            ///< "section.key" (or "section.sub.key")
  KeyType type;
  bool required;
  std::string default_text;    ///< as written in TOML, or a sentence ("grains.friction")
  double min, max;             ///< accepted range for real/integer/vec2 components
  bool min_open, max_open;     ///< exclusive bounds
  std::vector<std::string> choices;  ///< accepted values for text/text_list ("" = any)
  std::string unit;
  std::string description;
  std::string only_for_law;    ///< grains.contact keys: the law they belong to ("" = any)
};

/// All keys, in the order docs list them.
const std::vector<KeySpec>& case_keys();
/// The key with this dotted path, or nullptr.
const KeySpec* find_key(const std::string& path);
/// True when the dotted path names a section (a table), e.g. "grains.contact".
bool is_section(const std::string& path);
/// Human text of the accepted range or choices, e.g. "(0, 1]" or "one of: a, b".
std::string accepted_range(const KeySpec& k);
/// The type as a word ("number", "[x, y] numbers", ...).
std::string type_name(KeyType t);
/// Markdown table of every key, used for docs/case-format.md.
std::string keys_markdown();

}  // namespace grainlift
