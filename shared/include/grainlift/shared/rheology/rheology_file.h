// The fitted rheology of one grain material as a small TOML file: the mu(I) and Phi(I) laws
// with their uncertainties, where they came from, and the measured points they were fitted to.
// Written by the calibration, read by whoever wants "the same material" in the continuum.
//
//   [source]                 free strings: grains, date, grainlift_version, ...
//   [mu_i]                   mu_s, mu_2, I0, *_err, covariance (3x3), chi2_per_dof, points,
//                            I_min, I_max (range of the data: the law is measured there only)
//   [phi_i]                  phi_max, a, *_err, chi2_per_dof, points
//   [[point]]                I, mu, mu_stderr, phi, phi_stderr (one table per measurement)
//   [wall]                   optional: the grains' friction at an intruder's surface, friction
//                            (constant), mu_a, mu_b, v0 (slip law), *_err, chi2_per_dof, points
//   [nonlocal]               optional: the cooperativity amplitude A of the nonlocal fluidity,
//                            amplitude, amplitude_err, chi2_per_dof, points, mu_min, mu_max
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "grainlift/shared/rheology/rheology_fit.h"

namespace grainlift {

/// The grains' wall law at an intruder's surface, measured on DEM runs (studies/wall_law/):
/// the effective Coulomb friction and the slip law
/// mu_w(v) = mu_a + (mu_b - mu_a) |v| / (|v| + v0), v the slip speed (m/s). Errors one sigma.
struct WallLaw {
  double friction = 0, friction_err = 0;  ///< effective constant friction, sum|s_t| / sum s_n
  double mu_a = 0, mu_a_err = 0;          ///< friction of a surface that does not slip
  double mu_b = 0, mu_b_err = 0;          ///< friction of a fast slip
  double v0 = 0, v0_err = 0;              ///< m/s, slip speed half-way from mu_a to mu_b
  double chi2_per_dof = 0;
  int points = 0;  ///< (slip, friction) pairs the law was fitted to
};

/// The amplitude A of the nonlocal fluidity's cooperativity length xi = A d / sqrt|mu - mu_s|,
/// measured on a creeping layer of the grains (cooperativity_fit.h). Errors one sigma.
struct Cooperativity {
  double amplitude = 0, amplitude_err = 0;
  double chi2_per_dof = 0;
  int points = 0;                  ///< shear rates the line was fitted to
  double mu_min = 0, mu_max = 0;   ///< range of mu = tau / p over them
};

/// Everything a rheology file holds.
struct RheologyFile {
  std::map<std::string, std::string> source;  ///< free strings (grains, date, grainlift_version)
  MuIFit mu_i;                                ///< message and converged are not stored
  double I_min = 0, I_max = 0;                ///< range of I of the points mu_i was fitted to
  PhiFit phi_i;
  std::vector<ShearPoint> points;             ///< the measurements
  std::optional<WallLaw> wall;                ///< the [wall] table, when the file has one
  std::optional<Cooperativity> nonlocal;      ///< the [nonlocal] table, when the file has one
};

/// @brief Fits mu(I) and Phi(I) to @p points and fills a RheologyFile (I_min, I_max from the
/// points; source["grainlift_version"] added when absent).
/// @throws std::invalid_argument as fit_mu_i / fit_phi_i do; RunError when mu(I) did not converge.
RheologyFile make_rheology_file(const std::vector<ShearPoint>& points,
                                std::map<std::string, std::string> source);

/// @brief Writes @p data to @p path atomically (temporary file + rename), every number with 17
/// significant digits so that reading it back gives the same doubles.
/// @throws InputError naming the key when @p data would not pass read_rheology_file's checks;
///         RunError when the file cannot be written.
void write_rheology_file(const std::string& path, const RheologyFile& data);

/// @brief The text write_rheology_file() writes (checked the same way; @p path names the file
/// in an error).
std::string rheology_file_text(const RheologyFile& data, const std::string& path);

/// @brief Reads and validates a rheology file: every number finite, 0 <= mu_s < mu_2, I0 > 0,
/// errors >= 0, 0 < I_min <= I_max, 0 < phi_max <= 1, stderr of each point > 0; an optional
/// [wall] table with 0 <= friction, mu_a, mu_b, v0 > 0, errors >= 0, points >= 4; an optional
/// [nonlocal] table with amplitude > 0, its error >= 0, points >= 3, 0 <= mu_min <= mu_max.
/// @throws InputError naming the file, the key and the accepted range (or the TOML error).
RheologyFile read_rheology_file(const std::string& path);

/// @brief Whether @p path is meant as a rheology file rather than a case: valid TOML with a
/// [mu_i] table and no [domain] (used by `grainlift validate` to check each kind as its own).
bool is_rheology_file(const std::string& path);

}  // namespace grainlift
