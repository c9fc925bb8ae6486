#include "grainlift/shared/rheology/rheology_file.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <toml++/toml.h>

#include "grainlift/shared/results/atomic_file.h"
#include "grainlift/shared/errors.h"
#include "grainlift/shared/run/run_driver.h"

namespace grainlift {

namespace {

/// The numeric keys of each table and the range each accepts (messages and checks share it).
struct NumberKey {
  const char* name;
  const char* range;
};
const NumberKey mu_i_keys[] = {
    {"mu_s", "finite, 0 <= mu_s < mu_2"},   {"mu_2", "finite, mu_2 > mu_s"},
    {"I0", "finite, > 0"},                  {"mu_s_err", "finite, >= 0"},
    {"mu_2_err", "finite, >= 0"},           {"I0_err", "finite, >= 0"},
    {"chi2_per_dof", "finite, >= 0"},       {"points", "integer, >= 4"},
    {"I_min", "finite, 0 < I_min <= I_max"}, {"I_max", "finite, I_max >= I_min"},
};
const NumberKey phi_i_keys[] = {
    {"phi_max", "finite, 0 < phi_max <= 1"}, {"a", "finite"},
    {"phi_max_err", "finite, >= 0"},         {"a_err", "finite, >= 0"},
    {"chi2_per_dof", "finite, >= 0"},        {"points", "integer, >= 3"},
};
const NumberKey point_keys[] = {
    {"I", "finite, > 0"},          {"mu", "finite"}, {"mu_stderr", "finite, > 0"},
    {"phi", "finite, 0 <= phi <= 1"}, {"phi_stderr", "finite, > 0"},
};
const NumberKey wall_keys[] = {
    {"friction", "finite, >= 0"}, {"friction_err", "finite, >= 0"},
    {"mu_a", "finite, >= 0"},     {"mu_a_err", "finite, >= 0"},
    {"mu_b", "finite, >= 0"},     {"mu_b_err", "finite, >= 0"},
    {"v0", "finite, > 0 (m/s)"},  {"v0_err", "finite, >= 0"},
    {"chi2_per_dof", "finite, >= 0"}, {"points", "integer, >= 4"},
};
const NumberKey nonlocal_keys[] = {
    {"amplitude", "finite, > 0"},     {"amplitude_err", "finite, >= 0"},
    {"chi2_per_dof", "finite, >= 0"}, {"points", "integer, >= 3"},
    {"mu_min", "finite, 0 <= mu_min <= mu_max"}, {"mu_max", "finite, mu_max >= mu_min"},
};
constexpr const char* covariance_range = "3 arrays of 3 finite numbers, diagonal >= 0";

template <std::size_t N>
const char* range_of(const NumberKey (&keys)[N], const std::string& name) {
  for (const auto& k : keys)
    if (name == k.name) return k.range;
  return "?";
}

/// Throws InputError "<where>: [<table>] <key> = <value>: accepted <range>" unless @p ok.
void require(bool ok, const std::string& where, const std::string& table, const std::string& key,
             double value, const char* range) {
  if (!ok)
    throw InputError(
        fmt::format("{}: [{}] {} = {:.17g}: accepted {}", where, table, key, value, range));
}

/// The checks of read_rheology_file, also run before writing.
void validate(const RheologyFile& d, const std::string& where) {
  const MuIFit& m = d.mu_i;
  auto mu = [&](const char* key, double v, bool ok) {
    require(std::isfinite(v) && ok, where, "mu_i", key, v, range_of(mu_i_keys, key));
  };
  mu("mu_s", m.mu_s, m.mu_s >= 0 && m.mu_s < m.mu_2);
  mu("mu_2", m.mu_2, m.mu_2 > m.mu_s);
  mu("I0", m.I0, m.I0 > 0);
  mu("mu_s_err", m.mu_s_err, m.mu_s_err >= 0);
  mu("mu_2_err", m.mu_2_err, m.mu_2_err >= 0);
  mu("I0_err", m.I0_err, m.I0_err >= 0);
  mu("chi2_per_dof", m.chi2_per_dof, m.chi2_per_dof >= 0);
  mu("points", m.points, m.points >= 4);
  mu("I_min", d.I_min, d.I_min > 0 && d.I_min <= d.I_max);
  mu("I_max", d.I_max, d.I_max >= d.I_min);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      require(std::isfinite(m.covariance[i][j]) && (i != j || m.covariance[i][j] >= 0), where,
              "mu_i", fmt::format("covariance[{}][{}]", i, j), m.covariance[i][j],
              covariance_range);
  const PhiFit& p = d.phi_i;
  auto phi = [&](const char* key, double v, bool ok) {
    require(std::isfinite(v) && ok, where, "phi_i", key, v, range_of(phi_i_keys, key));
  };
  phi("phi_max", p.phi_max, p.phi_max > 0 && p.phi_max <= 1);
  phi("a", p.a, true);
  phi("phi_max_err", p.phi_max_err, p.phi_max_err >= 0);
  phi("a_err", p.a_err, p.a_err >= 0);
  phi("chi2_per_dof", p.chi2_per_dof, p.chi2_per_dof >= 0);
  phi("points", p.points, p.points >= 3);
  for (std::size_t k = 0; k < d.points.size(); ++k) {
    const ShearPoint& s = d.points[k];
    const std::string table = fmt::format("point {}", k + 1);
    auto pt = [&](const char* key, double v, bool ok) {
      require(std::isfinite(v) && ok, where, table, key, v, range_of(point_keys, key));
    };
    pt("I", s.I, s.I > 0);
    pt("mu", s.mu, true);
    pt("mu_stderr", s.mu_stderr, s.mu_stderr > 0);
    pt("phi", s.phi, s.phi >= 0 && s.phi <= 1);
    pt("phi_stderr", s.phi_stderr, s.phi_stderr > 0);
  }
  if (d.nonlocal) {
    const Cooperativity& a = *d.nonlocal;
    auto nl = [&](const char* key, double v, bool ok) {
      require(std::isfinite(v) && ok, where, "nonlocal", key, v, range_of(nonlocal_keys, key));
    };
    nl("amplitude", a.amplitude, a.amplitude > 0);
    nl("amplitude_err", a.amplitude_err, a.amplitude_err >= 0);
    nl("chi2_per_dof", a.chi2_per_dof, a.chi2_per_dof >= 0);
    nl("points", a.points, a.points >= 3);
    nl("mu_min", a.mu_min, a.mu_min >= 0 && a.mu_min <= a.mu_max);
    nl("mu_max", a.mu_max, a.mu_max >= a.mu_min);
  }
  if (!d.wall) return;
  const WallLaw& w = *d.wall;
  auto wl = [&](const char* key, double v, bool ok) {
    require(std::isfinite(v) && ok, where, "wall", key, v, range_of(wall_keys, key));
  };
  const std::pair<const char*, double> non_negative[] = {
      {"friction", w.friction}, {"friction_err", w.friction_err}, {"mu_a", w.mu_a},
      {"mu_a_err", w.mu_a_err}, {"mu_b", w.mu_b},                 {"mu_b_err", w.mu_b_err},
      {"v0_err", w.v0_err},     {"chi2_per_dof", w.chi2_per_dof}};
  for (const auto& [key, v] : non_negative) wl(key, v, v >= 0);
  wl("v0", w.v0, w.v0 > 0);
  wl("points", w.points, w.points >= 4);
}

// ---- writing

/// A TOML basic string: quotes, backslashes and control characters escaped.
std::string toml_string(const std::string& s) {
  std::string out = "\"";
  for (unsigned char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c < 0x20 || c == 0x7f) {
      out += fmt::format("\\u{:04X}", c);
    } else {
      out += static_cast<char>(c);
    }
  }
  return out + "\"";
}

std::string toml_key(const std::string& key) {
  const bool bare = !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
  return bare ? key : toml_string(key);
}

/// 17 significant digits: enough for any double to read back bit for bit.
std::string number(double v) { return fmt::format("{:.17g}", v); }

// ---- reading

std::string at(const std::string& file, const toml::node* node) {
  if (node && node->source().begin.line > 0)
    return fmt::format("{}:{}", file, node->source().begin.line);
  return file;
}

const toml::table& table_of(const toml::table& root, const std::string& name,
                            const std::string& file) {
  const toml::table* t = root[name].as_table();
  if (!t) throw InputError(fmt::format("{}: missing table [{}]", file, name));
  return *t;
}

/// Refuses keys of @p t that are not in @p keys (or @p extra): a typo must not go unnoticed.
template <std::size_t N>
void refuse_unknown(const toml::table& t, const NumberKey (&keys)[N], const char* extra,
                    const std::string& table, const std::string& file) {
  for (const auto& [k, node] : t) {
    const std::string key(k.str());
    const bool known = key == (extra ? extra : "") ||
                       std::any_of(std::begin(keys), std::end(keys),
                                   [&](const NumberKey& n) { return key == n.name; });
    if (!known) {
      std::string names;
      for (const auto& n : keys) names += std::string(names.empty() ? "" : ", ") + n.name;
      if (extra) names += std::string(", ") + extra;
      throw InputError(fmt::format("{}: [{}] unknown key '{}' (accepted: {})", at(file, &node),
                                   table, key, names));
    }
  }
}

template <std::size_t N>
double get_number(const toml::table& t, const NumberKey (&keys)[N], const char* key,
                  const std::string& table, const std::string& file) {
  const toml::node* node = t.get(key);
  if (!node)
    throw InputError(fmt::format("{}: [{}] missing key '{}' (a number; accepted {})", file, table,
                                 key, range_of(keys, key)));
  const std::optional<double> v = node->value<double>();
  if (!v || node->is_boolean())
    throw InputError(fmt::format("{}: [{}] {} is not a number (accepted {})", at(file, node),
                                 table, key, range_of(keys, key)));
  return *v;
}

/// The number of points a fit used: an integer (accepted range as in @p keys).
template <std::size_t N>
int get_count(const toml::table& t, const NumberKey (&keys)[N], const std::string& table,
              const std::string& file) {
  const double v = get_number(t, keys, "points", table, file);
  if (!t.get("points")->is_integer())
    throw InputError(fmt::format("{}: [{}] points = {} is not an integer (accepted {})",
                                 at(file, t.get("points")), table, v, range_of(keys, "points")));
  // refused before the conversion to int, which would be undefined out of its range
  const long long count = t.get("points")->as_integer()->get();
  if (count < 0 || count > std::numeric_limits<int>::max())
    throw InputError(fmt::format("{}: [{}] points = {} is out of range (accepted {}, at most {})",
                                 at(file, t.get("points")), table, count,
                                 range_of(keys, "points"), std::numeric_limits<int>::max()));
  return static_cast<int>(count);
}

/// The optional [wall] table (its ranges are checked by validate).
WallLaw read_wall(const toml::table& root, const std::string& path) {
  const toml::table& t = table_of(root, "wall", path);
  refuse_unknown(t, wall_keys, nullptr, "wall", path);
  auto num = [&](const char* key) { return get_number(t, wall_keys, key, "wall", path); };
  WallLaw w;
  w.friction = num("friction");
  w.friction_err = num("friction_err");
  w.mu_a = num("mu_a");
  w.mu_a_err = num("mu_a_err");
  w.mu_b = num("mu_b");
  w.mu_b_err = num("mu_b_err");
  w.v0 = num("v0");
  w.v0_err = num("v0_err");
  w.chi2_per_dof = num("chi2_per_dof");
  w.points = get_count(t, wall_keys, "wall", path);
  return w;
}

/// The optional [nonlocal] table (its ranges are checked by validate).
Cooperativity read_nonlocal(const toml::table& root, const std::string& path) {
  const toml::table& t = table_of(root, "nonlocal", path);
  refuse_unknown(t, nonlocal_keys, nullptr, "nonlocal", path);
  auto num = [&](const char* key) { return get_number(t, nonlocal_keys, key, "nonlocal", path); };
  Cooperativity a;
  a.amplitude = num("amplitude");
  a.amplitude_err = num("amplitude_err");
  a.chi2_per_dof = num("chi2_per_dof");
  a.points = get_count(t, nonlocal_keys, "nonlocal", path);
  a.mu_min = num("mu_min");
  a.mu_max = num("mu_max");
  return a;
}

}  // namespace

RheologyFile make_rheology_file(const std::vector<ShearPoint>& points,
                                std::map<std::string, std::string> source) {
  RheologyFile d;
  d.mu_i = fit_mu_i(points);
  if (!d.mu_i.converged) throw RunError("mu(I) fit: " + d.mu_i.message);
  d.phi_i = fit_phi_i(points);
  d.points = points;
  d.I_min = d.I_max = points.front().I;
  for (const auto& p : points) {
    d.I_min = std::min(d.I_min, p.I);
    d.I_max = std::max(d.I_max, p.I);
  }
  source.emplace("grainlift_version", grainlift_version());
  d.source = std::move(source);
  return d;
}

std::string rheology_file_text(const RheologyFile& d, const std::string& path) {
  validate(d, path + " (writing)");
  const MuIFit& m = d.mu_i;
  const PhiFit& p = d.phi_i;
  std::string s =
      "# grainlift rheology: mu(I) = mu_s + (mu_2 - mu_s) / (I0 / I + 1) (Jop et al. 2006) and\n"
      "# Phi(I) = phi_max - a I, fitted to steady simple-shear points; errors are one sigma.\n\n"
      "[source]\n";
  for (const auto& [key, value] : d.source) s += toml_key(key) + " = " + toml_string(value) + "\n";
  auto line = [&s](const char* key, double value) {
    s += fmt::format("{} = {}\n", key, number(value));
  };
  s += "\n[mu_i]\n";
  line("mu_s", m.mu_s);
  line("mu_2", m.mu_2);
  line("I0", m.I0);
  line("mu_s_err", m.mu_s_err);
  line("mu_2_err", m.mu_2_err);
  line("I0_err", m.I0_err);
  s += "covariance = [  # (mu_s, mu_2, I0)\n";
  for (const auto& row : m.covariance)
    s += fmt::format("  [{}, {}, {}],\n", number(row[0]), number(row[1]), number(row[2]));
  s += "]\n";
  line("chi2_per_dof", m.chi2_per_dof);
  s += fmt::format("points = {}\n", m.points);
  line("I_min", d.I_min);
  line("I_max", d.I_max);
  s += "\n[phi_i]\n";
  line("phi_max", p.phi_max);
  line("a", p.a);
  line("phi_max_err", p.phi_max_err);
  line("a_err", p.a_err);
  line("chi2_per_dof", p.chi2_per_dof);
  s += fmt::format("points = {}\n", p.points);
  for (const auto& q : d.points)
    s += fmt::format("\n[[point]]\nI = {}\nmu = {}\nmu_stderr = {}\nphi = {}\nphi_stderr = {}\n",
                     number(q.I), number(q.mu), number(q.mu_stderr), number(q.phi),
                     number(q.phi_stderr));
  if (d.wall) {
    const WallLaw& w = *d.wall;
    s += "\n# the grains' wall law: mu_w(v) = mu_a + (mu_b - mu_a) |v| / (|v| + v0), v in m/s\n"
         "[wall]\n";
    line("friction", w.friction);
    line("friction_err", w.friction_err);
    line("mu_a", w.mu_a);
    line("mu_a_err", w.mu_a_err);
    line("mu_b", w.mu_b);
    line("mu_b_err", w.mu_b_err);
    line("v0", w.v0);
    line("v0_err", w.v0_err);
    line("chi2_per_dof", w.chi2_per_dof);
    s += fmt::format("points = {}\n", w.points);
  }
  if (d.nonlocal) {
    const Cooperativity& a = *d.nonlocal;
    s += "\n# the nonlocal fluidity's cooperativity length xi = amplitude d / sqrt|mu - mu_s|,\n"
         "# fitted on a layer sheared at its top, mu_min <= mu = tau / p <= mu_max\n[nonlocal]\n";
    line("amplitude", a.amplitude);
    line("amplitude_err", a.amplitude_err);
    line("chi2_per_dof", a.chi2_per_dof);
    s += fmt::format("points = {}\n", a.points);
    line("mu_min", a.mu_min);
    line("mu_max", a.mu_max);
  }
  return s;
}

void write_rheology_file(const std::string& path, const RheologyFile& d) {
  write_text_atomically(path, rheology_file_text(d, path));
}

RheologyFile read_rheology_file(const std::string& path) {
  toml::table root;
  try {
    root = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    throw InputError(fmt::format("{}:{}:{}: not a valid TOML rheology file: {}", path,
                                 e.source().begin.line, e.source().begin.column,
                                 e.description()));
  }
  for (const auto& [k, node] : root) {
    const std::string key(k.str());
    if (key != "source" && key != "mu_i" && key != "phi_i" && key != "point" && key != "wall" &&
        key != "nonlocal")
      throw InputError(fmt::format(
          "{}: unknown table '{}' (accepted: source, mu_i, phi_i, point, wall, nonlocal)",
          at(path, &node), key));
  }
  RheologyFile d;
  if (const toml::table* src = root["source"].as_table()) {
    for (const auto& [k, node] : *src) {
      const auto v = node.value<std::string>();
      if (!v || !node.is_string())
        throw InputError(fmt::format("{}: [source] {} is not a string", at(path, &node), k.str()));
      d.source[std::string(k.str())] = *v;
    }
  }

  const toml::table& mu = table_of(root, "mu_i", path);
  refuse_unknown(mu, mu_i_keys, "covariance", "mu_i", path);
  auto mu_number = [&](const char* key) { return get_number(mu, mu_i_keys, key, "mu_i", path); };
  MuIFit& m = d.mu_i;
  m.mu_s = mu_number("mu_s");
  m.mu_2 = mu_number("mu_2");
  m.I0 = mu_number("I0");
  m.mu_s_err = mu_number("mu_s_err");
  m.mu_2_err = mu_number("mu_2_err");
  m.I0_err = mu_number("I0_err");
  m.chi2_per_dof = mu_number("chi2_per_dof");
  m.points = get_count(mu, mu_i_keys, "mu_i", path);
  d.I_min = mu_number("I_min");
  d.I_max = mu_number("I_max");
  const toml::array* cov = mu["covariance"].as_array();
  if (!cov || cov->size() != 3)
    throw InputError(fmt::format("{}: [mu_i] covariance missing or malformed (accepted {})",
                                 at(path, cov), covariance_range));
  for (std::size_t i = 0; i < 3; ++i) {
    const toml::array* row = (*cov)[i].as_array();
    if (!row || row->size() != 3)
      throw InputError(fmt::format("{}: [mu_i] covariance row {} malformed (accepted {})",
                                   at(path, cov), i, covariance_range));
    for (std::size_t j = 0; j < 3; ++j) {
      const auto v = (*row)[j].value<double>();
      if (!v)
        throw InputError(fmt::format("{}: [mu_i] covariance[{}][{}] is not a number (accepted {})",
                                     at(path, cov), i, j, covariance_range));
      m.covariance[i][j] = *v;
    }
  }
  m.converged = true;
  m.message = "read from " + path;

  const toml::table& phi = table_of(root, "phi_i", path);
  refuse_unknown(phi, phi_i_keys, nullptr, "phi_i", path);
  auto phi_number = [&](const char* key) {
    return get_number(phi, phi_i_keys, key, "phi_i", path);
  };
  d.phi_i.phi_max = phi_number("phi_max");
  d.phi_i.a = phi_number("a");
  d.phi_i.phi_max_err = phi_number("phi_max_err");
  d.phi_i.a_err = phi_number("a_err");
  d.phi_i.chi2_per_dof = phi_number("chi2_per_dof");
  d.phi_i.points = get_count(phi, phi_i_keys, "phi_i", path);

  if (const toml::node* points = root.get("point")) {
    const toml::array* arr = points->as_array();
    if (!arr || !arr->is_array_of_tables())
      throw InputError(fmt::format("{}: 'point' must be an array of tables ([[point]])",
                                   at(path, points)));
    std::size_t k = 0;
    for (const auto& node : *arr) {
      const toml::table& t = *node.as_table();
      const std::string table = fmt::format("point {}", ++k);
      refuse_unknown(t, point_keys, nullptr, table, path);
      auto pt = [&](const char* key) { return get_number(t, point_keys, key, table, path); };
      d.points.push_back({pt("I"), pt("mu"), pt("mu_stderr"), pt("phi"), pt("phi_stderr")});
    }
  }
  if (root.contains("wall")) d.wall = read_wall(root, path);
  if (root.contains("nonlocal")) d.nonlocal = read_nonlocal(root, path);
  validate(d, path);
  return d;
}

}  // namespace grainlift

namespace grainlift {

bool is_rheology_file(const std::string& path) {
  try {
    const toml::table root = toml::parse_file(path);
    return root.contains("mu_i") && !root.contains("domain");
  } catch (const toml::parse_error&) {
    return false;
  }
}

}  // namespace grainlift
