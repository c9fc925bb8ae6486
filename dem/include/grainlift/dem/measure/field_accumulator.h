// Coarse-grained fields in the intruder frame (Kumar 2019 appendix, eq. A3-A7) and the
// contact stress tensor, accumulated over snapshots. Reads the system, never changes it.
#pragma once

#include <cstdint>
#include <vector>

#include "grainlift/dem/dem_config.h"
#include "grainlift/dem/dem_output.h"
#include "grainlift/dem/system/dem_system.h"

namespace grainlift::dem {

/// The sums of a FieldAccumulator over its snapshots so far (a checkpoint keeps them).
struct FieldSums {
  std::int32_t snapshots = 0;
  std::vector<double> gamma, gvx, gvy, gv2, sxx, sxy, syy;
};

class FieldAccumulator {
 public:
  /// @brief Grid of spec.nx x spec.ny square bins of side spec.spacing (m), lower-left corner
  /// (spec.x0, spec.y0) relative to the intruder centre, axes of the lab frame.
  explicit FieldAccumulator(const FieldGridSpec& spec);

  /// @brief Add one snapshot of the current state of s.
  ///
  /// Each disk adds, to each bin it covers, Gamma = its area inside the bin (h^2 when the bin
  /// lies inside the disk, else counted on 10 x 10 sub-bins as in Kumar's appendix) with the
  /// velocity of the disk's material point at the bin centre relative to the intruder,
  /// v* = v_i + omega_i z x (r* - r_i) - V (eq. A1-A2). Each contact adds -f (x) l / h^2 to the
  /// bin holding the midpoint of its branch vector l (from partner centre to the disk centre;
  /// f the force on the disk), symmetrised (tension positive, so compression is negative).
  void add_snapshot(const DemSystem& s);

  /// @brief Averages over the snapshots: area fraction (A6), Gamma-weighted velocity (A3-A4),
  /// granular temperature (A7), mean contact stress. Bins no grain ever covered report 0.
  FieldAverages finish() const;

  int snapshots() const { return snapshots_; }

  /// The sums so far.
  FieldSums sums() const {
    return {snapshots_, gamma_, gvx_, gvy_, gv2_, sxx_, sxy_, syy_};
  }
  /// @brief Go on from saved sums. @throws ConfigError when their grid is not this one.
  void restore(const FieldSums& s);

 private:
  void add_stress(double mx, double my, double fx, double fy, double lx, double ly);
  FieldGridSpec spec_;
  int snapshots_ = 0;
  std::vector<double> gamma_, gvx_, gvy_, gv2_, sxx_, sxy_, syy_;
};

}  // namespace grainlift::dem
