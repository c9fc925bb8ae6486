#include "grainlift/shared/case/case_keys.h"

#include <fmt/format.h>

#include <limits>

namespace grainlift {
namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

KeySpec real(std::string path, bool req, std::string def, double lo, double hi, bool lo_open,
             bool hi_open, std::string unit, std::string desc, std::string law = "") {
  return {std::move(path), KeyType::real, req, std::move(def), lo, hi, lo_open, hi_open, {},
          std::move(unit), std::move(desc), std::move(law)};
}
KeySpec integer(std::string path, std::string def, double lo, double hi, std::string desc) {
  return {std::move(path), KeyType::integer, false, std::move(def), lo, hi, false, false, {}, "-",
          std::move(desc), ""};
}
KeySpec vec2(std::string path, bool req, std::string def, double lo, double hi, std::string unit,
             std::string desc) {
  return {std::move(path), KeyType::vec2, req, std::move(def), lo, hi, false, false, {},
          std::move(unit), std::move(desc), ""};
}
KeySpec choice(std::string path, std::string def, std::vector<std::string> choices,
               std::string desc) {
  return {std::move(path), KeyType::text, false, std::move(def), 0, 0, false, false,
          std::move(choices), "-", std::move(desc), ""};
}
KeySpec boolean(std::string path, std::string def, std::string desc) {
  return {std::move(path), KeyType::boolean, false, std::move(def), 0, 0, false, false, {}, "-",
          std::move(desc), ""};
}

/// [scene]
void add_scene_keys(std::vector<KeySpec>& k) {
  k.push_back(vec2("scene.gravity", false, "[0.0, 0.0]", -1e3, 1e3, "m/s^2",
                   "gravitational acceleration [gx, gy]"));
  k.push_back(choice("scene.depth_mode", "\"box\"",
                     {"box", "free_surface", "heavy_lid", "lid_only"},
                     "how the intruder's depth is made (Guillard et al. 2014, Sec. II; "
                     "docs/dem-model.md, \"Depth modes\"): box = as the domain and "
                     "domain.lid_pressure say; free_surface = gravity, no lid, the top of the "
                     "box set to intruder.position[1] + scene.depth; heavy_lid = gravity and a "
                     "lid on the top wall whose pressure makes the equivalent depth "
                     "scene.depth; lid_only = the same lid pressure rho |g| scene.depth with "
                     "gravity on the lid only (the grains feel none: P0 with no gradient)"));
  k.push_back(real("scene.depth", false, "0.0", 0, 1e4, false, false, "m",
                   "equivalent depth h of the intruder centre, P0 = rho |g| h with rho = Phi "
                   "rho_s (needed, > 0, by every scene.depth_mode but box)"));
}

/// [domain]
void add_domain_keys(std::vector<KeySpec>& k) {
  k.push_back(vec2("domain.x_range", true, "", -1e4, 1e4, "m", "[xmin, xmax] of the box"));
  k.push_back(vec2("domain.y_range", true, "", -1e4, 1e4, "m", "[ymin, ymax] of the box"));
  k.push_back({"domain.periodic", KeyType::bool2, false, "[true, false]", 0, 0, false, false, {},
               "-", "periodic in [x, y]", ""});
  k.push_back({"domain.walls", KeyType::text_list, false, "[]", 0, 0, false, false,
               {"bottom", "top", "left", "right"}, "-",
               "box edges closed by walls of frozen grains (not on a periodic direction)", ""});
  k.push_back(real("domain.lid_pressure", false, "0.0", 0, 1e9, false, false, "Pa",
                   "DEM: confining pressure P on the top wall, which becomes a rigid lid moving "
                   "in y and pushed down with P times the box width (2D reading as for "
                   "grains.density: force per unit depth per unit lid length, N/m per m; "
                   "rho g h with rho = Phi rho_s gives the lithostatic value); 0 = fixed top "
                   "wall; > 0 needs the \"top\" wall and domain.periodic[1] = false"));
  k.push_back(choice("domain.lid", "\"rigid\"", {"rigid", "free_disks"},
                     "DEM, with a lid pressure: rigid = the top wall moves as one body; "
                     "free_disks = each of its disks rises and sinks on its own under its share "
                     "of the load (Guillard et al. 2014's heavy lid of free-to-rise disks; "
                     "docs/dem-model.md)"));
}

/// [intruder]
void add_intruder_keys(std::vector<KeySpec>& k) {
  k.push_back(real("intruder.diameter", true, "", 0, 1e3, true, false, "m", "intruder diameter D"));
  k.push_back(vec2("intruder.position", false, "[0.0, 0.0]", -1e4, 1e4, "m",
                   "centre of the intruder at t = 0 (inside the box)"));
  k.push_back(vec2("intruder.velocity", true, "", -1e3, 1e3, "m/s",
                   "translational velocity V [vx, vy] (lab frame, not zero)"));
  k.push_back(real("intruder.omega", false, "0.0", -1e5, 1e5, false, false, "rad/s",
                   "angular velocity, counter-clockwise positive"));
  k.push_back(real("intruder.spin_ramp_time", false, "0.0", 0, 1e4, false, false, "s",
                   "omega ramps linearly from 0 over this time (0: from the start)"));
  k.push_back(real("intruder.friction", false, "grains.friction", 0, 10, false, false, "-",
                   "Coulomb friction between grains and the intruder"));
}

/// [grains]
void add_grains_keys(std::vector<KeySpec>& k) {
  k.push_back(real("grains.diameter", true, "", 0, 1e2, true, false, "m", "mean grain diameter d"));
  k.push_back(real("grains.polydispersity", false, "0.1", 0, 0.5, false, false, "-",
                   "half-width of the uniform diameter distribution, relative to d"));
  k.push_back(real("grains.density", true, "", 0, 1e6, true, false, "kg/m^3",
                   "solid density rho_s per unit length (= 2D mass per area, kg/m^2)"));
  k.push_back(real("grains.area_fraction", true, "", 0, 0.9, true, false, "-",
                   "area fraction Phi of the bed"));
  k.push_back(real("grains.friction", false, "0.5", 0, 10, false, false, "-",
                   "Coulomb friction coefficient mu between grains"));
}

/// [grains.contact]
void add_contact_keys(std::vector<KeySpec>& k) {
  k.push_back(choice("grains.contact.law", "\"kumar2019\"", {"kumar2019", "guillard2014"},
                     "contact law (see docs/dem-model.md)"));
  k.push_back(real("grains.contact.kn", false, "2e9", 0, 1e15, true, false, "Pa",
                   "normal stiffness K_n (Kumar eq. 1)", "kumar2019"));
  k.push_back(real("grains.contact.kt", false, "2.45e9", 0, 1e15, false, false, "Pa",
                   "tangential stiffness K_t (Kumar eq. 2)", "kumar2019"));
  k.push_back(real("grains.contact.gamma_n", false, "8e6", 0, 1e12, false, false, "1/(m s)",
                   "normal damping gamma_n (Kumar eq. 1)", "kumar2019"));
  k.push_back(real("grains.contact.gamma_t", false, "8e6", 0, 1e12, false, false, "1/(m s)",
                   "tangential damping gamma_t (Kumar eq. 2)", "kumar2019"));
  k.push_back(real("grains.contact.youngs_modulus", false, "5e6", 0, 1e13, true, false, "Pa",
                   "Young's modulus E (Guillard Table I)", "guillard2014"));
  k.push_back(real("grains.contact.poisson_ratio", false, "0.45", -1, 0.5, true, true, "-",
                   "Poisson ratio nu (Guillard Table I)", "guillard2014"));
  k.push_back(real("grains.contact.restitution", false, "0.6", 0, 1, true, false, "-",
                   "coefficient of restitution e (Guillard Table I)", "guillard2014"));
}

/// [dem]
void add_dem_keys(std::vector<KeySpec>& k) {
  k.push_back(real("dem.dt", false, "2e-6", 0, 1e-2, true, false, "s", "time step"));
  k.push_back(real("dem.max_dt_fraction", false, "0.1", 0, 1, true, false, "-",
                   "largest accepted dt as a fraction of the binary collision time"));
  k.push_back(real("dem.travel", false, "300.0", 0, 1e6, true, false, "d",
                   "distance the intruder travels, in mean grain diameters"));
  k.push_back(real("dem.steady_travel", false, "30.0", 0, 1e6, false, false, "d",
                   "travel before averaging starts (less than dem.travel)"));
  k.push_back(real("dem.target_error", false, "0.0", 0, 1, false, true, "-",
                   "stop once the relative standard errors of the mean drag and of the mean lift "
                   "(block averages, corrected for correlated blocks) are both at most this; "
                   "0: run the whole dem.travel, which remains the limit"));
  k.push_back(boolean("dem.frictionless_path", "true",
                      "with grains.friction = 0, evaluate grain contacts by their normal force "
                      "only (no tangential history): the same trajectories, less work "
                      "(docs/performance.md); false: the general law"));
  k.push_back(boolean("dem.sleep", "true",
                      "sleeping grains: grains far from the intruder that are at rest, with "
                      "neighbours at rest, leave the step until something touches them "
                      "(scenes without gravity; docs/performance.md)"));
  k.push_back(real("dem.sleep_speed", false, "0.0", 0, 1, false, false, "V",
                   "with dem.sleep: grains at most this fraction of the intruder speed may sleep "
                   "and are stopped; 0: only grains exactly at rest (the same trajectories as "
                   "without sleeping, bit for bit)"));
  k.push_back(real("dem.checkpoint_minutes", false, "10.0", 0, 1e6, false, false, "min",
                   "wall time between checkpoints (<out>/dem.checkpoint; `grainlift run CASE "
                   "--resume DIR` goes on from it); 0: only when interrupted"));
  k.push_back(integer("dem.checkpoint_steps", "0", 0, 9.2e18,
                      "also a checkpoint every this many steps (0: by time only)"));
  k.push_back(integer("dem.seed", "1", 0, 9.2e18, "random seed: packing and size distribution"));
  k.push_back(integer("dem.sample_every", "50", 1, 1e7, "steps between force samples"));
  k.push_back(integer("dem.sort_every", "0", 0, 1e9,
                      "steps between renumberings of the grains into rows of cells, which "
                      "keep the threads' slabs of rows compact as the flow mixes the bed "
                      "(docs/performance.md, \"Threads\"); new bits, the same for any thread "
                      "count; 0: never (the bed's order from its packing)"));
  k.push_back(integer("dem.field_every", "500", 1, 1e9,
                      "steps between field snapshots (after the steady state)"));
  k.push_back(choice("dem.preparation", "\"radius_growth\"", {"radius_growth", "wall_compression"},
                     "how a bed above Phi 0.4 is made (docs/dem-model.md): radius_growth, the "
                     "grains inserted small and grown in place (fast); wall_compression, Kumar "
                     "2019's: inserted at full size in a taller box whose top wall then closes "
                     "at dem.compression_speed (needs a top wall, no side walls, y not periodic)"));
  k.push_back(real("dem.compression_speed", false, "0.2", 0, 1e3, true, false, "m/s",
                   "with dem.preparation = \"wall_compression\": the speed of the closing top "
                   "wall"));
  k.push_back(boolean("dem.compression_drag", "true",
                      "with dem.preparation = \"wall_compression\": the walls close under the "
                      "relaxation's background drag (1/(2000 dt)); false: contact damping only, "
                      "which leaves a more uniform bed (docs/results-kumar2019.md section 7)"));
  k.push_back(real("dem.relax_ke", false, "1e-9", 0, 1e3, true, false, "J",
                   "packing is relaxed until the mean kinetic energy per grain is below this"));
  {
    KeySpec s = choice("dem.packing_cache", "\"auto\"", {}, "folder where prepared beds are "
                       "saved and reused; \"auto\" = $XDG_CACHE_HOME/grainlift (or "
                       "~/.cache/grainlift), \"\" = never cache");
    k.push_back(s);
  }
}

/// [continuum]
void add_continuum_keys(std::vector<KeySpec>& k) {
  k.push_back(real("continuum.ambient_pressure", false, "0.0", 0, 1e9, false, false, "Pa",
                   "continuum only: confining pressure at the intruder centre on top of the "
                   "lithostatic part, for a scene without a lid (with domain.lid_pressure the "
                   "lid is P0 of both solvers and this key is refused); the DEM bed does not "
                   "have this pressure, and the FEM run warns so"));
  k.push_back(real("continuum.mu_s", false, "0.38", 0, 5, false, false, "-",
                   "static friction coefficient of mu(I) (default: Jop et al. 2006, glass "
                   "beads)"));
  k.push_back(real("continuum.mu_2", false, "0.64", 0, 5, false, false, "-",
                   "limiting friction coefficient of mu(I) (>= mu_s)"));
  k.push_back(
      real("continuum.I0", false, "0.279", 0, 10, true, false, "-", "inertial number scale"));
  k.push_back(choice("continuum.rheology_file", "\"\"", {},
                     "TOML file of a calibrated mu(I) and Phi(I) (docs/schema.md, rheology "
                     "file; a relative path is taken from the case file's folder): its mu_s, "
                     "mu_2 and I0 replace the three keys above, which must then be absent; "
                     "\"\" = use those keys, or, when the case gives none of them, the "
                     "calibration `grainlift calibrate` cached for its grains at its P0"));
  k.push_back(choice("continuum.regularisation", "\"barker_gray\"",
                     {"chauchat_medale", "barker_gray"}, "viscosity regularisation"));
  k.push_back(real("continuum.delta", false, "1e-3", 0, 1e3, true, false, "1/s",
                   "strain-rate regularisation delta"));
  k.push_back(real("continuum.barker_gray_IN", false, "0.0", 0, 1, false, true, "-",
                   "barker_gray only: I_N below which mu(I) takes the well-posed low-I branch of "
                   "Barker & Gray 2017; 0 = 1.5 x the lower end of the range of I where mu(I) is "
                   "well posed (Barker et al. 2015); otherwise inside that range"));
  k.push_back(real("continuum.eta_max", false, "1e4", 0, 1e12, true, false, "Pa s",
                   "viscosity cap"));
  k.push_back(real("continuum.pressure_smoothing", false, "0.0", 0, 1, false, false, "-",
                   "p_eps / P0: with p_eps > 0 the rheology sees (p + sqrt(p^2 + p_eps^2)) / 2 "
                   "instead of max(p, 0) (a Jacobian continuous where the pressure vanishes)"));
  k.push_back(choice("continuum.gravity_treatment", "\"full\"", {"full", "linearised"},
                     "full: nonlinear solve with gravity; linearised: the base state without "
                     "gravity at P0 plus one linear solve for the O(D/h) gravity correction "
                     "(Guillard 2014 appendix B)"));
  k.push_back(choice("continuum.wall", "\"no_slip\"", {"no_slip", "coulomb"},
                     "intruder surface condition"));
  k.push_back(real("continuum.wall_friction", false, "intruder.friction", 0, 10, false, false, "-",
                   "mu_w of the Coulomb wall condition"));
  k.push_back(choice("continuum.wall_law", "\"coulomb\"",
                     {"coulomb", "measured", "measured_slip"},
                     "the Coulomb wall's friction: coulomb = continuum.wall_friction; measured "
                     "= the grains' effective wall friction, the [wall] table's friction of "
                     "continuum.rheology_file (studies/wall_law/), constant over the surface; "
                     "measured_slip = that table's slip law mu_a + (mu_b - mu_a) |s| / (|s| + "
                     "v0) at the local slip s of the wall"));
  k.push_back(choice("continuum.inertia", "\"auto\"", {"auto", "on", "off"},
                     "rho (u.grad)u term: auto skips it when rho V^2 / P0 is negligible"));
  k.push_back(vec2("continuum.box_half_size", false, "from the domain", 0, 1e4, "m",
                   "an FE box of its own, symmetric about the intruder (half width, half "
                   "height; u = -V on its inflow sides, lithostatic traction downstream), "
                   "instead of the DEM's domain: the run says the two boxes differ"));
  k.push_back(real("continuum.bed_top", false, "the domain's", -1e4, 1e4, false, false, "m",
                   "y of the FE box's top edge: where the DEM's bed settled under its lid or "
                   "free surface (dem.h5 /lid/y less a grain radius), if not at the top wall's "
                   "inner edge (or the box's top for a free surface)"));
  k.push_back(choice("continuum.far_field", "\"auto\"", {"auto", "periodic", "open"},
                     "the continuum's ends in x: periodic = the case's x period (the DEM's "
                     "developed state after many crossings); open = inflow of undisturbed bed "
                     "and a traction outflow at the ends of a box continuum.open_length long "
                     "(the DEM's first crossing); auto = periodic when the case is periodic in "
                     "x and dem.travel reaches the intruder's own wake, open otherwise"));
  k.push_back(vec2("continuum.open_length", false, "[8.0, 8.0]", 1, 1e3, "D",
                   "open far field: the FE box's length upstream and downstream of the "
                   "intruder's centre, in intruder diameters"));
}

/// [continuum], the mesh and the solver
void add_continuum_solver_keys(std::vector<KeySpec>& k) {
  k.push_back(integer("continuum.refinement", "4", 0, 7,
                      "mesh level (each quarters the cells): the finest allowed with a target "
                      "error; stated without one, the level solved; unstated with nested = "
                      "false or adaptive_cycles, 2"));
  k.push_back(real("continuum.target_error", false, "0.01", 0, 1, false, true, "-",
                   "> 0: the nested levels (>= 2), then adaptive cycles, stop at the first "
                   "whose estimated relative force error is at most this; 0: all. Unstated: "
                   "0.01, or 0 with a stated refinement, adaptive cycles or nested = false"));
  k.push_back(integer("continuum.adaptive_cycles", "0", 0, 5,
                      "refinement cycles after the (nested) levels: each refines the 30% of "
                      "the cells of largest Kelly indicator of the velocity (level jumps of at "
                      "most one; the same mesh on 1 and N MPI ranks); a target_error stops them"));
  k.push_back(integer("continuum.wall_layers", "0", 0, 6,
                      "rings of cells round the intruder, each twice as thick as the one "
                      "inside it, in the inner half of the room between the intruder and the "
                      "square block around it: the cells on the intruder 2 (2^n - 1) times "
                      "thinner radially, where the forces' mesh error is (docs/continuum-"
                      "model.md, \"Wall layers\"); 0: none"));
  k.push_back(boolean("continuum.nested", "true",
                      "nested iteration: the continuation in the regularisation runs on "
                      "refinement 0, each finer level starts from the interpolated coarser "
                      "solution (docs/performance.md); false: the whole continuation on the "
                      "requested mesh"));
  k.push_back(boolean("continuum.mesh_error_estimate", "true",
                      "solve the next coarser level (refinement - 1) first and write its forces "
                      "and their difference to the requested level as the mesh-error estimate "
                      "(/diagnostics *_mesh_error; compare and report combine it with the "
                      "DEM's standard error; with continuum.nested the coarser level is one "
                      "of the nested levels, at no extra cost); not with adaptive_cycles or "
                      "at refinement 0"));
  k.push_back(real("continuum.tolerance", false, "1e-8", 0, 1, true, true, "-",
                   "relative nonlinear residual at which the solve stops"));
  k.push_back(integer("continuum.max_iterations", "50", 1, 1000, "largest number of Newton steps"));
  k.push_back(integer("continuum.picard_iterations", "5", 0, 1000, "Picard warm-up steps"));
  k.push_back(choice("continuum.linear_solver", "\"direct\"", {"direct", "amg"},
                     "direct (MUMPS) or amg (FGMRES, block preconditioner "
                     "with Trilinos AMG on the velocity block and a 1/eta-weighted pressure mass "
                     "matrix)"));
}

/// [continuum], the nonlocal model's keys
void add_nonlocal_keys(std::vector<KeySpec>& k) {
  k.push_back(choice("continuum.model", "\"local\"", {"local", "nonlocal_fluidity"},
                     "local = the mu(I) law; nonlocal_fluidity = Kamrin & Koval's nonlocal "
                     "granular fluidity (eta = p / g, g - xi^2 Laplacian g = g_loc, xi = A d / "
                     "sqrt|mu - mu_s|), solved from the local state by splitting; one MPI rank, "
                     "full gravity"));
  k.push_back(real("continuum.nonlocal_amplitude", false, "0.5", 0, 10, true, true, "-",
                   "A of the cooperativity length (Kamrin & Koval's glass beads: 0.48); "
                   "unstated, the [nonlocal] A of continuum.rheology_file when it has one "
                   "(grainlift calibrate --nonlocal)"));
  k.push_back(integer("continuum.nonlocal_iterations", "60", 1, 1000,
                      "largest number of splitting iterations (fluidity, then flow)"));
  k.push_back(real("continuum.nonlocal_tolerance", false, "2e-3", 0, 1, true, true, "-",
                   "the splitting stops when the force and the torque move by less than this "
                   "(relative) in two iterations running"));
  k.push_back(choice("continuum.dilatancy", "\"auto\"", {"none", "phi_i", "auto"},
                     "phi_i = the packing follows the calibrated Phi(I) of "
                     "continuum.rheology_file (or the calibration cache), floored at its "
                     "calibrated range's end: div(Phi u) = 0 and the weight rho Phi / phi_max g "
                     "(local mu(I), full gravity); none = incompressible at the case's bulk "
                     "density; auto = phi_i where the law is calibrated, the model local and "
                     "gravity full, none elsewhere (the default: the law closest to the grains "
                     "on the most rows of docs/crosscheck.md)"));
  k.push_back(real("continuum.nonlocal_relaxation", false, "1", 0, 1, true, false, "-",
                   "w of the Anderson mixing of log g between splitting iterations (the flow "
                   "step's local part is implicit; 0.2 and 0.5 settled more slowly on the demo)"));
}

/// [output]
void add_output_keys(std::vector<KeySpec>& k) {
  k.push_back(integer("output.angles", "64", 8, 4096, "M, number of angles of the surface grid"));
  k.push_back(real("output.kernel_width_deg", false, "8.0", 0, 90, true, false, "deg",
                   "standard deviation of the Gaussian surface kernel (Guillard eq. A4)"));
  k.push_back(
      integer("output.histogram_bins", "24", 4, 720, "contact histogram bins (24 = pi/12)"));
  k.push_back(
      integer("output.blocks", "20", 2, 10000, "blocks for block-averaged standard errors"));
  k.push_back(boolean("output.fields", "true", "write fields on the grid in the intruder frame"));
  k.push_back(real("output.field_spacing", false, "0.5", 0, 100, true, false, "d",
                   "field grid spacing, in mean grain diameters"));
  k.push_back(vec2("output.field_half_size", false, "[3.0, 3.0]", 0, 1e3, "D",
                   "half extent of the field grid, in intruder diameters"));
  k.push_back(boolean("output.vtu", "true", "continuum: write VTU files for ParaView"));
}

std::vector<KeySpec> make_keys() {
  std::vector<KeySpec> k;
  add_scene_keys(k);
  add_domain_keys(k);
  add_intruder_keys(k);
  add_grains_keys(k);
  add_contact_keys(k);
  add_dem_keys(k);
  add_continuum_keys(k);
  add_continuum_solver_keys(k);
  add_nonlocal_keys(k);
  add_output_keys(k);
  return k;
}

}  // namespace

const std::vector<KeySpec>& case_keys() {
  static const std::vector<KeySpec> keys = make_keys();
  return keys;
}

const KeySpec* find_key(const std::string& path) {
  for (const auto& k : case_keys())
    if (k.path == path) return &k;
  return nullptr;
}

bool is_section(const std::string& path) {
  for (const auto& k : case_keys())
    if (k.path.size() > path.size() && k.path.compare(0, path.size(), path) == 0 &&
        k.path[path.size()] == '.')
      return true;
  return false;
}

std::string type_name(KeyType t) {
  switch (t) {
    case KeyType::real: return "number";
    case KeyType::integer: return "integer";
    case KeyType::boolean: return "boolean";
    case KeyType::text: return "string";
    case KeyType::vec2: return "[x, y] numbers";
    case KeyType::bool2: return "[x, y] booleans";
    case KeyType::text_list: return "list of strings";
  }
  return "?";
}

std::string accepted_range(const KeySpec& k) {
  if (!k.choices.empty()) {
    std::string s = "one of: ";
    for (std::size_t i = 0; i < k.choices.size(); ++i) s += (i ? ", " : "") + k.choices[i];
    return s;
  }
  switch (k.type) {
    case KeyType::real:
    case KeyType::integer:
    case KeyType::vec2: {
      auto num = [&](double v) {
        if (v == inf) return std::string("inf");
        if (v == -inf) return std::string("-inf");
        return k.type == KeyType::integer ? fmt::format("{:.0f}", v) : fmt::format("{:g}", v);
      };
      return fmt::format("{}{}, {}{}", k.min_open ? "(" : "[", num(k.min), num(k.max),
                         k.max_open ? ")" : "]");
    }
    case KeyType::boolean:
    case KeyType::bool2: return "true or false";
    default: return "any";
  }
}

std::string keys_markdown() {
  std::string out =
      "| key | type | unit | default | accepted | meaning |\n|---|---|---|---|---|---|\n";
  for (const auto& k : case_keys()) {
    std::string def = k.required ? "**required**" : "`" + k.default_text + "`";
    std::string desc = k.description;
    if (!k.only_for_law.empty()) desc += " (law `" + k.only_for_law + "` only)";
    out += fmt::format("| `{}` | {} | {} | {} | {} | {} |\n", k.path, type_name(k.type), k.unit,
                       def, accepted_range(k), desc);
  }
  return out;
}

}  // namespace grainlift
