#include "fluidity/fluidity_viscosity.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace grainlift::continuum::internal {

using namespace dealii;

FluidityViscosity::FluidityViscosity(const RheologyParams& params, const DoFHandler<2>& g_dofs,
                                     const Vector<double>& g)
    : p_(params), g_dofs_(g_dofs), g_(g), g_min_(2 * params.delta / params.mu_s) {}

void FluidityViscosity::fill_fields(const FEValues<2>& fev, RheologyInputs& in) const {
  // the same cell of the fluidity's DoFHandler; the values at the reference quadrature points
  // need no mapping (the field is a sum of shape functions on the cell)
  const auto& cell = fev.get_cell();
  const typename DoFHandler<2>::active_cell_iterator g_cell(&g_dofs_.get_triangulation(),
                                                            cell->level(), cell->index(),
                                                            &g_dofs_);
  const auto& fe = g_dofs_.get_fe();
  thread_local std::vector<types::global_dof_index> dofs;  // no allocation per cell
  dofs.resize(fe.n_dofs_per_cell());
  g_cell->get_dof_indices(dofs);
  const Quadrature<2>& quad = fev.get_quadrature();
  in.fluidity.assign(quad.size(), 0.0);
  for (unsigned int q = 0; q < quad.size(); ++q) {
    double v = 0;
    for (unsigned int i = 0; i < dofs.size(); ++i)
      v += g_(dofs[i]) * fe.shape_value(i, quad.point(q));
    in.fluidity[q] = std::max(v, g_min_);
  }
}

void FluidityViscosity::evaluate(const RheologyInputs& in, RheologyOutputs& out) const {
  for (std::size_t q = 0; q < in.size(); ++q) {
    const double p = std::max(in.pressure[q], 0.0);
    const double g = in.fluidity.size() == in.size() ? in.fluidity[q] : g_min_;
    const double raw = p / g;
    const double eta = std::clamp(raw, p_.eta_min, p_.eta_max);
    const bool free = raw > p_.eta_min && raw < p_.eta_max && in.pressure[q] > 0;
    const double rate = std::sqrt(std::max(in.strain_rate_sq[q], 0.0));
    out.viscosity[q] = eta;
    out.deta_dstrain_sq[q] = 0;
    out.deta_dpressure[q] = free ? 1 / g : 0;
    out.friction[q] = p > 0 ? 2 * eta * rate / p : 0;
    out.inertial_number[q] = p > 0 ? 2 * rate * p_.grain_diameter / std::sqrt(p / p_.solid_density)
                                   : 0;
  }
}

}  // namespace grainlift::continuum::internal
