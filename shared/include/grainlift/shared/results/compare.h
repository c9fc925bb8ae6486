// Differences between two result files (A is the reference): relative differences of drag,
// lift and torque, and L2 / max differences of sigma_n(theta), sigma_t(theta) normalised by a
// stated pressure scale.
#pragma once

#include <optional>
#include <string>

#include "grainlift/shared/results/json_writer.h"
#include "grainlift/shared/results/run_result.h"

namespace grainlift {

struct Comparison {
  std::string solver_a, solver_b;
  std::optional<double> drag_rel, lift_rel, torque_rel;  ///< (B - A) / |A|; absent when A == 0
  double drag_a = 0, drag_b = 0, lift_a = 0, lift_b = 0, torque_a = 0, torque_b = 0;
  bool have_means = false;
  bool have_surface = false;
  double pressure_scale = 0;        ///< Pa, the scale the stress differences are divided by
  std::string pressure_scale_from;  ///< which file / rule gave it
  double sigma_n_l2 = 0, sigma_n_max = 0, sigma_t_l2 = 0, sigma_t_max = 0;  ///< / pressure_scale
  /// The same L2 and max differences of the symmetric and antisymmetric parts
  /// (symmetry_split) of the difference B - A, / pressure_scale. The drag comes from the
  /// symmetric sigma_n and antisymmetric sigma_t, the lift and torque from the other two.
  double sigma_n_symmetric_l2 = 0, sigma_n_symmetric_max = 0;
  double sigma_n_antisymmetric_l2 = 0, sigma_n_antisymmetric_max = 0;
  double sigma_t_symmetric_l2 = 0, sigma_t_symmetric_max = 0;
  double sigma_t_antisymmetric_l2 = 0, sigma_t_antisymmetric_max = 0;
  /// The error of each side's drag, lift, torque: its standard error (a DEM's block average),
  /// else its mesh-error estimate (a FEM's /diagnostics *_mesh_error: the change from the next
  /// coarser level); absent when the file has neither.
  std::optional<double> drag_err_a, drag_err_b, lift_err_a, lift_err_b, torque_err_a,
      torque_err_b;
  std::string error_kind_a, error_kind_b;  ///< "standard error", "mesh-error estimate" or "none"
  /// (B - A) / sqrt(err_A^2 + err_B^2), the difference in units of the combined error (a
  /// missing error counts 0); absent when neither side has an error or the combined error is 0.
  std::optional<double> drag_z, lift_z, torque_z;
};

/// @brief Compare B against A. B's surface distribution is interpolated (periodic, linear) onto
/// A's angle grid, the shared grid theta_m on which theta_{M-1-m} = -theta_m, where the
/// difference is split into its symmetric and antisymmetric parts. The pressure scale is A's
/// geometry.pressure_scale, else B's, else max |sigma_n| of A.
Comparison compare_results(const RunResult& a, const RunResult& b);

/// The comparison as a JSON object (numbers; null where a quantity is absent).
JsonObject comparison_object(const Comparison& c);
/// comparison_object serialised; @p indent > 0 pretty-prints.
std::string comparison_json(const Comparison& c, int indent = 0);
/// The comparison as a short human-readable table.
std::string comparison_text(const Comparison& c);

}  // namespace grainlift
