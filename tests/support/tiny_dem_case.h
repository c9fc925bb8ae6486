// The tiny DEM case of the tests that run the real `grainlift` binary (test_end_to_end,
// test_report): a 20 d x 14 d box at Phi 0.6 with walls top and bottom, periodic in x, an
// intruder of 5 d at 2 m/s spinning at 80 rad/s, 10 d of travel: about a second.
#pragma once

namespace grainlift::test_support {

inline const char* const tiny_case = R"([domain]
x_range = [-0.2, 0.2]
y_range = [-0.14, 0.14]
periodic = [true, false]
walls = ["bottom", "top"]
[intruder]
diameter = 0.1
velocity = [2.0, 0.0]
omega = 80.0
[grains]
diameter = 0.02
density = 20.0
area_fraction = 0.6
[dem]
travel = 10.0
steady_travel = 2.0
sample_every = 20
packing_cache = ""
[output]
blocks = 5
field_half_size = [1.0, 1.0]
)";

}  // namespace grainlift::test_support
