// Differences between two result files (A is the reference): relative differences of drag,
// lift and torque, and L2 / max differences of sigma_n(theta), sigma_t(theta) normalised by a
// stated pressure scale.
#pragma once

#include <optional>
#include <string>

#include "grainlift/shared/json_writer.h"
#include "grainlift/shared/run_result.h"

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
};

/// @brief Compare B against A. B's surface distribution is interpolated (periodic, linear) onto
/// A's angle grid. The pressure scale is A's geometry.pressure_scale, else B's, else
/// max |sigma_n| of A.
Comparison compare_results(const RunResult& a, const RunResult& b);

/// The comparison as a JSON object (numbers; null where a quantity is absent).
JsonObject comparison_object(const Comparison& c);
/// comparison_object serialised; @p indent > 0 pretty-prints.
std::string comparison_json(const Comparison& c, int indent = 0);
/// The comparison as a short human-readable table.
std::string comparison_text(const Comparison& c);

}  // namespace grainlift
