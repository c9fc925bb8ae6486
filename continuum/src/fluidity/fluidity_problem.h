// FluidityProblem: the scalar equation of the nonlocal granular fluidity model,
//
//     g - xi^2 Laplacian(g) = g_loc      (Kamrin & Koval, PRL 108, 178301, 2012)
//
// on a given 2D triangulation, with xi and g_loc supplied per quadrature point (so that the
// coupling with the flow can evaluate mu and p there), Q1 or Q2 elements, g imposed on some
// boundaries and zero flux (xi^2 grad g . n = 0, the natural condition) on the others.
// Internal header (deal.II inside); the public, deal.II-free entry points are in
// grainlift/continuum/fluidity/. The deal.II tutorial shape (step-6): setup_system(),
// assemble_system(), solve(), errors(), run().
#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <array>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace grainlift::continuum::fluidity::internal {

constexpr int dim = 2;
using Point2 = dealii::Point<dim>;
using Vec2 = dealii::Tensor<1, dim>;
using ScalarField = std::function<double(const Point2&)>;
using GradientField = std::function<Vec2(const Point2&)>;
using CellIterator = dealii::Triangulation<dim>::active_cell_iterator;

/// The coefficients at the quadrature points of one cell.
struct CellCoefficients {
  std::vector<double> xi;     ///< m, cooperativity length
  std::vector<double> g_loc;  ///< 1/s, local fluidity
};

/// Fills @p out (sized to the number of quadrature points) at the mapped quadrature points
/// @p points of @p cell, in the order of FluidityProblem::quadrature(). The coupling with the
/// flow turns @p cell into a cell of its own DoFHandler on the same triangulation and evaluates
/// mu and p there with the same quadrature.
using CoefficientSupplier = std::function<void(
    const CellIterator& cell, const std::vector<Point2>& points, CellCoefficients& out)>;

/// A supplier from two functions of position.
CoefficientSupplier pointwise_coefficients(ScalarField xi, ScalarField g_loc);

struct FluiditySetup {
  CoefficientSupplier coefficients;
  /// g imposed (1/s) on these boundary ids; every other boundary is zero flux
  std::map<dealii::types::boundary_id, ScalarField> dirichlet;
  std::function<void(const std::string&)> log;
};

class FluidityProblem {
 public:
  /// Q@p degree elements (1 or 2) with a Q@p degree mapping on @p tria (not owned).
  FluidityProblem(const dealii::Triangulation<dim>& tria, unsigned int degree,
                  FluiditySetup setup);

  /// setup_system(), assemble_system(), solve().
  void run();
  /// Distribute the dofs, build the constraints (hanging nodes, Dirichlet) and the pattern.
  void setup_system();
  /// int xi^2 grad g . grad v + g v = int g_loc v, coefficients from the supplier.
  void assemble_system();
  /// Sparse direct solve (UMFPACK), then the constraints distributed.
  void solve();
  /// L2 norm and H1 seminorm of g_h - g against the exact @p g and its gradient @p grad_g
  /// (Gauss quadrature with degree + 2 points per direction).
  std::array<double, 2> errors(const ScalarField& g, const GradientField& grad_g) const;
  /// max over the support points of |g_h - g| (nodal interpolation error).
  double max_nodal_error(const ScalarField& g) const;

  const dealii::Quadrature<dim>& quadrature() const { return quadrature_; }
  const dealii::DoFHandler<dim>& dof_handler() const { return dof_handler_; }
  const dealii::Vector<double>& solution() const { return solution_; }
  const dealii::Mapping<dim>& mapping() const { return mapping_; }

 private:
  void log(const std::string& s) const { if (setup_.log) setup_.log(s); }

  const dealii::Triangulation<dim>& tria_;
  FluiditySetup setup_;
  dealii::FE_Q<dim> fe_;
  dealii::MappingQ<dim> mapping_;
  dealii::QGauss<dim> quadrature_;
  dealii::DoFHandler<dim> dof_handler_;
  dealii::AffineConstraints<double> constraints_;
  dealii::SparsityPattern sparsity_pattern_;
  dealii::SparseMatrix<double> system_matrix_;
  dealii::Vector<double> solution_, system_rhs_;
};

}  // namespace grainlift::continuum::fluidity::internal
