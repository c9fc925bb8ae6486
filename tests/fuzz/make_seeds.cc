// Writes the binary seeds of tests/fuzz/corpus/ (run by hand when a format changes; see
// tests/fuzz/README.md): checkpoints made by encode_checkpoint and result files made by
// write_result, each in the input format of its fuzz target, plus the result files as they
// are for the raw-bytes target.
//   make_fuzz_seeds tests/fuzz/corpus
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "grainlift/dem/system/checkpoint.h"
#include "grainlift/shared/results/result_file.h"
#include "result_ops.h"
#include "sample_result.h"

namespace fs = std::filesystem;
using namespace grainlift;

namespace {

void write(const fs::path& path, const std::vector<unsigned char>& bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  std::printf("%s (%zu bytes)\n", path.c_str(), bytes.size());
}

// ---- checkpoints

dem::RunCheckpoint small_checkpoint(bool lid, bool fields) {
  dem::RunCheckpoint c;
  c.case_tag = "0123456789abcdef";
  c.step = 40;
  c.planned_steps = 100;
  auto& s = c.system;
  for (int i = 0; i < 3; ++i) {
    s.grains.push_back({0.01 * i, 0.02, 0.005, 1e-3, 0.1, -0.1, 2.0});
    s.ax.push_back(0.5 * i);
    s.ay.push_back(-9.81);
    s.alpha.push_back(0.0);
  }
  s.frozen.push_back({0.0, 0.0, 0.005, 0.0, 0.0, 0.0, 0.0});
  s.time = 4e-4;
  s.steps = 40;
  s.intruder.present = true;
  s.intruder.r = 0.02;
  s.intruder.vx = 0.5;
  s.pair_i = {0, 1};
  s.pair_j = {1, 3};
  s.pair_sx = {1e-6, -2e-6};
  s.pair_sy = {0.0, 3e-7};
  s.ic_grain = {2};
  s.ic_sx = {4e-7};
  s.ic_sy = {-1e-7};
  s.has_lid = lid;
  if (lid) {
    s.lid.y = 0.1;
    s.lid.pressure = 1000;
    s.lid_disk_y = {0.1, 0.1};
    s.lid_disk_velocity = {0.0, 0.0};
  }
  s.builds = 3;
  for (int k = 0; k < 4; ++k) c.out.samples.push_back({1e-4 * k, -1.0, 0.1, 0.01, 2});
  c.out.contacts.push_back({2, 0.3, 1.5, 0.2, false});
  c.out.contacts.push_back({3, -2.0, 0.7, -0.7, true});
  c.out.steady_start_index = 2;
  c.out.grains = 3;
  c.out.wall_grains = 1;
  if (lid) c.out.lid.push_back({1e-4, 0.1, 990});
  c.out.far_field.push_back({1e-4, 800, -790, 3, -810, 1e-3});
  if (fields) {
    c.fields.snapshots = 2;
    for (auto* v : {&c.fields.gamma, &c.fields.gvx, &c.fields.gvy, &c.fields.gv2, &c.fields.sxx,
                    &c.fields.sxy, &c.fields.syy})
      *v = {0.1, 0.2, 0.3, 0.4};
  }
  return c;
}

/// @p bytes (a whole checkpoint) as inputs of fuzz_checkpoint in each of its three modes.
void checkpoint_seeds(const fs::path& dir, const std::string& name,
                      const std::vector<unsigned char>& bytes) {
  std::vector<unsigned char> whole{0};
  whole.insert(whole.end(), bytes.begin(), bytes.end());
  write(dir / (name + "-raw.bin"), whole);
  std::vector<unsigned char> framed{1};
  framed.insert(framed.end(), bytes.begin() + 8, bytes.end() - 8);
  write(dir / (name + "-framed.bin"), framed);
  std::vector<unsigned char> payload{2};
  payload.insert(payload.end(), bytes.begin() + 12, bytes.end() - 8);
  write(dir / (name + "-payload.bin"), payload);
}

// ---- result files

RunResult dem_result() {
  RunResult r = grainlift::test_support::sample_result_head();
  r.geometry.gravity_y = -9.81;
  r.geometry.reference_gravity = 9.81;
  r.geometry.equivalent_depth = 0.4;
  ForceSeries f;
  for (int i = 0; i < 6; ++i) {
    f.time.push_back(i * 1e-4);
    f.fx.push_back(-1.0 - std::sin(double(i)));
    f.fy.push_back(0.1 * std::cos(double(i)));
    f.torque.push_back(0.01 * i);
    f.contacts.push_back(double(i % 3));
  }
  r.forces = f;
  MeanForces m;
  m.drag = 1.5;
  m.lift = -0.25;
  m.torque = 0.01;
  m.drag_stderr = 0.05;
  m.lift_stderr = 0.02;
  m.torque_stderr = 0.001;
  m.contacts = 6.5;
  m.samples = 4;
  m.blocks = 2;
  r.means = m;
  r.bed = grainlift::test_support::sample_bed();
  LidSeries lid;
  lid.time = {0, 1e-4};
  lid.y = {0.06, 0.0599};
  lid.pressure = {1.2, 1.21};
  lid.target = 1.2;
  lid.mean = 1.21;
  lid.mean_stderr = 0.003;
  lid.mass = 0.04;
  lid.damping = 1.5;
  r.lid = lid;
  FarFieldSeries ff;
  ff.time = {0, 1e-4};
  ff.pressure = {800, 810};
  ff.stress_xx = {-790, -800};
  ff.stress_xy = {3, 4};
  ff.stress_yy = {-810, -820};
  ff.mean = 805;
  ff.mean_stderr = 5;
  ff.exclusion = 0.3;
  ff.half_height = 0.15;
  r.far_field = ff;
  SurfaceDistribution s;
  const int M = 8;
  for (int k = 0; k < M; ++k) {
    s.theta.push_back((k + 0.5) * 2 * M_PI / M);
    s.sigma_n.push_back(100 + 10 * std::cos(s.theta.back()));
    s.sigma_t.push_back(5 * std::sin(s.theta.back()));
  }
  s.kernel_width_deg = 5;
  s.sigma_n_stderr = std::vector<double>(M, 1.0);
  s.sigma_t_stderr = std::vector<double>(M, 0.5);
  r.surface = s;
  SurfaceHistogram h;
  for (int k = 0; k < 4; ++k) {
    h.theta_lo.push_back(-M_PI + k * M_PI / 2);
    h.theta_hi.push_back(-M_PI + (k + 1) * M_PI / 2);
    h.contact_count.push_back(1.5);
    h.normal_force.push_back(2.0);
    h.tangential_force.push_back(-0.1);
    h.slip_fraction.push_back(0.2);
  }
  r.histogram = h;
  FieldGrid g;
  g.x = {-0.1, 0.0, 0.1};
  g.y = {-0.05, 0.05};
  g.velocity_x = std::vector<double>(6, -0.5);
  g.velocity_y = std::vector<double>(6, 0.0);
  g.pressure = std::vector<double>{1, 2, NAN, 4, 5, 6};
  g.area_fraction = std::vector<double>(6, 0.8);
  g.granular_temperature = std::vector<double>(6, 1e-4);
  r.fields = g;
  r.diagnostics.counts = {{"grains", 300}, {"steps", 1000}};
  r.diagnostics.values = {{"area_fraction", 0.8}, {"collision_time", 1e-5}};
  r.diagnostics.texts = {{"pressure_scale_source", "lid + lithostatic"}};
  r.diagnostics.series = {{"replica_drag", {1.4, 1.6}}};
  return r;
}

RunResult fem_result() {
  RunResult r = dem_result();
  r.meta.solver = "fem";
  r.forces->contacts.clear();
  r.forces->time.resize(1);
  r.forces->fx.resize(1);
  r.forces->fy.resize(1);
  r.forces->torque.resize(1);
  r.means->drag_stderr.reset();
  r.means->lift_stderr.reset();
  r.means->torque_stderr.reset();
  r.means->contacts.reset();
  r.surface->sigma_n_stderr.reset();
  r.surface->sigma_t_stderr.reset();
  r.surface->sigma_n_pointwise = r.surface->sigma_n;
  r.surface->sigma_t_pointwise = r.surface->sigma_t;
  r.histogram.reset();
  r.lid.reset();
  r.far_field.reset();
  r.fields->area_fraction.reset();
  r.fields->granular_temperature.reset();
  r.fields->stress_xx = std::vector<double>(6, -100);
  r.fields->stress_xy = std::vector<double>(6, 1);
  r.fields->stress_yy = std::vector<double>(6, -90);
  r.diagnostics = {};
  r.diagnostics.counts = {{"converged", 1}, {"cells", 512}};
  r.diagnostics.values = {{"drag_mesh_error", 0.02}, {"lift_mesh_error", 0.01}};
  r.diagnostics.texts = {{"linear_solver", "direct"}};
  r.diagnostics.series = {{"residual_history", {1, 1e-3, 1e-9}}};
  return r;
}

RunResult minimal_result() {
  RunResult r;
  r.meta.solver = "dem";
  r.geometry.intruder_diameter = 0.1;
  r.geometry.velocity_x = 1;
  return r;
}

void result_seeds(const fs::path& corpus, const std::string& name, const RunResult& r) {
  const fs::path h5 = corpus / "result_raw" / (name + ".h5");
  fs::create_directories(h5.parent_path());
  write_result(h5.string(), r);
  std::printf("%s\n", h5.c_str());
  write(corpus / "result_file" / (name + ".ops"), fuzz::describe_file(h5.string()));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR\n", argv[0]);
    return 2;
  }
  const fs::path corpus = argv[1];
  const fs::path ck = corpus / "checkpoint";
  checkpoint_seeds(ck, "lid-fields", dem::encode_checkpoint(small_checkpoint(true, true)));
  checkpoint_seeds(ck, "plain", dem::encode_checkpoint(small_checkpoint(false, false)));
  checkpoint_seeds(ck, "empty", dem::encode_checkpoint(dem::RunCheckpoint{}));

  result_seeds(corpus, "dem", dem_result());
  result_seeds(corpus, "fem", fem_result());
  result_seeds(corpus, "minimal", minimal_result());
  return 0;
}
