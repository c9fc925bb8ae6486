// The typed Case from a checked case table: defaults filled from the key registry, the
// sections read into the model, the depth sweep's mode, the checks between keys and the
// calibrated rheology file (case_loader.cc checks each key first).
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

#include "case/case_reader_parts.h"
#include "grainlift/shared/case/case_keys.h"
#include "grainlift/shared/errors.h"
#include "grainlift/shared/rheology/rheology_cache.h"
#include "grainlift/shared/rheology/rheology_file.h"

namespace grainlift::case_detail {

namespace {

/// The case's table with every absent key filled from the key registry, the only place a
/// default is written: a literal default as parsed TOML, a default that names another key
/// (intruder.friction: "grains.friction") as that key's value. Required keys and
/// the keys whose default is a sentence (continuum.box_half_size "from the domain", read as
/// [0, 0]; continuum.bed_top "the domain's", read as NaN) stay absent.
toml::table with_defaults(const toml::table& root) {
  toml::table full = root;
  const auto split = [](const std::string& path) {
    std::vector<std::string> parts;
    std::stringstream ss(path);
    for (std::string p; std::getline(ss, p, '.');) parts.push_back(p);
    return parts;
  };
  // literal defaults first, then those naming a key (in registry order: intruder.friction
  // before continuum.wall_friction, which names it)
  for (const bool naming : {false, true}) {
    for (const KeySpec& k : case_keys()) {
      if (k.required || k.default_text.empty() || full.at_path(k.path)) continue;
      if (const KeySpec* other = find_key(k.default_text)) {
        if (naming) {
          if (const toml::node* v = full.at_path(other->path).node())
            insert_at(full, split(k.path), toml::node_view<const toml::node>(v));
        }
        continue;
      }
      if (naming) continue;
      toml::table parsed;
      try {
        parsed = toml::parse("v = " + k.default_text);
      } catch (const toml::parse_error&) {
        continue;  // a sentence, not a value ("from the domain")
      }
      insert_at(full, split(k.path), std::move(*parsed.get("v")));
    }
  }
  return full;
}

// ---- typed getters (values are already validated; defaults filled by with_defaults)
double get_real(const toml::table& r, const std::string& path) {
  auto n = r.at_path(path);
  if (auto f = n.as_floating_point()) return f->get();
  if (auto i = n.as_integer()) return double(i->get());
  return 0;
}
long long get_int(const toml::table& r, const std::string& path) {
  if (auto i = r.at_path(path).as_integer()) return i->get();
  return 0;
}
bool get_bool(const toml::table& r, const std::string& path) {
  return r.at_path(path).value_or(false);
}
std::string get_text(const toml::table& r, const std::string& path) {
  return r.at_path(path).value_or(std::string());
}
Vec2 get_vec2(const toml::table& r, const std::string& path) {
  if (auto a = r.at_path(path).as_array())
    return {(*a)[0].value_or(0.0), (*a)[1].value_or(0.0)};
  return {0, 0};
}

/// The [continuum] section of the filled table @p r (@p root: the case as written, to tell a
/// law the case states from the registry's default).
ContinuumSection read_continuum(const toml::table& r, const toml::table& root) {
  ContinuumSection cn;
  cn.ambient_pressure = get_real(r, "continuum.ambient_pressure");
  cn.mu_s = get_real(r, "continuum.mu_s");
  cn.mu_2 = get_real(r, "continuum.mu_2");
  cn.I0 = get_real(r, "continuum.I0");
  cn.rheology_file = get_text(r, "continuum.rheology_file");
  cn.law_source = "default";
  for (const char* law_key : {"continuum.mu_s", "continuum.mu_2", "continuum.I0"})
    if (root.at_path(law_key)) cn.law_source = "case";
  cn.regularisation = get_text(r, "continuum.regularisation");
  cn.delta = get_real(r, "continuum.delta");
  cn.barker_gray_IN = get_real(r, "continuum.barker_gray_IN");
  cn.eta_max = get_real(r, "continuum.eta_max");
  cn.pressure_smoothing = get_real(r, "continuum.pressure_smoothing");
  cn.gravity_treatment = get_text(r, "continuum.gravity_treatment");
  cn.wall = get_text(r, "continuum.wall");
  cn.wall_friction = get_real(r, "continuum.wall_friction");
  cn.wall_law = get_text(r, "continuum.wall_law");
  cn.inertia = get_text(r, "continuum.inertia");
  cn.box_half_size = get_vec2(r, "continuum.box_half_size");
  cn.bed_top = r.at_path("continuum.bed_top") ? get_real(r, "continuum.bed_top")
                                               : std::numeric_limits<double>::quiet_NaN();
  cn.far_field = get_text(r, "continuum.far_field");
  cn.open_length = get_vec2(r, "continuum.open_length");
  cn.refinement = int(get_int(r, "continuum.refinement"));
  cn.adaptive_cycles = int(get_int(r, "continuum.adaptive_cycles"));
  cn.wall_layers = int(get_int(r, "continuum.wall_layers"));
  cn.target_error = get_real(r, "continuum.target_error");
  cn.nested = get_bool(r, "continuum.nested");
  cn.mesh_error_estimate = get_bool(r, "continuum.mesh_error_estimate");
  // The default is a stated error, not a level: a case that names neither
  // continuum.refinement nor continuum.target_error gets nested levels up to the default
  // refinement that stop at the first meeting the default target; a level stated alone is
  // solved as it is (no target). Without nested levels to stop (nested = false, adaptive
  // cycles) an unstated level is 2, the level these modes were measured at, and no target.
  const bool level_stated = bool(root.at_path("continuum.refinement"));
  const bool target_stated = bool(root.at_path("continuum.target_error"));
  const bool levels_stop = cn.nested && cn.adaptive_cycles == 0;
  if (!target_stated && (level_stated || !levels_stop)) cn.target_error = 0;
  if (!level_stated && !levels_stop) cn.refinement = 2;
  cn.tolerance = get_real(r, "continuum.tolerance");
  cn.max_iterations = int(get_int(r, "continuum.max_iterations"));
  cn.picard_iterations = int(get_int(r, "continuum.picard_iterations"));
  cn.linear_solver = get_text(r, "continuum.linear_solver");
  cn.model = get_text(r, "continuum.model");
  cn.nonlocal_amplitude = get_real(r, "continuum.nonlocal_amplitude");
  cn.nonlocal_iterations = int(get_int(r, "continuum.nonlocal_iterations"));
  cn.nonlocal_relaxation = get_real(r, "continuum.nonlocal_relaxation");
  cn.nonlocal_tolerance = get_real(r, "continuum.nonlocal_tolerance");
  cn.dilatancy = get_text(r, "continuum.dilatancy");
  return cn;
}

}  // namespace

void cross_checks(const toml::table& r, const Case& c, Diagnostics& diag) {
  auto where = [&](const std::string& path) { return diag.where(path, r.at_path(path).node()); };
  const auto& d = c.domain;
  if (!(d.x_range[1] > d.x_range[0]))
    diag.error(where("domain.x_range"), "x_range must be [xmin, xmax] with xmax > xmin");
  if (!(d.y_range[1] > d.y_range[0]))
    diag.error(where("domain.y_range"), "y_range must be [ymin, ymax] with ymax > ymin");
  if (d.periodic[0] && (d.wall_left || d.wall_right))
    diag.error(where("domain.walls"), "walls 'left'/'right' need domain.periodic[0] = false");
  if (d.periodic[1] && (d.wall_bottom || d.wall_top))
    diag.error(where("domain.walls"), "walls 'bottom'/'top' need domain.periodic[1] = false");
  if (d.lid_pressure > 0 && (!d.wall_top || d.periodic[1]))
    diag.error(where("domain.lid_pressure"),
               fmt::format("domain.lid_pressure = {} Pa needs the \"top\" wall in domain.walls "
                           "(it becomes the lid) and domain.periodic[1] = false",
                           d.lid_pressure));
  if (d.lid_pressure > 0 && c.continuum.ambient_pressure > 0)
    diag.error(where("continuum.ambient_pressure"),
               fmt::format("continuum.ambient_pressure = {} Pa and domain.lid_pressure = {} Pa: "
                           "with a lid, the lid is the confining pressure of both solvers; remove "
                           "continuum.ambient_pressure",
                           c.continuum.ambient_pressure, d.lid_pressure));
  const auto& in = c.intruder;
  const double R = 0.5 * in.diameter;
  if (in.position[0] < d.x_range[0] || in.position[0] > d.x_range[1] ||
      in.position[1] - R < d.y_range[0] || in.position[1] + R > d.y_range[1])
    diag.error(where("intruder.position"),
               fmt::format("the intruder (centre [{}, {}] m, radius {} m) must lie inside the box",
                           in.position[0], in.position[1], R));
  if (std::hypot(in.velocity[0], in.velocity[1]) == 0)
    diag.error(where("intruder.velocity"),
               "intruder.velocity must not be zero (drag and lift are defined along V)");
  // the continuum's box (solver_box, docs/continuum-model.md "The box")
  const auto& cn = c.continuum;
  if (cn.wall_law != "coulomb") {
    const std::string law = fmt::format("continuum.wall_law = \"{}\"", cn.wall_law);
    if (cn.wall != "coulomb")
      diag.error(where("continuum.wall_law"),
                 law + " is a Coulomb wall's friction: it needs continuum.wall = \"coulomb\"");
    if (cn.rheology_file.empty())
      diag.error(where("continuum.wall_law"),
                 law + " reads the [wall] table of continuum.rheology_file: name the file "
                       "(studies/wall_law/ writes the table)");
    if (r.at_path("continuum.wall_friction"))
      diag.error(where("continuum.wall_friction"),
                 "continuum.wall_friction and " + law +
                     " both give the wall's friction: remove continuum.wall_friction");
  }
  if (cn.far_field == "periodic" && (!d.periodic[0] || d.wall_left || d.wall_right))
    diag.error(where("continuum.far_field"),
               "continuum.far_field = \"periodic\" needs a box periodic in x "
               "(domain.periodic[0] = true, no left or right wall); use \"open\" or \"auto\"");
  if (!std::isnan(cn.bed_top)) {
    const double bottom = d.y_range[0] + (d.wall_bottom ? c.grains.diameter : 0.0);
    if (!(cn.bed_top > in.position[1] + R && cn.bed_top <= d.y_range[1] && cn.bed_top > bottom))
      diag.error(where("continuum.bed_top"),
                 fmt::format("continuum.bed_top = {} m must lie above the intruder's top ({} m) "
                             "and at most at the top of the box ({} m)",
                             cn.bed_top, in.position[1] + R, d.y_range[1]));
  }
  if (c.dem.steady_travel >= c.dem.travel)
    diag.error(where("dem.steady_travel"),
               fmt::format("dem.steady_travel = {} must be less than dem.travel = {}",
                           c.dem.steady_travel, c.dem.travel));
  if (c.continuum.mu_2 < c.continuum.mu_s)
    diag.error(where("continuum.mu_2"),
               fmt::format("continuum.mu_2 = {} must be >= continuum.mu_s = {}", c.continuum.mu_2,
                           c.continuum.mu_s));
  const double Lx = d.x_range[1] - d.x_range[0], Ly = d.y_range[1] - d.y_range[0];
  if (c.grains.diameter * 4 > std::min(Lx, Ly))
    diag.error(where("grains.diameter"),
               "the box must be at least 4 grain diameters wide in each direction");
  // Law-specific contact keys may only appear with their law.
  if (auto contact = r.at_path("grains.contact").as_table()) {
    for (const auto& [key, node] : *contact) {
      const std::string path = "grains.contact." + std::string(key.str());
      const KeySpec* k = find_key(path);
      if (k && !k->only_for_law.empty() && k->only_for_law != c.grains.contact.law)
        diag.error(diag.where(path, &node),
                   fmt::format("'{}' belongs to law \"{}\", but grains.contact.law = \"{}\"", path,
                               k->only_for_law, c.grains.contact.law));
    }
  }
}

/// The calibrated law of continuum.rheology_file (relative to the case file's folder) in place
/// of continuum.mu_s, mu_2, I0, which the case must then leave out.
void apply_rheology_file(const toml::table& root, const std::string& name, Case& c,
                         Diagnostics& diag) {
  const std::string key = "continuum.rheology_file";
  for (const char* law_key : {"continuum.mu_s", "continuum.mu_2", "continuum.I0"})
    if (root.at_path(law_key))
      diag.error(diag.where(law_key, root.at_path(law_key).node()),
                 fmt::format("{} and {} both give mu(I): remove {} (the file's calibrated law "
                             "is used)",
                             law_key, key, law_key));
  if (!diag.empty()) return;
  std::filesystem::path file(c.continuum.rheology_file);
  if (file.is_relative()) file = std::filesystem::path(name).parent_path() / file;
  c.continuum.rheology_file = file.string();
  try {
    const RheologyFile law = read_rheology_file(file.string());
    c.continuum.law_source = "rheology file";
    c.continuum.mu_s = law.mu_i.mu_s;
    c.continuum.mu_2 = law.mu_i.mu_2;
    c.continuum.I0 = law.mu_i.I0;
    take_phi_i(law, c.continuum);
    if (c.continuum.wall_law != "coulomb") {
      if (!law.wall)
        diag.error(diag.where("continuum.wall_law", root.at_path("continuum.wall_law").node()),
                   fmt::format("continuum.wall_law = \"{}\": {} has no [wall] table "
                               "(studies/wall_law/wall_law.py --write-wall writes one)",
                               c.continuum.wall_law, file.string()));
      else
        c.continuum.wall_friction = law.wall->friction;
      if (law.wall && c.continuum.wall_law == "measured_slip") {
        c.continuum.wall_mu_a = law.wall->mu_a;
        c.continuum.wall_mu_b = law.wall->mu_b;
        c.continuum.wall_v0 = law.wall->v0;
      }
    }
    // the cooperativity amplitude measured on these grains, unless the case states its own
    if (law.nonlocal && !root.at_path("continuum.nonlocal_amplitude")) {
      c.continuum.nonlocal_amplitude = law.nonlocal->amplitude;
      c.continuum.nonlocal_amplitude_source = "[nonlocal] of " + file.string();
    }
  } catch (const InputError& e) {
    diag.error(diag.where(key, root.at_path(key).node()), e.what());
  }
}

/// Guillard et al. (2014)'s three ways of putting the intruder at depth h (scene.depth_mode;
/// docs/dem-model.md, "Depth modes"): derives the top of the box (free_surface), the lid pressure
/// (heavy_lid, lid_only) and the grains' gravity (lid_only) from scene.depth.
void apply_depth_mode(const toml::table& root, Case& c, Diagnostics& diag) {
  auto where = [&](const std::string& path) { return diag.where(path, root.at_path(path).node()); };
  auto& s = c.scene;
  if (s.depth_mode == "box") {
    if (s.depth > 0)
      diag.error(where("scene.depth"),
                 fmt::format("scene.depth = {} m needs scene.depth_mode = \"free_surface\", "
                             "\"heavy_lid\" or \"lid_only\" (in \"box\" mode the domain sets "
                             "the depth)",
                             s.depth));
    return;
  }
  const std::string mode = fmt::format("scene.depth_mode = \"{}\"", s.depth_mode);
  if (!(s.depth > 0))
    diag.error(where("scene.depth_mode"),
               fmt::format("{} needs scene.depth > 0 (m, the equivalent depth of the intruder "
                           "centre)",
                           mode));
  if (root.at_path("domain.lid_pressure"))
    diag.error(where("domain.lid_pressure"),
               fmt::format("{} derives domain.lid_pressure from scene.depth: remove it", mode));
  if (c.continuum.ambient_pressure > 0)
    diag.error(where("continuum.ambient_pressure"),
               fmt::format("{} sets the pressure from scene.depth: remove "
                           "continuum.ambient_pressure",
                           mode));
  const double g = std::hypot(s.gravity[0], s.gravity[1]);
  if (!(g > 0) || s.gravity[0] != 0 || !(s.gravity[1] < 0))
    diag.error(where("scene.gravity"),
               fmt::format("{} needs gravity along -y, scene.gravity = [0.0, -g] with g > 0 "
                           "(lid_only: the g of the lid); got [{}, {}]",
                           mode, s.gravity[0], s.gravity[1]));
  const bool lid = s.depth_mode != "free_surface";
  if (lid && !c.domain.wall_top)
    diag.error(where("domain.walls"),
               fmt::format("{} needs the \"top\" wall in domain.walls: it becomes the lid", mode));
  if (!lid && c.domain.wall_top)
    diag.error(where("domain.walls"),
               fmt::format("{}: a free surface has no top wall; remove \"top\" from domain.walls",
                           mode));
  if (!diag.empty()) return;

  const double rho = c.bulk_density(), yc = c.intruder.position[1];
  auto& d = c.domain;
  if (s.depth_mode == "free_surface") {
    d.y_range[1] = yc + s.depth;  // the bed fills the box: its top is the free surface
  } else if (s.depth_mode == "heavy_lid") {
    // The real bed above the centre weighs rho g (ymax - yc); the lid adds the rest of h.
    const double real = d.y_range[1] - yc;
    if (!(s.depth > real * (1 + 1e-9)))
      diag.error(where("scene.depth"),
                 fmt::format("scene.depth = {} m must exceed the real depth of the bed above the "
                             "intruder, domain.y_range[1] - intruder.position[1] = {} m (the lid "
                             "adds the rest); lower the top of the box or use \"free_surface\"",
                             s.depth, real));
    d.lid_pressure = rho * g * (s.depth - real);
  } else {  // lid_only: the same P0 with no gradient
    d.lid_pressure = rho * g * s.depth;
    s.lid_gravity = g;
    s.gravity = {0.0, 0.0};
  }
}

Case build_case(const toml::table& root) {
  const toml::table r = with_defaults(root);
  Case c;
  c.scene.gravity = get_vec2(r, "scene.gravity");
  c.scene.depth_mode = get_text(r, "scene.depth_mode");
  c.scene.depth = get_real(r, "scene.depth");
  c.domain.x_range = get_vec2(r, "domain.x_range");
  c.domain.y_range = get_vec2(r, "domain.y_range");
  if (auto a = r.at_path("domain.periodic").as_array())
    c.domain.periodic = {(*a)[0].value_or(false), (*a)[1].value_or(false)};
  if (auto a = r.at_path("domain.walls").as_array())
    for (const auto& e : *a) {
      const std::string w = e.value_or(std::string());
      c.domain.wall_bottom |= w == "bottom";
      c.domain.wall_top |= w == "top";
      c.domain.wall_left |= w == "left";
      c.domain.wall_right |= w == "right";
    }
  c.domain.lid_pressure = get_real(r, "domain.lid_pressure");
  c.domain.lid = get_text(r, "domain.lid");
  auto& g = c.grains;
  g.diameter = get_real(r, "grains.diameter");
  g.polydispersity = get_real(r, "grains.polydispersity");
  g.density = get_real(r, "grains.density");
  g.area_fraction = get_real(r, "grains.area_fraction");
  g.friction = get_real(r, "grains.friction");
  auto& ct = g.contact;
  ct.law = get_text(r, "grains.contact.law");
  ct.kn = get_real(r, "grains.contact.kn");
  ct.kt = get_real(r, "grains.contact.kt");
  ct.gamma_n = get_real(r, "grains.contact.gamma_n");
  ct.gamma_t = get_real(r, "grains.contact.gamma_t");
  ct.youngs_modulus = get_real(r, "grains.contact.youngs_modulus");
  ct.poisson_ratio = get_real(r, "grains.contact.poisson_ratio");
  ct.restitution = get_real(r, "grains.contact.restitution");
  auto& in = c.intruder;
  in.diameter = get_real(r, "intruder.diameter");
  in.position = get_vec2(r, "intruder.position");
  in.velocity = get_vec2(r, "intruder.velocity");
  in.omega = get_real(r, "intruder.omega");
  in.spin_ramp_time = get_real(r, "intruder.spin_ramp_time");
  in.friction = get_real(r, "intruder.friction");
  auto& dm = c.dem;
  dm.dt = get_real(r, "dem.dt");
  dm.max_dt_fraction = get_real(r, "dem.max_dt_fraction");
  dm.travel = get_real(r, "dem.travel");
  dm.steady_travel = get_real(r, "dem.steady_travel");
  dm.target_error = get_real(r, "dem.target_error");
  dm.frictionless_path = get_bool(r, "dem.frictionless_path");
  dm.sleep = get_bool(r, "dem.sleep");
  dm.checkpoint_minutes = get_real(r, "dem.checkpoint_minutes");
  dm.checkpoint_steps = get_int(r, "dem.checkpoint_steps");
  dm.sleep_speed = get_real(r, "dem.sleep_speed");
  dm.seed = std::uint64_t(get_int(r, "dem.seed"));
  dm.sample_every = int(get_int(r, "dem.sample_every"));
  dm.sort_every = get_int(r, "dem.sort_every");
  dm.field_every = int(get_int(r, "dem.field_every"));
  dm.relax_ke = get_real(r, "dem.relax_ke");
  dm.preparation = get_text(r, "dem.preparation");
  dm.compression_speed = get_real(r, "dem.compression_speed");
  dm.compression_drag = get_bool(r, "dem.compression_drag");
  dm.packing_cache = get_text(r, "dem.packing_cache");
  c.continuum = read_continuum(r, root);
  auto& o = c.output;
  o.angles = int(get_int(r, "output.angles"));
  o.kernel_width_deg = get_real(r, "output.kernel_width_deg");
  o.histogram_bins = int(get_int(r, "output.histogram_bins"));
  o.blocks = int(get_int(r, "output.blocks"));
  o.fields = get_bool(r, "output.fields");
  o.field_spacing = get_real(r, "output.field_spacing");
  o.field_half_size = get_vec2(r, "output.field_half_size");
  o.vtu = get_bool(r, "output.vtu");
  return c;
}

}  // namespace grainlift::case_detail
