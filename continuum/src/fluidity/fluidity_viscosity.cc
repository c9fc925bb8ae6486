#include "fluidity/fluidity_viscosity.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "grainlift/shared/rheology/fluidity_law.h"

namespace grainlift::continuum::internal {

using namespace dealii;

FluidityViscosity::FluidityViscosity(const RheologyParams& params, const DoFHandler<2>& g_dofs,
                                     const Vector<double>& g)
    : p_(params), g_dofs_(g_dofs), g_(g), g_min_(2 * params.delta / params.mu_s) {}

void FluidityViscosity::set_local_fluidity(const Quadrature<2>& quadrature,
                                           std::vector<double> g_loc) {
  local_points_ = g_loc.empty() ? std::vector<Point<2>>() : quadrature.get_points();
  g_loc_prev_ = std::move(g_loc);
}

void FluidityViscosity::fill_fields_at(const Triangulation<2>::cell_iterator& cell,
                                       const std::vector<Point<2>>& unit,
                                       RheologyInputs& in) const {
  // the same cell of the fluidity's DoFHandler; the field is a sum of shape functions on the
  // cell, evaluated at the reference points (no mapping)
  const typename DoFHandler<2>::active_cell_iterator g_cell(&g_dofs_.get_triangulation(),
                                                            cell->level(), cell->index(),
                                                            &g_dofs_);
  const auto& fe = g_dofs_.get_fe();
  thread_local std::vector<types::global_dof_index> dofs;  // no allocation per cell
  dofs.resize(fe.n_dofs_per_cell());
  g_cell->get_dof_indices(dofs);
  in.fluidity.assign(unit.size(), 0.0);
  for (unsigned int q = 0; q < unit.size(); ++q) {
    double v = 0;
    for (unsigned int i = 0; i < dofs.size(); ++i) v += g_(dofs[i]) * fe.shape_value(i, unit[q]);
    in.fluidity[q] = std::max(v, g_min_);
  }
  in.fluidity_excess.clear();
}

void FluidityViscosity::fill_fields(const FEValues<2>& fev, RheologyInputs& in) const {
  const Quadrature<2>& quad = fev.get_quadrature();
  fill_fields_at(fev.get_cell(), quad.get_points(), in);
  if (g_loc_prev_.empty() || quad.get_points() != local_points_) return;
  const std::size_t first = fev.get_cell()->active_cell_index() * quad.size();
  in.fluidity_excess.resize(quad.size());
  for (unsigned int q = 0; q < quad.size(); ++q)
    in.fluidity_excess[q] = in.fluidity[q] - g_loc_prev_[first + q];
}

void FluidityViscosity::evaluate(const RheologyInputs& in, RheologyOutputs& out) const {
  const bool implicit = in.fluidity_excess.size() == in.size();
  for (std::size_t q = 0; q < in.size(); ++q) {
    const double p = std::max(in.pressure[q], 0.0);
    const double rate = std::sqrt(std::max(in.strain_rate_sq[q], 0.0));
    out.inertial_number[q] =
        p > 0 ? 2 * rate * p_.grain_diameter / std::sqrt(p / p_.solid_density) : 0;
    if (!implicit || !evaluate_implicit(in, q, out)) {
      evaluate_lagged(in, q, out);
      out.friction[q] = p > 0 ? 2 * out.viscosity[q] * rate / p : 0;
    }
  }
}

void FluidityViscosity::evaluate_lagged(const RheologyInputs& in, std::size_t q,
                                        RheologyOutputs& out) const {
  const double p = std::max(in.pressure[q], 0.0);
  const double g = in.fluidity.size() == in.size() ? in.fluidity[q] : g_min_;
  const double raw = p / g;
  const bool free = raw > p_.eta_min && raw < p_.eta_max && in.pressure[q] > 0;
  out.viscosity[q] = std::clamp(raw, p_.eta_min, p_.eta_max);
  out.deta_dstrain_sq[q] = 0;
  out.deta_dpressure[q] = free ? 1 / g : 0;
}

bool FluidityViscosity::evaluate_implicit(const RheologyInputs& in, std::size_t q,
                                          RheologyOutputs& out) const {
  const double p = in.pressure[q];
  // gamma_dot regularised as the local law's, 2 sqrt(|D|^2 + delta^2): with a zero excess the
  // step is MuIRheology's law (up to the cap of I)
  const double s = std::max(in.strain_rate_sq[q], 0.0);
  const double rate = 2 * std::sqrt(s + p_.delta * p_.delta);
  const FluidityStressRatio m = stress_ratio_at_fluidity(
      rate, p, in.fluidity_excess[q],
      {p_.mu_s, p_.mu_2, p_.I0, p_.solid_density, p_.grain_diameter});
  if (!(m.mu > 0)) return false;  // p <= 0 or no root: the lagged form
  double eta = m.mu * p / rate;
  // eta = mu p / gamma_dot, d gamma_dot / d|D|^2 = 2 / gamma_dot
  double deta_ds = p * (m.dmu_drate * rate - m.mu) / (rate * rate) * 2 / rate;
  double deta_dp = (m.mu + p * m.dmu_dp) / rate;
  cap_viscosity(p_, eta, deta_ds, deta_dp);
  out.viscosity[q] = eta;
  out.deta_dstrain_sq[q] = deta_ds;
  out.deta_dpressure[q] = deta_dp;
  out.friction[q] = m.mu;  // the step's own stress ratio (g_loc of the next table)
  return true;
}

}  // namespace grainlift::continuum::internal
