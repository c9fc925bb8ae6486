// The schema table drives the result file: every entry of a result that has all of them is in
// the file and reads back exactly (tolerance 0: the same bits); a file without a required
// entry is refused with the reader's message naming the file and the entry; docs/schema.md
// holds the table that `grainlift schema --markdown` prints.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "grainlift/shared/errors.h"
#include "grainlift/shared/results/result_file.h"
#include "grainlift/shared/results/result_schema.h"
#include "sample_result.h"

using namespace grainlift;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("grainlift_schema_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d / name;
}

std::vector<double> ramp(std::size_t n, double start, double step) {
  std::vector<double> v;
  for (std::size_t i = 0; i < n; ++i) v.push_back(start + step * double(i));
  return v;
}

/// A result with every optional entry of the schema present (values made up, all distinct).
RunResult complete_result() {
  RunResult r = test_support::sample_result_head();
  r.meta.partial = true;
  r.geometry.intruder_y = 0.25;
  r.geometry.gravity_y = -9.81;
  r.geometry.reference_gravity = 9.81;
  r.geometry.equivalent_depth = 0.4;
  const std::size_t n = 6, m = 8, bins = 4;
  r.forces = ForceSeries{ramp(n, 0, 1e-3), ramp(n, -1, 0.1), ramp(n, 0.2, 0.01),
                         ramp(n, 0.01, 0.001), ramp(n, 3, 1)};
  r.means = MeanForces{1.5, -0.25, 0.01, 0.05, 0.02, 0.003, 6.5, 90, 10};
  r.lid = LidSeries{ramp(n, 0, 1e-3), ramp(n, 0.06, -1e-5), ramp(n, 1.2, 0.01),
                    1.2066, 1.21, 0.003, 0.04, 1.5};
  r.far_field = FarFieldSeries{ramp(n, 0, 1e-3), ramp(n, 1.1, 0.01), ramp(n, -1, 0.01),
                               ramp(n, 0.01, 0.001), ramp(n, -1.2, 0.01), 1.15, 0.002, 0.3,
                               0.15};
  r.bed = test_support::sample_bed();
  SurfaceDistribution s;
  s.theta = ramp(m, 0.39, 0.785);
  s.sigma_n = ramp(m, 100, 1);
  s.sigma_t = ramp(m, 0, -3);
  s.kernel_width_deg = 8;
  s.sigma_n_pointwise = ramp(m, 101, 1);
  s.sigma_t_pointwise = ramp(m, 1, -3);
  s.sigma_n_stderr = ramp(m, 0.5, 0.1);
  s.sigma_t_stderr = ramp(m, 0.25, 0.1);
  r.surface = s;
  r.histogram = SurfaceHistogram{ramp(bins, -3.14, 0.5), ramp(bins, -2.64, 0.5),
                                 ramp(bins, 0.5, 0.5), ramp(bins, 2, 2), ramp(bins, -1, -1),
                                 ramp(bins, 0, 0.25), ramp(bins, -0.5, 0.1)};
  FieldGrid g;
  g.x = {-0.1, 0.0, 0.1};
  g.y = {-0.05, 0.05};
  std::optional<std::vector<double>>* fields[] = {
      &g.velocity_x, &g.velocity_y, &g.pressure, &g.stress_xx,
      &g.stress_xy,  &g.stress_yy,  &g.area_fraction, &g.granular_temperature};
  for (std::size_t k = 0; k < std::size(fields); ++k) *fields[k] = ramp(6, double(k), 0.5);
  r.fields = g;
  r.diagnostics.counts = {{"steps", 1200}, {"list_builds", 31}};
  r.diagnostics.values = {{"area_fraction", 0.81}, {"collision_time", 2.5e-4}};
  r.diagnostics.texts = {{"pressure_scale_source", "lithostatic"}, {"law", "barker_gray"}};
  r.diagnostics.series = {{"replica_drag", {1.4, 1.6}}, {"residual_history", {1, 1e-3}}};
  return r;
}

/// Whether the file at @p path holds entry @p e under @p name.
bool file_holds(hid_t file, const SchemaEntry& e, const std::string& name) {
  const std::string parent = e.group[0] ? std::string("/") + e.group : std::string("/");
  if (e.kind == SchemaKind::group) return H5Lexists(file, e.name, H5P_DEFAULT) > 0;
  if (e.kind == SchemaKind::dataset)
    return H5Lexists(file, (parent + "/" + name).c_str(), H5P_DEFAULT) > 0;
  return H5Aexists_by_name(file, parent.c_str(), name.c_str(), H5P_DEFAULT) > 0;
}

std::string message_of(const std::string& path) {
  try {
    read_result(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(read without error)";
}

}  // namespace

TEST(ResultSchema, EveryEntryIsWrittenAndReadBackExactly) {
  const RunResult r = complete_result();
  const auto path = scratch("complete.h5").string();
  write_result(path, r);
  const RunResult back = read_result(path);
  const DerivedQuantities dr = derive(r), db = derive(back);
  const ResultView written{r, dr}, read{back, db};
  hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  for (const SchemaEntry& e : result_schema()) {
    if (e.by_name()) {
      const auto all = e.get_all(r);
      EXPECT_FALSE(all.empty()) << e.path() << ": the sample lacks it";
      for (const auto& [name, v] : all) EXPECT_TRUE(file_holds(file, e, name)) << name;
      EXPECT_TRUE(all == e.get_all(back)) << e.path();
      continue;
    }
    const SchemaValue v = e.get(written);
    EXPECT_FALSE(std::holds_alternative<std::monostate>(v)) << e.path() << ": sample lacks it";
    EXPECT_TRUE(file_holds(file, e, e.name)) << e.path() << " is not in the file";
    // exact: the same value after the round trip (derived ones recomputed from what was read)
    EXPECT_TRUE(v == e.get(read)) << e.path();
  }
  H5Fclose(file);
}

TEST(ResultSchema, AFileWithoutARequiredEntryIsRefusedNamingIt) {
  const RunResult r = complete_result();
  int checked = 0;
  for (const SchemaEntry& e : result_schema()) {
    if (!e.set || e.presence != Presence::required || e.by_name()) continue;
    const bool top = e.kind == SchemaKind::group;
    if (!top && !e.group[0]) continue;
    const auto path = scratch("without.h5").string();
    write_result(path, r);
    hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    const std::string parent = std::string("/") + (top ? "" : e.group);
    if (e.kind == SchemaKind::attribute)
      ASSERT_GE(H5Adelete_by_name(file, parent.c_str(), e.name, H5P_DEFAULT), 0);
    else
      ASSERT_GE(H5Ldelete(file, e.path().c_str(), H5P_DEFAULT), 0);
    H5Fclose(file);
    const std::string expected =
        e.kind == SchemaKind::group       ? fmt::format("missing group /{}", e.name)
        : e.kind == SchemaKind::attribute ? fmt::format("missing attribute {} of {}", e.name,
                                                        parent)
                                          : fmt::format("missing dataset {} in {}", e.name,
                                                        parent);
    EXPECT_EQ(message_of(path), path + ": " + expected) << e.path();
    ++checked;
  }
  EXPECT_GE(checked, 60);  // every required number and series of the table
}

TEST(ResultSchema, SeriesOfAGroupMustAgreeInLength) {
  RunResult r = complete_result();
  r.forces->fy.pop_back();
  const auto path = scratch("short.h5").string();
  write_result(path, r);
  EXPECT_EQ(message_of(path), path + ": /forces/fy has 5 values, /forces/time 6 (accepted: the "
                                     "same number)");
  r = complete_result();
  r.bed->gap_edges.pop_back();
  write_result(path, r);
  EXPECT_EQ(message_of(path), path + ": /bed/gap_edges holds 3 values, /bed/gap_fraction 3 "
                                     "(accepted: one edge more than bins)");
}

TEST(ResultSchema, EntriesAreUniqueAndInTheirGroups) {
  std::set<std::string> paths, groups{""};
  for (const SchemaEntry& e : result_schema()) {
    EXPECT_TRUE(paths.insert(e.path() + (e.by_name() ? std::to_string(int(e.type)) : ""))
                    .second)
        << "twice: " << e.path();
    EXPECT_TRUE(groups.count(e.group)) << e.path() << ": its group row is not before it";
    if (e.kind == SchemaKind::group) groups.insert(e.name);
    EXPECT_TRUE(e.get || e.get_all) << e.path();
    if (e.kind == SchemaKind::dataset && e.type == SchemaType::float64_array) {
      EXPECT_STRNE(e.unit, "") << e.path() << ": a numeric dataset carries its units";
    }
  }
}

TEST(ResultSchema, DocsHoldTheGeneratedTable) {
  std::ifstream in(GRAINLIFT_SOURCE_DIR "/docs/schema.md");
  ASSERT_TRUE(in) << "docs/schema.md missing";
  const std::string doc((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string begin = "<!-- schema:begin -->\n", end = "<!-- schema:end -->";
  const std::size_t i = doc.find(begin), j = doc.find(end);
  ASSERT_NE(i, std::string::npos) << "docs/schema.md has no " << begin;
  ASSERT_NE(j, std::string::npos) << "docs/schema.md has no " << end;
  EXPECT_EQ(doc.substr(i + begin.size(), j - i - begin.size()), schema_markdown())
      << "regenerate it with `make docs-schema`";
}
