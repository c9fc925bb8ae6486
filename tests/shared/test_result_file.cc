// The output schema: a full result written and read back is identical; blocks a solver did
// not produce stay absent; a writer killed mid-write never leaves a partial file under the
// final name.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "grainlift/shared/errors.h"
#include "grainlift/shared/results/result_file.h"
#include "sample_result.h"

using namespace grainlift;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("grainlift_test_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d / name;
}

RunResult full_result(std::size_t n_samples = 100) {
  RunResult r = grainlift::test_support::sample_result_head();
  ForceSeries f;
  for (std::size_t i = 0; i < n_samples; ++i) {
    f.time.push_back(i * 1e-4);
    f.fx.push_back(-1.0 - std::sin(double(i)));
    f.fy.push_back(0.1 * std::cos(double(i)));
    f.torque.push_back(0.01 * double(i));
    f.contacts.push_back(double(i % 7));
  }
  r.forces = f;
  MeanForces m;
  m.drag = 1.5;
  m.lift = -0.25;
  m.torque = 0.01;
  m.drag_stderr = 0.05;
  m.lift_stderr = 0.02;
  m.contacts = 6.5;
  m.samples = 90;
  m.blocks = 10;
  r.means = m;
  LidSeries lid;
  for (int k = 0; k < 5; ++k) {
    lid.time.push_back(0.01 * k);
    lid.y.push_back(0.06 - 1e-5 * k);
    lid.pressure.push_back(1.2 + 0.01 * k);
  }
  lid.target = 1.2066;
  lid.mean = 1.21;
  lid.mean_stderr = 0.003;
  lid.mass = 0.04;
  lid.damping = 1.5;
  r.lid = lid;
  SurfaceDistribution s;
  for (int k = 0; k < 8; ++k) {
    s.theta.push_back(k * 0.7);
    s.sigma_n.push_back(100 + k);
    s.sigma_t.push_back(-3.0 * k);
  }
  s.kernel_width_deg = 8;
  r.surface = s;
  SurfaceHistogram h;
  for (int k = 0; k < 4; ++k) {
    h.theta_lo.push_back(k);
    h.theta_hi.push_back(k + 1);
    h.contact_count.push_back(0.5 * k);
    h.normal_force.push_back(2.0 * k);
    h.tangential_force.push_back(-1.0 * k);
    h.slip_fraction.push_back(0.25 * k);
  }
  h.slip_velocity = std::vector<double>{0.1, -0.2, 0.0, 0.3};
  r.histogram = h;
  FieldGrid g;
  g.x = {-0.1, 0.0, 0.1};
  g.y = {-0.05, 0.05};
  g.velocity_x = std::vector<double>{1, 2, 3, 4, 5, 6};
  g.velocity_y = std::vector<double>{0, 0, 0, 0, 0, NAN};
  g.area_fraction = std::vector<double>{0.8, 0.8, 0.7, 0.6, 0.5, 0.4};
  r.fields = g;  // no stress, no pressure, no temperature: must stay absent
  r.bed = grainlift::test_support::sample_bed();
  return r;
}

void expect_equal(const RunResult& a, const RunResult& b) {
  EXPECT_EQ(a.meta.solver, b.meta.solver);
  EXPECT_EQ(a.meta.git_revision, b.meta.git_revision);
  EXPECT_EQ(a.meta.threads, b.meta.threads);
  EXPECT_EQ(a.meta.wall_seconds, b.meta.wall_seconds);
  EXPECT_EQ(a.meta.case_text, b.meta.case_text);
  EXPECT_EQ(a.meta.case_overrides, b.meta.case_overrides);
  EXPECT_EQ(a.meta.case_hash, b.meta.case_hash);
  EXPECT_EQ(a.meta.notes, b.meta.notes);
  EXPECT_EQ(a.geometry.pressure_scale, b.geometry.pressure_scale);
  EXPECT_EQ(a.geometry.omega, b.geometry.omega);
  ASSERT_EQ(a.forces.has_value(), b.forces.has_value());
  if (a.forces) {
    EXPECT_EQ(a.forces->fx, b.forces->fx);
    EXPECT_EQ(a.forces->contacts, b.forces->contacts);
  }
  ASSERT_EQ(a.means.has_value(), b.means.has_value());
  if (a.means) {
    EXPECT_EQ(a.means->drag, b.means->drag);
    EXPECT_EQ(a.means->lift_stderr, b.means->lift_stderr);
    EXPECT_EQ(a.means->torque_stderr, b.means->torque_stderr);
    EXPECT_EQ(a.means->samples, b.means->samples);
  }
  ASSERT_EQ(a.surface.has_value(), b.surface.has_value());
  if (a.surface) {
    EXPECT_EQ(a.surface->sigma_t, b.surface->sigma_t);
    EXPECT_EQ(a.surface->kernel_width_deg, b.surface->kernel_width_deg);
    EXPECT_EQ(a.surface->sigma_n_pointwise, b.surface->sigma_n_pointwise);
    EXPECT_EQ(a.surface->sigma_t_pointwise, b.surface->sigma_t_pointwise);
  }
  ASSERT_EQ(a.bed.has_value(), b.bed.has_value());
  if (a.bed) {
    EXPECT_EQ(a.bed->contacts_per_grain, b.bed->contacts_per_grain);
    EXPECT_EQ(a.bed->rattler_fraction, b.bed->rattler_fraction);
    EXPECT_EQ(a.bed->fabric_xy, b.bed->fabric_xy);
    EXPECT_EQ(a.bed->mean_gap, b.bed->mean_gap);
    EXPECT_EQ(a.bed->gap_edges, b.bed->gap_edges);
    EXPECT_EQ(a.bed->gap_fraction, b.bed->gap_fraction);
    EXPECT_EQ(a.bed->band_area_fraction, b.bed->band_area_fraction);
    EXPECT_EQ(a.bed->ring_r, b.bed->ring_r);
  }
  ASSERT_EQ(a.histogram.has_value(), b.histogram.has_value());
  if (a.histogram) {
    EXPECT_EQ(a.histogram->slip_fraction, b.histogram->slip_fraction);
    EXPECT_EQ(a.histogram->slip_velocity, b.histogram->slip_velocity);
  }
  ASSERT_EQ(a.fields.has_value(), b.fields.has_value());
  ASSERT_EQ(a.lid.has_value(), b.lid.has_value());
  if (a.lid) {
    EXPECT_EQ(a.lid->time, b.lid->time);
    EXPECT_EQ(a.lid->y, b.lid->y);
    EXPECT_EQ(a.lid->pressure, b.lid->pressure);
    EXPECT_EQ(a.lid->target, b.lid->target);
    EXPECT_EQ(a.lid->mean, b.lid->mean);
    EXPECT_EQ(a.lid->mean_stderr, b.lid->mean_stderr);
    EXPECT_EQ(a.lid->mass, b.lid->mass);
    EXPECT_EQ(a.lid->damping, b.lid->damping);
  }
}

}  // namespace

TEST(ResultFile, RoundTripIsExact) {
  const auto path = scratch("roundtrip.h5").string();
  const RunResult r = full_result();
  write_result(path, r);
  const RunResult back = read_result(path);
  expect_equal(r, back);
  // Field grid: present fields identical (NaN stays NaN), absent ones stay absent.
  ASSERT_TRUE(back.fields);
  EXPECT_EQ(back.fields->x, r.fields->x);
  EXPECT_EQ(*back.fields->velocity_x, *r.fields->velocity_x);
  EXPECT_TRUE(std::isnan((*back.fields->velocity_y)[5]));
  EXPECT_FALSE(back.fields->stress_xx.has_value());
  EXPECT_FALSE(back.fields->pressure.has_value());
  EXPECT_FALSE(back.fields->granular_temperature.has_value());
  EXPECT_FALSE(back.means->torque_stderr.has_value());
  // A DEM surface has no pointwise trace: the datasets are absent, not zeros.
  EXPECT_FALSE(back.surface->sigma_n_pointwise.has_value());
}

TEST(ResultFile, AbsentBlocksAreNotWritten) {
  // A steady FE solution: one force row, no contacts, no histogram, no fields.
  RunResult r = full_result(1);
  r.meta.solver = "fem";
  r.forces->contacts.clear();
  r.means->drag_stderr.reset();
  r.means->lift_stderr.reset();
  r.means->contacts.reset();
  r.histogram.reset();
  r.fields.reset();
  r.lid.reset();
  // the FE surface: the kernel average and, beside it, the pointwise trace
  r.surface->sigma_n_pointwise = std::vector<double>(8, 250.5);
  r.surface->sigma_t_pointwise = std::vector<double>(8, -1.25);
  const auto path = scratch("fem.h5").string();
  write_result(path, r);
  const RunResult back = read_result(path);
  expect_equal(r, back);
  EXPECT_TRUE(back.forces->contacts.empty());
  EXPECT_FALSE(back.means->drag_stderr.has_value());
  EXPECT_FALSE(back.histogram.has_value());
  EXPECT_FALSE(back.fields.has_value());
  EXPECT_FALSE(back.lid.has_value());
  ASSERT_TRUE(back.surface->sigma_n_pointwise && back.surface->sigma_t_pointwise);
}

TEST(ResultFile, NonGrainliftFilesAreInputErrors) {
  const auto path = scratch("garbage.h5").string();
  std::ofstream(path) << "not hdf5";
  EXPECT_THROW(read_result(path), InputError);
  EXPECT_THROW(read_result(scratch("missing.h5").string()), InputError);
}

TEST(ResultFile, XdmfSidecarNamesEveryPresentField) {
  const auto dir = scratch("xdmf");
  fs::create_directories(dir);
  const RunResult r = full_result();
  write_result((dir / "dem.h5").string(), r);
  write_fields_xdmf((dir / "dem_fields.xmf").string(), "dem.h5", r);
  std::ifstream in(dir / "dem_fields.xmf");
  const std::string x((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(x.find("dem.h5:/fields/velocity_x"), std::string::npos);
  EXPECT_NE(x.find("dem.h5:/fields/area_fraction"), std::string::npos);
  EXPECT_EQ(x.find("stress_xx"), std::string::npos);
  EXPECT_NE(x.find("Dimensions=\"3 4\""), std::string::npos);  // nodes: (ny+1) x (nx+1)
}

TEST(ResultFile, KilledWriterNeverLeavesAPartialFileUnderTheFinalName) {
  // A child rewrites a large file in a loop; the parent kills it at varied moments. Under the
  // final name there must always be either the previous complete file or a new complete one.
  const auto path = scratch("atomic.h5").string();
  const RunResult big = full_result(400000);  // ~16 MB of force series
  write_result(path, big);                     // a complete old file
  for (int attempt = 0; attempt < 6; ++attempt) {
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      for (;;) write_result(path, big);  // killed from outside
    }
    ::usleep(20000 + 37000 * attempt);
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status));
    const RunResult back = read_result(path);  // throws if partial
    ASSERT_TRUE(back.forces);
    EXPECT_EQ(back.forces->fx.size(), big.forces->fx.size());
    EXPECT_EQ(back.forces->fx.back(), big.forces->fx.back());
  }
}
