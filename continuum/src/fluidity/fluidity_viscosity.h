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
  /// Fills in.fluidity at the points @p unit (reference coordinates) of @p cell (faces,
  /// probes: the points of no assembly quadrature).
  virtual void fill_fields_at(const dealii::Triangulation<2>::cell_iterator& cell,
                              const std::vector<dealii::Point<2>>& unit,
                              RheologyInputs& in) const = 0;
};

/// @brief eta = p+ / g (Kamrin & Koval 2012: gamma_dot = g mu, tau = mu p, so tau = (p / g)
/// gamma_dot), g = max(g_h, g_min) from a Q-element field on the flow's triangulation,
/// clamped to [eta_min, eta_max] as MuIRheology is. g_min = 2 delta / mu_s gives the
/// largest viscosity of the local law's regularisation (mu_s p / (2 delta)).
///
/// Two forms. Lagged (no local fluidity given): g fixed, the law linear in p+, d eta / d p =
/// 1 / g, d eta / d|D|^2 = 0. Local part implicit (set_local_fluidity(), at the points of one
/// quadrature on every cell): g = g_loc(mu) + (g_h - g_loc_prev), the excess g_h - g_loc_prev
/// fixed and g_loc at the flow's own mu, so gamma_dot = mu (g_loc(mu, p) + excess) is solved
/// for mu (stress_ratio_at_fluidity) and eta = mu p / gamma_dot with its derivatives in |D|^2
/// and p (gamma_dot regularised as MuIRheology's, capped as it is). The table's g_loc is taken
/// at the model's friction output (this mu, or the local law's mu(I)): at the splitting's fixed
/// point mu = mu_prev and both forms give eta = p / g_h; with
/// xi -> 0 the excess vanishes and the flow step is the local law, so the splitting no longer
/// iterates the local law's stiff dependence on the strain rate as a Picard map. Points of
/// another quadrature (faces, probes) get the lagged form.
class FluidityViscosity final : public FieldViscosity {
 public:
  /// @param g_dofs, g  the fluidity field (1/s) on the flow's triangulation (not owned)
  FluidityViscosity(const RheologyParams& params, const dealii::DoFHandler<2>& g_dofs,
                    const dealii::Vector<double>& g);
  void fill_fields(const dealii::FEValues<2>& fev, RheologyInputs& in) const override;
  void fill_fields_at(const dealii::Triangulation<2>::cell_iterator& cell,
                      const std::vector<dealii::Point<2>>& unit,
                      RheologyInputs& in) const override;
  void evaluate(const RheologyInputs& in, RheologyOutputs& out) const override;
  bool is_nonlinear() const override { return true; }
  double g_min() const { return g_min_; }
  /// The previous flow's g_loc (1/s) at the points of @p quadrature on every active cell,
  /// @p g_loc[cell->active_cell_index() * n_points + q]; an empty vector restores the lagged
  /// form. The triangulation must not change while it is set.
  void set_local_fluidity(const dealii::Quadrature<2>& quadrature, std::vector<double> g_loc);

 private:
  void evaluate_lagged(const RheologyInputs& in, std::size_t q, RheologyOutputs& out) const;
  /// false (nothing written) where no stress ratio solves the step (p <= 0)
  bool evaluate_implicit(const RheologyInputs& in, std::size_t q, RheologyOutputs& out) const;

  RheologyParams p_;
  const dealii::DoFHandler<2>& g_dofs_;
  const dealii::Vector<double>& g_;
  double g_min_;
  std::vector<dealii::Point<2>> local_points_;  ///< the reference points of g_loc_prev_
  std::vector<double> g_loc_prev_;
};

}  // namespace grainlift::continuum::internal
