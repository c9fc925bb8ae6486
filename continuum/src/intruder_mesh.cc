// IntruderMesh: the box with the intruder's hole, graded towards the hole (intruder_mesh.h).
#include "intruder_mesh.h"

#include <deal.II/distributed/tria.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/manifold_lib.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "grainlift/continuum/mpi_session.h"
#include "grainlift/continuum/solver.h"

namespace grainlift::continuum::internal {

using namespace dealii;

namespace {

/// Sizes of the padding cells between the central block (half-size b) and the box edge
/// (distance pad): the first is b, each next 1.4 times larger, scaled to fit exactly.
std::vector<double> padding_steps(double b, double pad) {
  std::vector<double> steps;
  if (pad <= 1e-12 * b) return steps;
  double sum = 0, s = b;
  while (sum < pad * (1 - 1e-9)) {
    steps.push_back(s);
    sum += s;
    s *= 1.4;
  }
  for (double& x : steps) x *= pad / sum;
  return steps;
}

}  // namespace

IntruderMesh::IntruderMesh(double R, const std::array<double, 4>& box, int refinement,
                           bool periodic_x, int wall_layers)
    : R_(R), box_(box), wall_layers_(wall_layers) {
  const double nearest = std::min({-box[0], box[1], -box[2], box[3]});
  b_ = std::min(2 * R, 0.5 * (R + nearest));
  if (MpiSession::size() == 1) {  // (MPI may not even be initialised)
    tria_ = std::make_unique<Triangulation<2>>(
        Triangulation<2>::limit_level_difference_at_vertices);
    make_coarse(*tria_);
  } else {
    Triangulation<2> coarse;
    make_coarse(coarse);
    std::vector<CellData<2>> cells(coarse.n_cells(0));
    for (const auto& cell : coarse.cell_iterators_on_level(0))
      for (const unsigned int v : cell->vertex_indices())
        cells[cell->index()].vertices[v] = cell->vertex_index(v);
    tria_ = std::make_unique<parallel::distributed::Triangulation<2>>(MPI_COMM_WORLD);
    tria_->create_triangulation(coarse.get_vertices(), cells, SubCellData());
  }
  decorate(*tria_);
  if (periodic_x && MpiSession::size() > 1) {
    // p4est must know the periodic faces before refining (the serial mesh, refined alike on
    // both ends, needs nothing: its periodicity is a constraint of the dofs only)
    std::vector<GridTools::PeriodicFacePair<Triangulation<2>::cell_iterator>> pairs;
    GridTools::collect_periodic_faces(*tria_, kLeft, kRight, 0, pairs);
    tria_->add_periodicity(pairs);
  }
  tria_->refine_global(refinement);
  for (const auto& cell : tria_->active_cell_iterators())
    if (cell->is_locally_owned() && in_block(cell->center())) cell->set_refine_flag();
  tria_->execute_coarsening_and_refinement();
}

void IntruderMesh::make_coarse(Triangulation<2>& tria) const {
  const double b = b_;
  // cell sizes from the low edge to the high one: padding towards the block, the block's two
  // cells, padding away from it
  const auto steps_along = [b](double lo, double hi) {
    const std::vector<double> pad_lo = padding_steps(b, -lo - b);
    std::vector<double> steps(pad_lo.rbegin(), pad_lo.rend());
    steps.push_back(b);
    steps.push_back(b);
    const std::vector<double> pad_hi = padding_steps(b, hi - b);
    steps.insert(steps.end(), pad_hi.begin(), pad_hi.end());
    return steps;
  };
  Triangulation<2> outer, outer_holed, block;
  GridGenerator::subdivided_hyper_rectangle(
      outer, {steps_along(box_[0], box_[1]), steps_along(box_[2], box_[3])},
      Point2(box_[0], box_[2]), Point2(box_[1], box_[3]), false);
  std::set<Triangulation<2>::active_cell_iterator> central;
  for (const auto& cell : outer.active_cell_iterators())
    if (in_block(cell->center())) central.insert(cell);
  GridGenerator::create_triangulation_with_removed_cells(outer, central, outer_holed);
  if (wall_layers_ == 0)
    GridGenerator::hyper_cube_with_cylindrical_hole(block, R_, b, 1.0, 1, false);
  else
    make_ringed_block(block);
  GridGenerator::merge_triangulations(outer_holed, block, tria, 1e-9 * R_);
}

void IntruderMesh::make_ringed_block(Triangulation<2>& block) const {
  // 8 points on each circle and on the square, at the square's corners and the middles of
  // its sides (as hyper_cube_with_cylindrical_hole places them)
  const int n = wall_layers_;
  std::vector<Point2> vertices;
  for (int j = 0; j <= n + 1; ++j)
    for (int k = 0; k < 8; ++k) {
      const double a = k * M_PI / 4, c = std::cos(a), s = std::sin(a);
      const double r = j <= n ? ring_radius(j) : b_ / std::max(std::abs(c), std::abs(s));
      vertices.emplace_back(r * c, r * s);
    }
  std::vector<CellData<2>> cells;
  for (int j = 0; j <= n; ++j)
    for (int k = 0; k < 8; ++k) {
      CellData<2> cell;  // radial, then angular: positively oriented
      cell.vertices = {unsigned(8 * j + k), unsigned(8 * (j + 1) + k),
                       unsigned(8 * j + (k + 1) % 8), unsigned(8 * (j + 1) + (k + 1) % 8)};
      cells.push_back(cell);
    }
  block.create_triangulation(vertices, cells, SubCellData());
}

double IntruderMesh::ring_radius(int j) const {
  const double room = 0.5 * (b_ - R_);
  return R_ + room * (std::pow(2.0, j) - 1) / (std::pow(2.0, wall_layers_) - 1);
}

void IntruderMesh::decorate(Triangulation<2>& tria) const {
  tria.reset_all_manifolds();
  tria.set_all_manifold_ids(numbers::flat_manifold_id);
  const double tol = 1e-6 * R_;
  for (const auto& cell : tria.active_cell_iterators())
    if (in_block(cell->center())) cell->set_all_manifold_ids(1);
  // the rings are polar: their cells, their circles, their spokes. A second pass, after the
  // block's: the circle between the outermost ring and the block's outer cells must end up polar
  // whichever cell is visited last (one pass setting each cell's ids gave other meshes)
  if (wall_layers_ > 0) {
    const double r_out = ring_radius(wall_layers_) * (1 + 1e-9);
    for (const auto& cell : tria.active_cell_iterators()) {
      bool ring = true;
      for (const unsigned int v : cell->vertex_indices()) ring &= cell->vertex(v).norm() < r_out;
      if (ring) cell->set_all_manifold_ids(0);
    }
  }
  for (const auto& cell : tria.active_cell_iterators())
    for (const auto& face : cell->face_iterators()) {
      if (!face->at_boundary()) continue;
      const Point2 c = face->center();
      if (std::abs(face->vertex(0).norm() - R_) < tol &&
          std::abs(face->vertex(1).norm() - R_) < tol) {
        face->set_boundary_id(kHole);
        face->set_manifold_id(0);
      } else if (std::abs(c[0] - box_[0]) < tol)
        face->set_boundary_id(kLeft);
      else if (std::abs(c[0] - box_[1]) < tol) face->set_boundary_id(kRight);
      else if (std::abs(c[1] - box_[2]) < tol) face->set_boundary_id(kBottom);
      else face->set_boundary_id(kTop);
    }
  tria.set_manifold(0, PolarManifold<2>(Point2()));
  TransfiniteInterpolationManifold<2> tfi;
  tfi.initialize(tria);
  tria.set_manifold(1, tfi);
}

}  // namespace grainlift::continuum::internal

namespace grainlift::continuum {

MeshOutline mesh_outline(const ContinuumConfig& config) {
  using internal::IntruderMesh;
  const double R = 0.5 * config.intruder_diameter;
  IntruderMesh mesh(R, box_edges(config), config.refinement, false, config.wall_layers);
  const dealii::Triangulation<2>& tria = mesh.tria();
  MeshOutline o;
  o.cells = static_cast<int>(tria.n_active_cells());
  o.xmin = o.ymin = 1e300;
  o.xmax = o.ymax = -1e300;
  for (const auto& v : tria.get_vertices()) {
    o.xmin = std::min(o.xmin, v[0]);
    o.xmax = std::max(o.xmax, v[0]);
    o.ymin = std::min(o.ymin, v[1]);
    o.ymax = std::max(o.ymax, v[1]);
  }
  std::array<std::vector<double>, 4> at;  // x of the left/right faces, y of bottom/top
  std::vector<double> left_y, right_y;
  for (const auto& cell : tria.active_cell_iterators())
    for (const auto& face : cell->face_iterators()) {
      if (!face->at_boundary()) continue;
      const auto id = face->boundary_id();
      if (id == internal::kHole) {
        for (unsigned int k = 0; k < 2; ++k)
          o.hole_radius_error = std::max(o.hole_radius_error, std::abs(face->vertex(k).norm() - R));
        continue;
      }
      for (unsigned int k = 0; k < 2; ++k) at[id].push_back(face->vertex(k)[id < 2 ? 0 : 1]);
      if (id == internal::kLeft) left_y.push_back(face->center()[1]);
      if (id == internal::kRight) right_y.push_back(face->center()[1]);
    }
  for (int e = 0; e < 4; ++e) {
    double sum = 0;
    for (const double x : at[e]) sum += x;
    o.edge[e] = at[e].empty() ? 0.0 : sum / double(at[e].size());
    for (const double x : at[e]) o.edge_spread = std::max(o.edge_spread, std::abs(x - o.edge[e]));
  }
  o.left_faces = static_cast<int>(left_y.size());
  o.right_faces = static_cast<int>(right_y.size());
  for (const double y : left_y) {
    double best = 1e300;
    for (const double yr : right_y) best = std::min(best, std::abs(yr - y));
    if (best < 1e-3 * R) {
      ++o.periodic_pairs;
      o.periodic_mismatch = std::max(o.periodic_mismatch, best);
    }
  }
  return o;
}

}  // namespace grainlift::continuum
