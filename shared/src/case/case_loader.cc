#include "grainlift/shared/case/case_loader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <limits>
#include <sstream>
#include <toml++/toml.h>

#include "grainlift/shared/case/case_keys.h"
#include "grainlift/shared/errors.h"
#include "grainlift/shared/rheology/rheology_file.h"
#include "case/case_reader_parts.h"

namespace grainlift {

std::string fnv1a64_hex(const std::string& text) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return fmt::format("{:016x}", h);
}

namespace {

using case_detail::Diagnostics;
using case_detail::insert_at;


bool in_range(const KeySpec& k, double v) {
  if (!std::isfinite(v)) return false;
  if (k.min_open ? !(v > k.min) : !(v >= k.min)) return false;
  if (k.max_open ? !(v < k.max) : !(v <= k.max)) return false;
  return true;
}

std::string range_msg(const KeySpec& k) {
  return fmt::format("accepted: {}{}", accepted_range(k),
                     k.unit.empty() || k.unit == "-" ? "" : " " + k.unit);
}

/// Checks one leaf node against its spec; returns false (and reports) on a type/range error.
bool check_value(const KeySpec& k, const toml::node& node, const std::string& where,
                 Diagnostics& diag) {
  auto number = [](const toml::node& n, double& out) {
    if (auto f = n.as_floating_point()) { out = f->get(); return true; }
    if (auto i = n.as_integer()) { out = double(i->get()); return true; }
    return false;
  };
  const std::string expect =
      fmt::format("'{}' must be {} ({})", k.path, type_name(k.type), range_msg(k));
  switch (k.type) {
    case KeyType::real: {
      double v;
      if (!number(node, v)) { diag.error(where, expect); return false; }
      if (!in_range(k, v)) {
        diag.error(where, fmt::format("'{}' = {} is out of range ({})", k.path, v, range_msg(k)));
        return false;
      }
      return true;
    }
    case KeyType::integer: {
      auto i = node.as_integer();
      if (!i) { diag.error(where, expect); return false; }
      if (!in_range(k, double(i->get()))) {
        diag.error(where,
                   fmt::format("'{}' = {} is out of range ({})", k.path, i->get(), range_msg(k)));
        return false;
      }
      return true;
    }
    case KeyType::boolean:
      if (!node.is_boolean()) { diag.error(where, expect); return false; }
      return true;
    case KeyType::text: {
      auto s = node.as_string();
      if (!s) { diag.error(where, expect); return false; }
      if (!k.choices.empty() &&
          std::find(k.choices.begin(), k.choices.end(), s->get()) == k.choices.end()) {
        diag.error(where, fmt::format("'{}' = \"{}\" is not accepted ({})", k.path, s->get(),
                                      range_msg(k)));
        return false;
      }
      return true;
    }
    case KeyType::vec2: {
      auto a = node.as_array();
      double v[2];
      if (!a || a->size() != 2 || !number(*a->get(0), v[0]) || !number(*a->get(1), v[1])) {
        diag.error(where, expect);
        return false;
      }
      for (double x : v)
        if (!in_range(k, x)) {
          diag.error(where, fmt::format("'{}' = [{}, {}] has a component out of range ({})",
                                        k.path, v[0], v[1], range_msg(k)));
          return false;
        }
      return true;
    }
    case KeyType::bool2: {
      auto a = node.as_array();
      if (!a || a->size() != 2 || !a->get(0)->is_boolean() || !a->get(1)->is_boolean()) {
        diag.error(where, expect);
        return false;
      }
      return true;
    }
    case KeyType::text_list: {
      auto a = node.as_array();
      if (!a) { diag.error(where, expect); return false; }
      for (const auto& e : *a) {
        auto s = e.as_string();
        if (!s || std::find(k.choices.begin(), k.choices.end(), s->get()) == k.choices.end()) {
          diag.error(where, expect);
          return false;
        }
      }
      return true;
    }
  }
  return false;
}

/// Walks the table: unknown keys, wrong types, out-of-range values.
void check_table(const toml::table& table, const std::string& prefix, Diagnostics& diag,
                 std::map<std::string, const toml::node*>& seen) {
  for (const auto& [key, node] : table) {
    const std::string path = prefix.empty() ? std::string(key.str())
                                            : prefix + "." + std::string(key.str());
    const std::string where = diag.where(path, &node);
    if (node.is_table()) {
      if (!is_section(path)) {
        diag.error(where, fmt::format("unknown section [{}]", path));
        continue;
      }
      check_table(*node.as_table(), path, diag, seen);
      continue;
    }
    const KeySpec* spec = find_key(path);
    if (!spec) {
      if (is_section(path))
        diag.error(where, fmt::format("'{}' must be a table (a [{}] section)", path, path));
      else if (path == "dem.window_width")
        diag.error(where, "'dem.window_width': the co-moving window was removed, as it failed "
                          "its own validation (studies/comoving_window/README.md); use a longer "
                          "periodic box");
      else
        diag.error(where, fmt::format("unknown key '{}' (see `grainlift keys` or "
                                      "docs/case-format.md)", path));
      continue;
    }
    if (check_value(*spec, node, where, diag)) seen[path] = &node;
  }
}


void apply_override(toml::table& root, const std::string& arg, Diagnostics& diag) {
  const auto eq = arg.find('=');
  if (eq == std::string::npos || eq == 0) {
    diag.error(fmt::format("--set '{}'", arg), "expected section.key=value");
    return;
  }
  std::string path = arg.substr(0, eq);
  const std::string value = arg.substr(eq + 1);
  // Value in TOML syntax; a bare word that is not valid TOML is taken as a string.
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + value);
  } catch (const toml::parse_error&) {
    try {
      toml::table t;
      t.insert("v", value);
      parsed = std::move(t);
    } catch (...) {
      diag.error(fmt::format("--set '{}'", arg), "cannot parse the value");
      return;
    }
  }
  std::vector<std::string> parts;
  std::stringstream ss(path);
  for (std::string p; std::getline(ss, p, '.');) parts.push_back(p);
  if (parts.size() < 2) {
    diag.error(fmt::format("--set '{}'", arg), "expected section.key=value");
    return;
  }
  if (const std::string bad = insert_at(root, parts, std::move(*parsed.get("v"))); !bad.empty()) {
    diag.error(fmt::format("--set '{}'", arg), fmt::format("'{}' is not a section", bad));
    return;
  }
  diag.set_override_origin(path, arg);
}

}  // namespace

Case parse_case(const std::string& text, const std::string& name,
                const std::vector<std::string>& overrides) {
  Diagnostics diag(name);
  toml::table root;
  try {
    root = toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    throw InputError(fmt::format("{}:{}:{}: invalid TOML: {}", name, e.source().begin.line,
                                 e.source().begin.column, e.description()));
  }
  for (const auto& o : overrides) apply_override(root, o, diag);

  std::map<std::string, const toml::node*> seen;
  check_table(root, "", diag, seen);
  for (const auto& k : case_keys())
    if (k.required && !root.at_path(k.path))
      diag.error(name, fmt::format("missing required key '{}' ({}, {}{})", k.path,
                                   type_name(k.type), k.description,
                                   k.unit == "-" ? "" : ", in " + k.unit));
  if (!diag.empty()) throw InputError(diag.text());

  Case c = case_detail::build_case(root);
  case_detail::apply_depth_mode(root, c, diag);
  if (!diag.empty()) throw InputError(diag.text());
  case_detail::cross_checks(root, c, diag);
  if (!diag.empty()) throw InputError(diag.text());
  if (!c.continuum.rheology_file.empty()) case_detail::apply_rheology_file(root, name, c, diag);
  if (!diag.empty()) throw InputError(diag.text());

  c.source.path = name;
  c.source.text = text;
  c.source.overrides = overrides;
  std::string joined;
  for (const auto& o : overrides) joined += o + "\n";
  c.source.hash = fnv1a64_hex(text + "\n--\n" + joined);
  std::ostringstream eff;
  eff << root;
  c.source.effective_toml = eff.str();
  return c;
}

Case load_case(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open the case file", path));
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError(fmt::format("{}: cannot read the case file", path));
  return parse_case(ss.str(), path, overrides);
}

}  // namespace grainlift
