// IntruderMesh: the box with the intruder's hole, graded towards the hole (intruder_mesh.h).
#include "intruder_mesh.h"

#include <deal.II/distributed/tria.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/manifold_lib.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "grainlift/continuum/mpi_session.h"

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

IntruderMesh::IntruderMesh(double R, double W, double H, int refinement)
    : R_(R), W_(W), H_(H) {
  b_ = std::min(2 * R, 0.5 * (R + std::min(W, H)));
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
  tria_->refine_global(refinement);
  for (const auto& cell : tria_->active_cell_iterators())
    if (cell->is_locally_owned() && in_block(cell->center())) cell->set_refine_flag();
  tria_->execute_coarsening_and_refinement();
}

void IntruderMesh::make_coarse(Triangulation<2>& tria) const {
  const double W = W_, H = H_;
  const double b = b_;
  const auto steps_along = [b](double half) {
    const std::vector<double> pad = padding_steps(b, half - b);
    std::vector<double> steps(pad.rbegin(), pad.rend());
    steps.push_back(b);
    steps.push_back(b);
    steps.insert(steps.end(), pad.begin(), pad.end());
    return steps;
  };
  Triangulation<2> outer, outer_holed, block;
  GridGenerator::subdivided_hyper_rectangle(outer, {steps_along(W), steps_along(H)},
                                            Point2(-W, -H), Point2(W, H), false);
  std::set<Triangulation<2>::active_cell_iterator> central;
  for (const auto& cell : outer.active_cell_iterators())
    if (in_block(cell->center())) central.insert(cell);
  GridGenerator::create_triangulation_with_removed_cells(outer, central, outer_holed);
  GridGenerator::hyper_cube_with_cylindrical_hole(block, R_, b, 1.0, 1, false);
  GridGenerator::merge_triangulations(outer_holed, block, tria, 1e-9 * R_);
}

void IntruderMesh::decorate(Triangulation<2>& tria) const {
  tria.reset_all_manifolds();
  tria.set_all_manifold_ids(numbers::flat_manifold_id);
  const double tol = 1e-6 * R_;
  for (const auto& cell : tria.active_cell_iterators())
    if (in_block(cell->center())) cell->set_all_manifold_ids(1);
  for (const auto& cell : tria.active_cell_iterators())
    for (const auto& face : cell->face_iterators()) {
      if (!face->at_boundary()) continue;
      const Point2 c = face->center();
      if (std::abs(face->vertex(0).norm() - R_) < tol && std::abs(face->vertex(1).norm() - R_) < tol) {
        face->set_boundary_id(kHole);
        face->set_manifold_id(0);
      } else if (std::abs(c[0] + W_) < tol) face->set_boundary_id(kLeft);
      else if (std::abs(c[0] - W_) < tol) face->set_boundary_id(kRight);
      else if (std::abs(c[1] + H_) < tol) face->set_boundary_id(kBottom);
      else face->set_boundary_id(kTop);
    }
  tria.set_manifold(0, PolarManifold<2>(Point2()));
  TransfiniteInterpolationManifold<2> tfi;
  tfi.initialize(tria);
  tria.set_manifold(1, tfi);
}

}  // namespace grainlift::continuum::internal
