// Broad search: cell list + Verlet half list with a skin, holding the per-contact history.
#pragma once

#include <cstdint>
#include <vector>

#include "grainlift/dem/periodic_box.h"

namespace grainlift::dem {

/// Verlet half list in CSR form. Pairs (i, j) with i mobile (i < n_mobile) and j > i
/// (frozen disks sit at indices >= n_mobile), kept when |x_i - x_j| < r_i + r_j + skin.
/// Each row is sorted by j, so the tangential history of a pair that survives a rebuild is
/// carried over by a merge of the old and new rows. Per-pair outputs (force on i, n x F_t)
/// are written by the force loop (pair_forces.cc) and summed per particle at the kick
/// (velocity_verlet.cc) in pair order, through rfirst/rpair for the partners: results do
/// not depend on the thread count.
class NeighborList {
 public:
  /// @brief Rebuild the list from wrapped positions and carry the history over.
  /// @param skin m, extra distance kept beyond contact
  void build(const PeriodicBox& box, const double* x, const double* y, const double* r,
             int n_mobile, int n_total, double skin, int threads);

  /// @brief Forget every pair and its history (new set of bodies).
  void clear();

  /// @brief Remove the pairs whose two bodies are both marked in @p dormant (one byte per
  /// body, grains and frozen disks), keeping row order, histories and the reverse index
  /// consistent. Returns the pairs removed. Used for sleeping grains (sleeping.cc): the caller
  /// guarantees such pairs are apart and stay apart while both stay marked.
  std::size_t drop_dormant_pairs(const std::uint8_t* dormant);

  /// @brief Renumber the grains of the list: grain i becomes @p new_of_old[i] (frozen disks
  /// keep theirs). A pair whose new owner would be above its partner turns round, its spring
  /// negated (the displacement of the other body's contact point); rows sorted again by j.
  /// The stored pair forces are dropped (the next force pass writes them).
  void renumber(const std::vector<int>& new_of_old);

  int rows() const { return n_mobile_; }
  std::size_t pairs() const { return partner.size(); }

  std::vector<std::int64_t> first;  ///< row i spans [first[i], first[i+1])
  std::vector<int> partner;         ///< j of each pair
  std::vector<int> owner;           ///< i of each pair (flat loops over pairs)
  std::vector<double> sx, sy;       ///< m, tangential spring of each pair (history)
  std::vector<double> fx, fy;       ///< N, force on i of each pair (0 when not touching)
  std::vector<double> q;            ///< N, n x F_t (torque on i is -r_i q, on j -r_j q)
  std::vector<std::int64_t>
      rfirst;  ///< pairs where particle j is the partner: [rfirst[j], rfirst[j+1])
  std::vector<std::int64_t> rpair;

 private:
  int n_mobile_ = 0;
  // scratch kept between builds so that a rebuild does not allocate in steady state
  std::vector<std::int64_t> old_first_;
  std::vector<int> old_partner_;
  std::vector<double> old_sx_, old_sy_;
  std::vector<int> cell_start_, cell_items_, cell_of_, cursor_;
  std::vector<std::int64_t> rcursor_;
  std::vector<std::vector<int>> thread_partner_;
  std::vector<std::vector<std::int64_t>> thread_count_;
  /// The cell grid of a build: cells at least 2 rmax + skin wide over the box (and every
  /// disk along a direction that is not periodic).
  struct CellGrid {
    double xmin = 0, ymin = 0, hx = 0, hy = 0;
    int ncx = 1, ncy = 1;
  };
  /// Sorts every disk into its cell (cell_of_, cell_start_, cell_items_; index order inside
  /// each cell).
  CellGrid bin_disks(const PeriodicBox& box, const double* x, const double* y, const double* r,
                     int n_total, double skin);
  /// The partners j > i within r_i + r_j + skin of rows [lo, hi), each row sorted by j, into
  /// thread block @p t's scratch (thread_partner_, thread_count_).
  void list_rows(const PeriodicBox& box, const CellGrid& g, const double* x, const double* y,
                 const double* r, double skin, int t, int lo, int hi);
  /// first, partner and owner from the thread blocks in row order; the per-pair arrays zeroed.
  void concatenate_rows(int n_mobile, int nt);
  /// The springs of the pairs that survive from the previous list (rows sorted by j on both
  /// sides) carried over, on @p nt threads.
  void carry_history(int old_rows, int nt);
  /// Fill rfirst/rpair from first/partner (pairs where a body is the partner, in pair order).
  void build_reverse_index(int n_total);
};

}  // namespace grainlift::dem
