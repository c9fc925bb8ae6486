// Entry point of the continuum (finite-element) engine. deal.II-free.
#pragma once

#include <array>
#include <functional>
#include <string>

#include "grainlift/continuum/continuum_config.h"

namespace grainlift::continuum {

/// @brief Solve the steady 2D incompressible mu(I) flow around a translating, spinning cylinder.
///
/// The problem is posed in the intruder frame (intruder centred at the origin): the far field
/// moves at -V, the intruder surface at omega x r. See docs/continuum-model.md for the model,
/// the boundary conditions and the numerics.
///
/// @param config  case description (SI units, see continuum_config.h)
/// @param log     optional sink for one-line progress messages (nonlinear iterations etc.)
/// @return forces, surface stresses, sampled fields and convergence information. A run that
///         does not converge returns converged = false and a message (not an exception).
/// @throws ConfigError when a configuration value is out of range.
/// @throws SolverError when the solve fails with an exception (a bug, a failed factorisation,
///         memory): an error, not a non-convergence. On several MPI ranks it is thrown only
///         when every rank failed together; a failure of one rank alone ends all ranks
///         (MpiSession::all_ranks_failed).
ContinuumOutput solve_flow(const ContinuumConfig& config,
                           const std::function<void(const std::string&)>& log = {});

/// The mesh solve_flow() makes for a configuration, without solving: where its edges are
/// (m, relative to the intruder's centre) and whether its x ends match as periodic faces.
struct MeshOutline {
  double xmin = 0, xmax = 0, ymin = 0, ymax = 0;  ///< bounding box of the vertices
  /// each edge's position from its boundary faces: x of the left and right faces, y of the
  /// bottom and top faces (the mean over the faces; their spread in edge_spread)
  std::array<double, 4> edge{};
  double edge_spread = 0;      ///< largest deviation of a boundary face from its edge's position
  int left_faces = 0, right_faces = 0;
  /// left faces with a right face at the same y one period (xmax - xmin) away, and the largest
  /// y mismatch of those pairs (m)
  int periodic_pairs = 0;
  double periodic_mismatch = 0;
  double hole_radius_error = 0;  ///< largest |r - R| of the hole's vertices (m)
  int cells = 0;
};
MeshOutline mesh_outline(const ContinuumConfig& config);

/// @brief Check a configuration without solving. @throws ConfigError naming the bad field.
void validate_config(const ContinuumConfig& config);

}  // namespace grainlift::continuum
