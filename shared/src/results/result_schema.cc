// The schema table of <out>/<solver>.h5 (result_schema.h): one entry per group, attribute and
// dataset, in the order the writer writes them. The descriptions are docs/schema.md's table.
#include "grainlift/shared/results/result_schema.h"

#include <fmt/format.h>

#include <cstdint>
#include <map>
#include <optional>
#include <utility>

#include "grainlift/shared/errors.h"
#include "grainlift/shared/results/result_file.h"

namespace grainlift {
namespace {

// ---- values in and out of a RunResult member -------------------------------------------------
SchemaValue value_of(double v) { return v; }
SchemaValue value_of(int v) { return static_cast<long long>(v); }
SchemaValue value_of(bool v) { return static_cast<long long>(v ? 1 : 0); }
SchemaValue value_of(long v) { return static_cast<long long>(v); }
SchemaValue value_of(long long v) { return v; }
SchemaValue value_of(const std::string& v) { return v; }
SchemaValue value_of(const std::vector<double>& v) { return v; }
template <class T>
SchemaValue value_of(const std::optional<T>& v) {
  return v ? value_of(*v) : SchemaValue{};
}

void store(double& out, SchemaValue&& v) { out = std::get<double>(v); }
void store(int& out, SchemaValue&& v) { out = static_cast<int>(std::get<long long>(v)); }
void store(bool& out, SchemaValue&& v) { out = std::get<long long>(v) != 0; }
void store(long& out, SchemaValue&& v) { out = std::get<long long>(v); }
void store(long long& out, SchemaValue&& v) { out = std::get<long long>(v); }
void store(std::string& out, SchemaValue&& v) { out = std::move(std::get<std::string>(v)); }
void store(std::vector<double>& out, SchemaValue&& v) {
  out = std::move(std::get<std::vector<double>>(v));
}
template <class T>
void store(std::optional<T>& out, SchemaValue&& v) {
  T t{};
  store(t, std::move(v));
  out = std::move(t);
}

template <class T> struct type_of;
template <> struct type_of<double> { static constexpr SchemaType value = SchemaType::float64; };
template <> struct type_of<int> { static constexpr SchemaType value = SchemaType::int64; };
template <> struct type_of<bool> { static constexpr SchemaType value = SchemaType::int64; };
template <> struct type_of<long> { static constexpr SchemaType value = SchemaType::int64; };
template <> struct type_of<long long> { static constexpr SchemaType value = SchemaType::int64; };
template <> struct type_of<std::string> { static constexpr SchemaType value = SchemaType::text; };
template <> struct type_of<std::vector<double>> {
  static constexpr SchemaType value = SchemaType::float64_array;
};
template <class T> struct type_of<std::optional<T>> : type_of<T> {};

// ---- where a block of the result is -----------------------------------------------------------
template <class B>
const B* block_of(const RunResult& r, B RunResult::*b) { return &(r.*b); }
template <class B>
const B* block_of(const RunResult& r, std::optional<B> RunResult::*b) {
  return (r.*b) ? &*(r.*b) : nullptr;
}
template <class B>
B& block_for(RunResult& r, B RunResult::*b) { return r.*b; }
template <class B>
B& block_for(RunResult& r, std::optional<B> RunResult::*b) {
  if (!(r.*b)) (r.*b).emplace();
  return *(r.*b);
}

/// How an entry reaches its value, and the value's type.
struct Access {
  SchemaType type;
  std::function<SchemaValue(const ResultView&)> get;
  std::function<void(RunResult&, SchemaValue&&)> set;
};

/// Member @p m of block @p block (RunResult::geometry, or an optional one: RunResult::forces).
template <class BlockPtr, class B, class T>
Access at(BlockPtr block, T B::*m) {
  return {type_of<T>::value,
          [=](const ResultView& v) {
            const B* b = block_of(v.result, block);
            return b ? value_of(b->*m) : SchemaValue{};
          },
          [=](RunResult& r, SchemaValue&& x) { store(block_for(r, block).*m, std::move(x)); }};
}

/// The same, absent from the file when the array is empty (a plain vector, not an optional).
Access nonempty(Access a) {
  auto get = a.get;
  a.get = [get](const ResultView& v) {
    SchemaValue x = get(v);
    const auto* array = std::get_if<std::vector<double>>(&x);
    return array && array->empty() ? SchemaValue{} : x;
  };
  return a;
}

/// A value every file holds, not read back into the result.
Access constant(SchemaValue value) {
  const SchemaType type = std::holds_alternative<std::string>(value) ? SchemaType::text
                                                                     : SchemaType::int64;
  return {type, [value](const ResultView&) { return value; }, nullptr};
}

/// A derived quantity (derived_quantities.h), written, not read back.
template <class T>
Access derived(T DerivedQuantities::*m) {
  return {type_of<T>::value, [=](const ResultView& v) { return value_of(v.derived.*m); },
          nullptr};
}
/// A surface split of /derived: written with the split of sigma_n, whatever its length.
Access split(std::vector<double> DerivedQuantities::*m) {
  return {SchemaType::float64_array,
          [=](const ResultView& v) {
            return v.derived.sigma_n_symmetric.empty() ? SchemaValue{} : value_of(v.derived.*m);
          },
          nullptr};
}

/// A group that every file holds, its block always in the result.
Access always() {
  return {SchemaType::none, [](const ResultView&) { return SchemaValue{1LL}; },
          [](RunResult&, SchemaValue&&) {}};
}
/// A group present when the result's optional @p block is.
template <class B>
Access when(std::optional<B> RunResult::*block) {
  return {SchemaType::none,
          [=](const ResultView& v) {
            return (v.result.*block) ? SchemaValue{1LL} : SchemaValue{};
          },
          [=](RunResult& r, SchemaValue&&) { block_for(r, block); }};
}

// ---- rows ------------------------------------------------------------------------------------
constexpr Presence req = Presence::required, opt = Presence::optional,
                   dflt = Presence::defaulted;
constexpr const char* dem = "dem";
constexpr const char* fem = "fem";
constexpr const char* both = "dem, fem";

SchemaEntry group(const char* name, Presence p, const char* solvers, Access a,
                  const char* description, std::function<void(const RunResult&)> check = {}) {
  return {"", name, SchemaKind::group, SchemaType::none, "", "", p, solvers, description,
          a.get, a.set, {}, {}, check};
}
SchemaEntry attr(const char* group, const char* name, const char* unit, Presence p,
                 const char* solvers, Access a, const char* description) {
  return {group, name, SchemaKind::attribute, a.type, unit, "scalar", p, solvers, description,
          a.get, a.set, {}, {}, {}};
}
SchemaEntry data(const char* group, const char* name, const char* unit, const char* shape,
                 Presence p, const char* solvers, Access a, const char* description) {
  return {group, name, SchemaKind::dataset, a.type, unit, shape, p, solvers, description,
          a.get, a.set, {}, {}, {}};
}
/// Entries of any name: every element of Diagnostics member @p m.
template <class T>
SchemaEntry by_name(SchemaKind kind, std::map<std::string, T> Diagnostics::*m, const char* unit,
                    const char* shape, const char* description) {
  SchemaEntry e{"diagnostics", "*", kind, type_of<T>::value, unit, shape, opt, both,
                description, {}, {}, {}, {}, {}};
  e.get_all = [m](const RunResult& r) {
    std::vector<std::pair<std::string, SchemaValue>> all;
    for (const auto& [name, v] : r.diagnostics.*m) all.emplace_back(name, value_of(v));
    return all;
  };
  e.set_one = [m](RunResult& r, const std::string& name, SchemaValue&& v) {
    store((r.diagnostics.*m)[name], std::move(v));
  };
  return e;
}

/// /bed: one gap edge more than gap bins.
void check_bed(const RunResult& r) {
  const BedStructure& b = *r.bed;
  if (b.gap_edges.size() != b.gap_fraction.size() + 1)
    throw InputError(fmt::format("/bed/gap_edges holds {} values, /bed/gap_fraction {} "
                                 "(accepted: one edge more than bins)", b.gap_edges.size(),
                                 b.gap_fraction.size()));
}

std::vector<SchemaEntry> make_schema();

}  // namespace

const std::vector<SchemaEntry>& result_schema() {
  static const std::vector<SchemaEntry> table = make_schema();
  return table;
}

namespace {

/// The rows of the file's root and the groups every file holds.
void add_header(std::vector<SchemaEntry>& t) {
  const auto M = &RunResult::meta;
  const auto G = &RunResult::geometry;
  using Meta = RunMetadata;
  using Geo = Geometry;
  t.insert(t.end(), {
  attr("", "schema", "", req, both, constant(std::string("grainlift")), "always \"grainlift\""),
  attr("", "schema_version", "", req, both, constant(static_cast<long long>(schema_version)),
       "2 (version 1 files, without /derived and /diagnostics, are still read)"),
  attr("", "solver", "", req, both, {SchemaType::text, at(M, &Meta::solver).get, nullptr},
       "the solver that wrote the file, as /metadata/@solver"),
  group("metadata", req, both, always(), "the run"),
  attr("metadata", "solver", "", dflt, both, at(M, &Meta::solver), "\"dem\" or \"fem\""),
  attr("metadata", "grainlift_version", "", dflt, both, at(M, &Meta::grainlift_version),
       "the version that wrote the file"),
  attr("metadata", "git_revision", "", dflt, both, at(M, &Meta::git_revision), "its git revision"),
  attr("metadata", "threads", "", req, both, at(M, &Meta::threads), "threads of the run"),
  attr("metadata", "wall_seconds", "s", req, both, at(M, &Meta::wall_seconds),
       "wall time of the whole run, set-up included"),
  attr("metadata", "created_utc", "", dflt, both, at(M, &Meta::created_utc), "ISO 8601"),
  attr("metadata", "notes", "", dflt, both, at(M, &Meta::notes),
       "free text for people (convergence, packing cache, warnings); scripts read /diagnostics"),
  attr("metadata", "partial", "", dflt, both, at(M, &Meta::partial),
       "1 when the file holds a run not finished (see below)"),
  group("case", req, both, always(), "the case file the run was made from"),
  data("case", "text", "", "scalar", dflt, both, at(M, &Meta::case_text),
       "the case file verbatim"),
  data("case", "overrides", "", "scalar", dflt, both, at(M, &Meta::case_overrides),
       "the --set arguments, one per line"),
  attr("case", "hash", "", dflt, both, at(M, &Meta::case_hash),
       "16 hex digits, FNV-1a 64 of text + \"\\n--\\n\" + overrides"),
  attr("case", "hash_algorithm", "", req, both,
       constant(std::string("fnv1a64(text + \"\\n--\\n\" + overrides)")), "how hash is made"),
  attr("case", "path", "", dflt, both, at(M, &Meta::case_path), "the case file's path"),
  group("geometry", req, both, always(), "the scene, SI units, lab frame at t = 0"),
  attr("geometry", "intruder_diameter", "m", req, both, at(G, &Geo::intruder_diameter), "D"),
  attr("geometry", "intruder_x", "m", req, both, at(G, &Geo::intruder_x), "intruder centre"),
  attr("geometry", "intruder_y", "m", req, both, at(G, &Geo::intruder_y), "intruder centre"),
  attr("geometry", "grain_diameter", "m", req, both, at(G, &Geo::grain_diameter), "mean"),
  attr("geometry", "domain_xmin", "m", req, both, at(G, &Geo::domain_xmin), "the box"),
  attr("geometry", "domain_xmax", "m", req, both, at(G, &Geo::domain_xmax), "the box"),
  attr("geometry", "domain_ymin", "m", req, both, at(G, &Geo::domain_ymin), "the box"),
  attr("geometry", "domain_ymax", "m", req, both, at(G, &Geo::domain_ymax), "the box"),
  attr("geometry", "velocity_x", "m/s", req, both, at(G, &Geo::velocity_x), "intruder V"),
  attr("geometry", "velocity_y", "m/s", req, both, at(G, &Geo::velocity_y), "intruder V"),
  attr("geometry", "omega", "rad/s", req, both, at(G, &Geo::omega), "counter-clockwise"),
  attr("geometry", "gravity_x", "m/s^2", req, both, at(G, &Geo::gravity_x), "g"),
  attr("geometry", "gravity_y", "m/s^2", req, both, at(G, &Geo::gravity_y), "g"),
  attr("geometry", "bulk_density", "kg/m^3", req, both, at(G, &Geo::bulk_density),
       "rho = Phi rho_s (2D: per unit length)"),
  attr("geometry", "pressure_scale", "Pa", req, both, at(G, &Geo::pressure_scale),
       "the stated P that stresses are normalised by (Pressure scale, below)"),
  attr("geometry", "reference_gravity", "m/s^2", dflt, both,
       at(G, &Geo::reference_gravity),
       "|g| of the pressure scale (the lid's in scene.depth_mode = \"lid_only\", where "
       "gravity_* are 0)"),
  attr("geometry", "equivalent_depth", "m", dflt, both, at(G, &Geo::equivalent_depth),
       "h = P0 / (rho g); 0 without gravity"),
  });
}

/// The series of the DEM's lid and far field and the prepared bed (DEM only).
void add_dem_blocks(std::vector<SchemaEntry>& t) {
  const auto F = &RunResult::forces;
  const auto L = &RunResult::lid;
  const auto FF = &RunResult::far_field;
  const auto B = &RunResult::bed;
  using Bed = BedStructure;
  const char* n = "[n_samples]";
  t.insert(t.end(), {
  group("forces", opt, both, when(F),
        "force on the intruder against time; a steady FE solution is one row at t = 0"),
  data("forces", "time", "s", n, req, both, at(F, &ForceSeries::time), "sample times"),
  data("forces", "fx", "N/m", n, req, both, at(F, &ForceSeries::fx),
       "force of the medium on the intruder, lab frame"),
  data("forces", "fy", "N/m", n, req, both, at(F, &ForceSeries::fy), "as fx"),
  data("forces", "torque", "N", n, req, both, at(F, &ForceSeries::torque),
       "about the intruder centre, counter-clockwise positive"),
  data("forces", "contacts", "1", n, opt, dem, nonempty(at(F, &ForceSeries::contacts)),
       "grains touching the intruder"),
  group("lid", opt, dem, when(L),
        "the pressure-controlled lid (domain.lid_pressure > 0) at each force sample"),
  data("lid", "time", "s", n, req, dem, at(L, &LidSeries::time), "sample times"),
  data("lid", "y", "m", n, req, dem, at(L, &LidSeries::y), "height of the lid disks' centres"),
  data("lid", "pressure", "Pa", n, req, dem, at(L, &LidSeries::pressure),
       "force of the grains on the lid over the box width (2D reading)"),
  attr("lid", "target", "Pa", req, dem, at(L, &LidSeries::target), "domain.lid_pressure"),
  attr("lid", "mean", "Pa", req, dem, at(L, &LidSeries::mean),
       "mean pressure after the steady-state start"),
  attr("lid", "mean_stderr", "Pa", opt, dem, at(L, &LidSeries::mean_stderr),
       "its block-average standard error (lag-1 corrected)"),
  attr("lid", "mass", "kg", req, dem, at(L, &LidSeries::mass), "per unit depth"),
  attr("lid", "damping", "kg/s", req, dem, at(L, &LidSeries::damping), "docs/dem-model.md"),
  group("far_field", opt, dem, when(FF),
        "the bed's own stress away from the intruder at each force sample (with output.fields "
        "or a lid): contact plus kinetic stress over the strip |y - y_intruder| < half_height "
        "outside the disk of radius exclusion, 2 d clear of the walls"),
  data("far_field", "time", "s", n, req, dem, at(FF, &FarFieldSeries::time), "sample times"),
  data("far_field", "pressure", "Pa", n, req, dem, at(FF, &FarFieldSeries::pressure),
       "-(sxx + syy)/2"),
  data("far_field", "stress_xx", "Pa", n, req, dem, at(FF, &FarFieldSeries::stress_xx),
       "tension positive"),
  data("far_field", "stress_xy", "Pa", n, req, dem, at(FF, &FarFieldSeries::stress_xy),
       "as stress_xx"),
  data("far_field", "stress_yy", "Pa", n, req, dem, at(FF, &FarFieldSeries::stress_yy),
       "as stress_xx"),
  attr("far_field", "mean", "Pa", req, dem, at(FF, &FarFieldSeries::mean),
       "mean pressure after the steady-state start"),
  attr("far_field", "mean_stderr", "Pa", opt, dem, at(FF, &FarFieldSeries::mean_stderr),
       "its block-average standard error (lag-1 corrected)"),
  attr("far_field", "exclusion", "m", req, dem, at(FF, &FarFieldSeries::exclusion), "3 D"),
  attr("far_field", "half_height", "m", req, dem, at(FF, &FarFieldSeries::half_height),
       "1.5 D"),
  group("bed", opt, dem, when(B),
        "the prepared bed at rest before the intruder moves (also from `import lammps`)",
        check_bed),
  attr("bed", "contacts_per_grain", "1", req, dem, at(B, &Bed::contacts_per_grain),
       "touching neighbours (grains, wall disks, overlap > 0) per mobile grain"),
  attr("bed", "rattler_fraction", "1", req, dem, at(B, &Bed::rattler_fraction),
       "grains with fewer than 2 contacts"),
  attr("bed", "fabric_xx", "1", req, dem, at(B, &Bed::fabric_xx),
       "contact fabric <n n> over grain-grain contacts (trace 1)"),
  attr("bed", "fabric_xy", "1", req, dem, at(B, &Bed::fabric_xy), "as fabric_xx"),
  attr("bed", "fabric_yy", "1", req, dem, at(B, &Bed::fabric_yy), "as fabric_xx"),
  attr("bed", "mean_gap", "d", req, dem, at(B, &Bed::mean_gap),
       "mean surface gap to the nearest neighbour, in mean diameters"),
  data("bed", "gap_edges", "1", "[n_gap + 1]", req, dem, at(B, &Bed::gap_edges),
       "bin edges of each grain's nearest gap, mean diameters (negative: overlap)"),
  data("bed", "gap_fraction", "1", "[n_gap]", req, dem, at(B, &Bed::gap_fraction),
       "fraction of grains in each bin; beyond the last edge counts in the last bin"),
  data("bed", "band_y", "m", "[n_band]", req, dem, at(B, &Bed::band_y),
       "horizontal bands about one mean diameter high"),
  data("bed", "band_area_fraction", "1", "[n_band]", req, dem, at(B, &Bed::band_area_fraction),
       "grain area (by centre) over the band's area open to grains"),
  data("bed", "ring_r", "m", "[n_ring]", req, dem, at(B, &Bed::ring_r),
       "mid radii of rings one d wide round the intruder's start, to 10 d"),
  data("bed", "ring_area_fraction", "1", "[n_ring]", req, dem, at(B, &Bed::ring_area_fraction),
       "the same in the rings"),
  });
}

/// Means, surface distribution and histogram.
void add_surface_blocks(std::vector<SchemaEntry>& t) {
  const auto M = &RunResult::means;
  const auto S = &RunResult::surface;
  const auto H = &RunResult::histogram;
  using Surf = SurfaceDistribution;
  using Hist = SurfaceHistogram;
  const char* m = "[n_theta]";
  const char* b = "[n_bins]";
  t.insert(t.end(), {
  group("means", opt, both, when(M),
        "means after the steady-state start, standard errors from block averages; with "
        "--replicas N, over the replicas (errors SD / sqrt(N), blocks = N)"),
  attr("means", "drag", "N/m", req, both, at(M, &MeanForces::drag), "D = -F.V/|V|"),
  attr("means", "lift", "N/m", req, both, at(M, &MeanForces::lift), "L = F.(z x V/|V|)"),
  attr("means", "torque", "N", req, both, at(M, &MeanForces::torque), "counter-clockwise positive"),
  attr("means", "drag_stderr", "N/m", opt, dem, at(M, &MeanForces::drag_stderr),
       "block-average standard error, corrected for the blocks' lag-1 correlation"),
  attr("means", "lift_stderr", "N/m", opt, dem, at(M, &MeanForces::lift_stderr), "as drag_stderr"),
  attr("means", "torque_stderr", "N", opt, dem, at(M, &MeanForces::torque_stderr),
       "as drag_stderr"),
  attr("means", "contacts", "1", opt, dem, at(M, &MeanForces::contacts),
       "mean grains touching the intruder"),
  attr("means", "samples", "1", req, both, at(M, &MeanForces::samples), "samples averaged"),
  attr("means", "blocks", "1", req, both, at(M, &MeanForces::blocks),
       "blocks of the standard errors"),
  group("surface", opt, both, when(S),
        "stress on the intruder at theta_m = (m + 1/2) 2 pi / M, the Gaussian kernel average "
        "of Guillard eq. (A4) in both solvers (DEM over its contacts, FE over its traction at "
        "8 M angles)"),
  data("surface", "theta", "rad", m, req, both, at(S, &Surf::theta), "from V, ccw"),
  data("surface", "sigma_n", "Pa", m, req, both, at(S, &Surf::sigma_n), "compressive positive"),
  data("surface", "sigma_t", "Pa", m, req, both, at(S, &Surf::sigma_t),
       "positive when the medium pulls the surface counter-clockwise"),
  attr("surface", "kernel_width_deg", "deg", req, both, at(S, &Surf::kernel_width_deg),
       "the kernel's standard deviation, output.kernel_width_deg"),
  data("surface", "sigma_n_pointwise", "Pa", m, opt, fem, at(S, &Surf::sigma_n_pointwise),
       "the traction at theta_m itself, before the kernel"),
  data("surface", "sigma_t_pointwise", "Pa", m, opt, fem, at(S, &Surf::sigma_t_pointwise),
       "as sigma_n_pointwise"),
  data("surface", "sigma_n_stderr", "Pa", m, opt, dem, at(S, &Surf::sigma_n_stderr),
       "standard error at each angle over the forces' blocks (one bed's time average; "
       "lag-1 corrected)"),
  data("surface", "sigma_t_stderr", "Pa", m, opt, dem, at(S, &Surf::sigma_t_stderr),
       "as sigma_n_stderr"),
  group("histogram", opt, dem, when(H), "intruder contacts in pi/12 bins (Kumar Fig. 6)"),
  data("histogram", "theta_lo", "rad", b, req, dem, at(H, &Hist::theta_lo), "from -pi"),
  data("histogram", "theta_hi", "rad", b, req, dem, at(H, &Hist::theta_hi), "upper bin edges"),
  data("histogram", "contact_count", "1", b, req, dem, at(H, &Hist::contact_count),
       "mean contacts in the bin per sample"),
  data("histogram", "normal_force", "N/m", b, req, dem, at(H, &Hist::normal_force),
       "mean summed F_N per sample"),
  data("histogram", "tangential_force", "N/m", b, req, dem, at(H, &Hist::tangential_force),
       "mean summed F_T per sample"),
  data("histogram", "slip_fraction", "1", b, req, dem, at(H, &Hist::slip_fraction),
       "fraction of the bin's contacts with |F_T| = mu |F_N|"),
  data("histogram", "slip_velocity", "m/s", b, opt, dem, at(H, &Hist::slip_velocity),
       "mean slip velocity of the bin's contacts: the intruder's surface against the grain's "
       "contact point, counter-clockwise positive (omega R - V sin theta for grains at rest)"),
  });
}

/// Derived quantities, diagnostics and the field grid.
void add_derived_and_fields(std::vector<SchemaEntry>& t) {
  const auto F = &RunResult::fields;
  using Q = DerivedQuantities;
  using Grid = FieldGrid;
  using D = Diagnostics;
  const char* m = "[n_theta]";
  const char* cell = "[ny, nx]";
  const SchemaKind a = SchemaKind::attribute, d = SchemaKind::dataset;
  t.insert(t.end(), {
  group("derived", req, both, {SchemaType::none, always().get, nullptr},
        "from /geometry, /means and /surface (docs/conventions.md), for scripts; not read"),
  attr("derived", "spin_ratio", "1", req, both, derived(&Q::spin_ratio), "omega R / |V|"),
  attr("derived", "lift_over_drag", "1", opt, both, derived(&Q::lift_over_drag), "drag != 0"),
  attr("derived", "buoyancy", "N/m", opt, both, derived(&Q::buoyancy),
       "B = rho g pi D^2 / 4, g = reference_gravity"),
  attr("derived", "lift_over_buoyancy", "1", opt, both, derived(&Q::lift_over_buoyancy), "L / B"),
  attr("derived", "drag_coefficient", "1", opt, both, derived(&Q::drag_coefficient),
       "drag / (rho g h D), h = equivalent_depth (Guillard 2014)"),
  data("derived", "sigma_n_symmetric", "Pa", m, opt, both, split(&Q::sigma_n_symmetric),
       "(s(theta) + s(-theta))/2 of /surface"),
  data("derived", "sigma_n_antisymmetric", "Pa", m, opt, both,
       split(&Q::sigma_n_antisymmetric), "(s(theta) - s(-theta))/2"),
  data("derived", "sigma_t_symmetric", "Pa", m, opt, both, split(&Q::sigma_t_symmetric),
       "as for sigma_n"),
  data("derived", "sigma_t_antisymmetric", "Pa", m, opt, both,
       split(&Q::sigma_t_antisymmetric), "as for sigma_n"),
  group("diagnostics", opt, both,
        {SchemaType::none,
         [](const ResultView& v) {
           return v.result.diagnostics.empty() ? SchemaValue{} : SchemaValue{1LL};
         },
         [](RunResult&, SchemaValue&&) {}},
        "how the run went, by name (Diagnostics, below); absent in version 1 files"),
  by_name(a, &D::counts, "", "scalar", "int64 attributes"),
  by_name(a, &D::values, "", "scalar", "float64 attributes"),
  by_name(a, &D::texts, "", "scalar", "string attributes"),
  by_name(d, &D::series, "1", "[n]", "float64 series"),
  group("fields", opt, both, when(F),
        "fields on a regular grid in the intruder frame, each present or absent on its own"),
  data("fields", "x", "m", "[nx]", req, both, at(F, &Grid::x),
       "cell centres relative to the intruder centre"),
  data("fields", "y", "m", "[ny]", req, both, at(F, &Grid::y), "as x"),
  data("fields", "velocity_x", "m/s", cell, opt, both, at(F, &Grid::velocity_x),
       "relative to the intruder"),
  data("fields", "velocity_y", "m/s", cell, opt, both, at(F, &Grid::velocity_y), "as velocity_x"),
  data("fields", "pressure", "Pa", cell, opt, both, at(F, &Grid::pressure), "-(sxx + syy)/2"),
  data("fields", "stress_xx", "Pa", cell, opt, both, at(F, &Grid::stress_xx),
       "tension positive (DEM: contact stress)"),
  data("fields", "stress_xy", "Pa", cell, opt, both, at(F, &Grid::stress_xy), "as stress_xx"),
  data("fields", "stress_yy", "Pa", cell, opt, both, at(F, &Grid::stress_yy), "as stress_xx"),
  data("fields", "area_fraction", "1", cell, opt, dem, at(F, &Grid::area_fraction),
       "Kumar eq. (A6)"),
  data("fields", "granular_temperature", "m^2/s^2", cell, opt, dem,
       at(F, &Grid::granular_temperature), "Kumar eq. (A7)"),
  });
}

std::vector<SchemaEntry> make_schema() {
  std::vector<SchemaEntry> t;
  add_header(t);
  add_dem_blocks(t);
  add_surface_blocks(t);
  add_derived_and_fields(t);
  return t;
}

}  // namespace

}  // namespace grainlift
