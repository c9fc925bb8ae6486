// The flow's viscosity in the nonlocal granular fluidity model: eta = p+ / g, with the fluidity
// g a finite-element field (FluidityProblem's solution on the flow's mesh) read at the
// quadrature points of each cell. Internal header (deal.II inside).
#pragma once

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/vector.h>

#include "grainlift/continuum/mu_i_rheology.h"

namespace grainlift::continuum::internal {

/// @brief A viscosity that depends on a field besides |D|^2 and p: QuadratureRheology asks it
/// to fill RheologyInputs::fluidity on each cell before evaluate().
class FieldViscosity : public ViscosityModel {
 public:
  /// Fills in.fluidity (sized here) at the quadrature points of @p fev's cell.
  virtual void fill_fields(const dealii::FEValues<2>& fev, RheologyInputs& in) const = 0;
};

/// @brief eta = p+ / g (Kamrin & Koval 2012: gamma_dot = g mu, tau = mu p, so tau = (p / g)
/// gamma_dot), g = max(g_h, g_min) from a Q-element field on the flow's triangulation,
/// clamped to [eta_min, eta_max] as MuIRheology is. g_min = 2 delta / mu_s gives the
/// largest viscosity of the local law's regularisation (mu_s p / (2 delta)). For fixed g the
/// law is linear in p+: d eta / d p = 1 / g, d eta / d|D|^2 = 0 (the splitting iterates g).
class FluidityViscosity final : public FieldViscosity {
 public:
  /// @param g_dofs, g  the fluidity field (1/s) on the flow's triangulation (not owned)
  FluidityViscosity(const RheologyParams& params, const dealii::DoFHandler<2>& g_dofs,
                    const dealii::Vector<double>& g);
  void fill_fields(const dealii::FEValues<2>& fev, RheologyInputs& in) const override;
  void evaluate(const RheologyInputs& in, RheologyOutputs& out) const override;
  bool is_nonlinear() const override { return true; }
  double g_min() const { return g_min_; }

 private:
  RheologyParams p_;
  const dealii::DoFHandler<2>& g_dofs_;
  const dealii::Vector<double>& g_;
  double g_min_;
};

}  // namespace grainlift::continuum::internal
