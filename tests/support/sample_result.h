// The metadata and scene of the made-up result files that the tests and the fuzz seeds write
// (test_result_file, tests/fuzz/make_seeds): a DEM run of a 0.1 m intruder at 0.5 m/s spinning
// at 20 rad/s in a 6 m periodic box. Each caller adds the series it needs.
#pragma once

#include "grainlift/shared/results/run_result.h"

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

/// A made-up /bed (a loose bed: few contacts, most grains rattlers).
inline BedStructure sample_bed() {
  BedStructure bed;
  bed.contacts_per_grain = 0.17;
  bed.rattler_fraction = 0.93;
  bed.fabric_xx = 0.48;
  bed.fabric_xy = -0.01;
  bed.fabric_yy = 0.52;
  bed.mean_gap = 0.12;
  bed.gap_edges = {-0.05, 0.0, 0.01, 0.1};
  bed.gap_fraction = {0.1, 0.5, 0.4};
  bed.band_y = {0.01, 0.03};
  bed.band_area_fraction = {0.79, 0.81};
  bed.ring_r = {0.06};
  bed.ring_area_fraction = {0.7};
  return bed;
}

}  // namespace grainlift::test_support
