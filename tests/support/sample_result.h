// The metadata and scene of the made-up result files that the tests and the fuzz seeds write
// (test_result_file, tests/fuzz/make_seeds): a DEM run of a 0.1 m intruder at 0.5 m/s spinning
// at 20 rad/s in a 6 m periodic box. Each caller adds the series it needs.
#pragma once

#include "grainlift/shared/run_result.h"

namespace grainlift::test_support {

inline RunResult sample_result_head() {
  RunResult r;
  r.meta.solver = "dem";
  r.meta.grainlift_version = "0.1.0";
  r.meta.git_revision = "abc123";
  r.meta.threads = 2;
  r.meta.wall_seconds = 12.5;
  r.meta.created_utc = "2026-11-21T12:00:00Z";
  r.meta.case_text = "[intruder]\ndiameter = 0.1 # \xc3\xbc\n";  // a non-ASCII character
  r.meta.case_overrides = "intruder.omega=2\n";
  r.meta.case_hash = "0123456789abcdef";
  r.meta.case_path = "cases/demo/demo.toml";
  r.meta.notes = "packing reused";
  r.geometry.intruder_diameter = 0.1;
  r.geometry.grain_diameter = 0.02;
  r.geometry.domain_xmin = -3;
  r.geometry.domain_xmax = 3;
  r.geometry.velocity_x = 0.5;
  r.geometry.omega = 20;
  r.geometry.bulk_density = 16;
  r.geometry.pressure_scale = 123.4;
  return r;
}

}  // namespace grainlift::test_support
