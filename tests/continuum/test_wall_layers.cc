// continuum.wall_layers: rings of cells at the intruder (IntruderMesh), thinner towards it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "cylinder_case.h"
#include "grainlift/continuum/solver.h"

using namespace grainlift::continuum;
using grainlift::continuum::test::coarse_case;

// The rings are a mesh of the same box and hole: the hole's faces lie on the circle (to
// 1e-12 R) and each ring adds its 8 coarse cells, refined with the block (refinement + 1
// times), to the plain mesh's cells.
TEST(WallLayers, RingsAddTheirCellsOnTheSameHole) {
  ContinuumConfig c = coarse_case();
  const MeshOutline plain = mesh_outline(c);
  c.wall_layers = 3;
  const MeshOutline ringed = mesh_outline(c);
  const double R = 0.5 * c.intruder_diameter;
  EXPECT_LT(ringed.hole_radius_error, 1e-12 * R);
  EXPECT_EQ(ringed.cells - plain.cells, 3 * 8 * (1 << (2 * (c.refinement + 1))));
  for (int e = 0; e < 4; ++e) EXPECT_NEAR(ringed.edge[e], plain.edge[e], 1e-12);
}

// Where the forces' mesh error comes from the cells touching the intruder, thinning them
// radially makes the forces converge faster per level. The spinning cylinder of the shared
// small case (Omega = 1, no-slip), nested levels 0-2, plain and with two rings: at levels 1
// and 2 the change of the force vector from the level before is less than half the plain
// mesh's (measured 0.30 and 0.26 of it), for at most twice its unknowns (1.66x at level 2).
// (Against the limit of the finer meshes, the rings at level 3, 660.4 and -119.2 N/m: the
// rings' level 2 is 0.05% and 0.1% off, the plain level 4, with 9x its unknowns, 0.14% and
// 0.8%; docs/continuum-model.md, "Wall layers".)
TEST(WallLayers, TwoRingsConvergeFasterPerLevel) {
  ContinuumConfig c = coarse_case();
  c.intruder_omega = c.intruder_velocity[0] / (0.5 * c.intruder_diameter);
  c.refinement = 2;
  c.target_error = 0;
  const ContinuumOutput plain = solve_flow(c);
  c.wall_layers = 2;
  const ContinuumOutput ringed = solve_flow(c);
  ASSERT_TRUE(plain.converged && ringed.converged) << plain.message << ringed.message;
  ASSERT_EQ(plain.levels.size(), 3u);
  ASSERT_EQ(ringed.levels.size(), 3u);
  const auto change = [](const ContinuumOutput& o, int l) {
    return std::hypot(o.levels[l].fx - o.levels[l - 1].fx, o.levels[l].fy - o.levels[l - 1].fy);
  };
  for (int l = 0; l < 3; ++l)
    std::printf("level %d: plain %d unknowns, drag %.6g lift %.6g; rings %d, drag %.6g lift "
                "%.6g\n", l, plain.levels[l].dofs, -plain.levels[l].fx, plain.levels[l].fy,
                ringed.levels[l].dofs, -ringed.levels[l].fx, ringed.levels[l].fy);
  for (int l = 1; l <= 2; ++l) {
    EXPECT_LT(change(ringed, l), 0.5 * change(plain, l)) << "level " << l;
    EXPECT_LT(ringed.levels[l].dofs, 2 * plain.levels[l].dofs) << "level " << l;
  }
}
