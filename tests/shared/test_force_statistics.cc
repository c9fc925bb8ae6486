// Drag and lift follow docs/conventions.md: D = -F.V/|V|, L = F.(z x V/|V|). (Block means:
// test_statistics.cc.)
#include <gtest/gtest.h>

#include "grainlift/shared/statistics/force_statistics.h"

using namespace grainlift;

TEST(DragLift, SignConventionsOfTargets) {
  // V along +x: a force opposing motion (-x) is positive drag; lift is F_y.
  auto r = project_drag_lift(-3.0, 2.0, 0.5, 0.0);
  EXPECT_DOUBLE_EQ(r.drag, 3.0);
  EXPECT_DOUBLE_EQ(r.lift, 2.0);
  // V along -x: z x V/|V| = -y, so a force along +y is negative lift; +x opposes motion.
  r = project_drag_lift(3.0, 2.0, -0.5, 0.0);
  EXPECT_DOUBLE_EQ(r.drag, 3.0);
  EXPECT_DOUBLE_EQ(r.lift, -2.0);
  // V along +y: z x y = -x, so a force along -x is positive lift.
  r = project_drag_lift(-1.0, -4.0, 0.0, 2.0);
  EXPECT_DOUBLE_EQ(r.drag, 4.0);
  EXPECT_DOUBLE_EQ(r.lift, 1.0);
  // Inverse Magnus (Kumar 2019): omega > 0 (ccw), V along +x, lift along -omega x V = -y.
  // -omega z x V x = -omega V y: a force along -y is negative lift under our convention.
  r = project_drag_lift(0.0, -1.0, 1.0, 0.0);
  EXPECT_LT(r.lift, 0.0);
  EXPECT_THROW(project_drag_lift(1, 1, 0, 0), std::invalid_argument);
}
