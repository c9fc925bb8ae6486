// The case reader's private parts shared by its two files: where each key came from
// (Diagnostics), the insertion of a value at a dotted path, and the typed Case built from
// the checked table (case_build.cc).
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <map>
#include <string>
#include <utility>
#include <vector>
#include <toml++/toml.h>

#include "grainlift/shared/case/case_model.h"

namespace grainlift::case_detail {

/// Collects diagnostics; knows where each key came from (file line or --set argument).
class Diagnostics {
 public:
  explicit Diagnostics(std::string file) : file_(std::move(file)) {}

  void set_override_origin(const std::string& path, const std::string& arg) {
    override_origin_[path] = arg;
  }
  std::string where(const std::string& path, const toml::node* node) const {
    auto it = override_origin_.find(path);
    if (it != override_origin_.end()) return fmt::format("--set '{}'", it->second);
    if (node && node->source().begin.line > 0)
      return fmt::format("{}:{}", file_, node->source().begin.line);
    return file_;
  }
  void error(const std::string& where, const std::string& message) {
    lines_.push_back(fmt::format("{}: {}", where, message));
  }
  /// Orders messages by file line (messages without a line, e.g. --set ones, come last).
  void sort_by_line() {
    auto line_of = [&](const std::string& l) {
      const std::string prefix = file_ + ":";
      if (l.compare(0, prefix.size(), prefix) != 0) return 1L << 40;
      return std::strtol(l.c_str() + prefix.size(), nullptr, 10);
    };
    std::stable_sort(lines_.begin(), lines_.end(), [&](const std::string& a, const std::string& b) {
      return line_of(a) < line_of(b);
    });
  }
  bool empty() const { return lines_.empty(); }
  std::string text() {
    sort_by_line();
    std::string s;
    for (const auto& l : lines_) s += l + "\n";
    return s;
  }
  const std::string& file() const { return file_; }

 private:
  std::string file_;
  std::map<std::string, std::string> override_origin_;
  std::vector<std::string> lines_;
};

/// Insert @p value at the dotted path @p parts of @p root, creating sections. Returns "" or the
/// part that is not a section.
template <class Node>
std::string insert_at(toml::table& root, const std::vector<std::string>& parts, Node&& value) {
  toml::table* t = &root;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    toml::node* n = t->get(parts[i]);
    if (!n) {
      t->insert(parts[i], toml::table{});
      n = t->get(parts[i]);
    }
    if (!n->is_table()) return parts[i];
    t = n->as_table();
  }
  t->insert_or_assign(parts.back(), std::forward<Node>(value));
  return "";
}

/// The typed case of a table whose keys are checked (defaults filled from the registry).
Case build_case(const toml::table& root);
/// intruder.depth (the depth sweep's mode) applied to the case: its position and box.
void apply_depth_mode(const toml::table& root, Case& c, Diagnostics& diag);
/// Checks between keys (one key's range depends on another's value), with file:line.
void cross_checks(const toml::table& r, const Case& c, Diagnostics& diag);
/// The calibrated law of continuum.rheology_file in place of continuum.mu_s, mu_2, I0.
void apply_rheology_file(const toml::table& root, const std::string& name, Case& c,
                         Diagnostics& diag);

}  // namespace grainlift::case_detail
