// Internal: the mesh of the cylinder problem (IntruderMesh). Includes deal.II: never include
// it from a public header.
#pragma once

#include <deal.II/grid/tria.h>

#include <array>
#include <cmath>
#include <memory>

#include "flow_problem.h"

namespace grainlift::continuum::internal {

/// Boundary ids of IntruderMesh.
constexpr dealii::types::boundary_id kLeft = 0, kRight = 1, kBottom = 2, kTop = 3, kHole = 4;

/// Box [x0, x1] x [y0, y1] (x0, y0 < 0 < x1, y1: the intruder's centre at the origin) with a
/// hole of radius R at the origin. A square block of half-size b = min(2R, (R + the nearest
/// edge's distance) / 2) around the hole (8 cells, polar manifold on the hole, transfinite
/// interpolation inside) is merged into a tensor grid whose cells grow geometrically (ratio 1.4)
/// from the block to each edge, so the mesh is graded towards the intruder on every side
/// however far each edge is. Boundary ids: 0 x = x0, 1 x = x1, 2 y = y0, 3 y = y1, 4 the hole
/// (kLeft ... kHole). The left and right edges carry the same y nodes (one tensor grid), so
/// they match as periodic faces. After @p refinement global refinements the block is refined
/// once more (the mesh is finest at the intruder). With wall_layers = n > 0 the block's 8 cells
/// become n polar rings of 8 cells at the hole, each twice as thick as the one inside it, and
/// 8 cells from the outermost ring to the square (continuum.wall_layers).
///
/// One MPI rank: a serial Triangulation. Several: a parallel::distributed::Triangulation (p4est)
/// made from the vertices and cells of the same coarse mesh; the ids and the manifolds are then
/// set on the distributed mesh itself, whose coarse mesh every rank holds whole, so the
/// transfinite interpolation is initialised on exactly the serial coarse cells. (Copying the
/// decorated serial mesh with copy_triangulation instead made TransfiniteInterpolationManifold::
/// initialize() throw ExcTransformationFailed in an earlier attempt.) The refinement is the
/// same on both; a rank flags only its own cells. The serial mesh limits the level jump to one
/// across vertices too (limit_level_difference_at_vertices), as p4est's 2:1 balance does: the
/// adaptive cycles then refine the same cells on one and on N ranks (with faces only, a cell
/// touching a block corner two levels finer would stay coarse on one process and be refined by
/// p4est). Uniform meshes never have such a jump: the rule changes nothing there.
class IntruderMesh {
 public:
  /// @param R intruder radius (m); @param box {x0, x1, y0, y1}, the box's edges relative to
  /// the intruder's centre (m); @param refinement number of global refinements (then the block
  /// around the hole once more)
  /// @param periodic_x the left and right edges are identified (a distributed mesh is told
  /// before it is refined, so that p4est balances across them)
  /// @param wall_layers rings of cells round the hole inside the block (make_ringed_block())
  IntruderMesh(double R, const std::array<double, 4>& box, int refinement,
               bool periodic_x = false, int wall_layers = 0);
  dealii::Triangulation<2>& tria() { return *tria_; }

 private:
  bool in_block(const Point2& x) const { return std::abs(x[0]) < b_ && std::abs(x[1]) < b_; }
  void make_coarse(dealii::Triangulation<2>& tria) const;
  /// The block with wall_layers_ rings of 8 cells round the hole (polar manifold), then one
  /// layer of 8 cells from the outermost circle to the square (transfinite interpolation).
  void make_ringed_block(dealii::Triangulation<2>& block) const;
  /// Radius of circle j = 0 ... wall_layers_ (0: the hole): the rings fill the inner half of
  /// the room b - R, each twice as thick as the one inside it.
  double ring_radius(int j) const;
  /// Boundary and manifold ids, the polar and transfinite-interpolation manifolds.
  void decorate(dealii::Triangulation<2>& tria) const;

  double R_;
  std::array<double, 4> box_;  ///< x0, x1, y0, y1
  double b_ = 0;
  int wall_layers_ = 0;
  std::unique_ptr<dealii::Triangulation<2>> tria_;
};

}  // namespace grainlift::continuum::internal
