// Quantities derived from a solver's result by the definitions of docs/conventions.md, computed
// once here for summary.json, the /derived group of the HDF5 file and `compare`, so that
// scripts only draw.
#pragma once

#include <optional>
#include <vector>

#include "grainlift/shared/results/run_result.h"

namespace grainlift {

struct DerivedQuantities {
  double spin_ratio = 0;                     ///< Omega = omega R / |V| (Kumar eq. 4); 0 if V = 0
  std::optional<double> lift_over_drag;      ///< L / D (when D != 0)
  /// N/m, 2D buoyancy B = rho g pi D^2 / 4 with g = Geometry::reference_gravity (the lid's g in
  /// lid_only mode, where B only normalises: the grains feel no gravity)
  std::optional<double> buoyancy;
  std::optional<double> lift_over_buoyancy;  ///< L / B
  /// C_d = D / (rho g h D_intruder) with h = Geometry::equivalent_depth (Guillard et al. 2014,
  /// Sec. III); set when h > 0
  std::optional<double> drag_coefficient;
  /// Symmetric (s(theta) + s(-theta))/2 and antisymmetric (s(theta) - s(-theta))/2 parts of
  /// the surface stresses about the axis of motion (Pa); empty without a surface distribution.
  std::vector<double> sigma_n_symmetric, sigma_n_antisymmetric;
  std::vector<double> sigma_t_symmetric, sigma_t_antisymmetric;
};

/// @brief The derived quantities of @p r (its geometry, means and surface distribution).
DerivedQuantities derive(const RunResult& r);

}  // namespace grainlift
