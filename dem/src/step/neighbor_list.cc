// Cell list + Verlet half list. Rows are built in contiguous per-thread blocks and
// concatenated in row order, so the layout is independent of the thread count.
#include "grainlift/dem/step/neighbor_list.h"

#include <algorithm>
#include <cmath>

#include <omp.h>

namespace grainlift::dem {

void NeighborList::clear() {
  first.assign(1, 0);
  partner.clear();
  owner.clear();
  sx.clear();
  sy.clear();
  fx.clear();
  fy.clear();
  q.clear();
  rfirst.clear();
  rpair.clear();
  n_mobile_ = 0;
}

void NeighborList::build(const PeriodicBox& box, const double* x, const double* y,
                         const double* r, int n_mobile, int n_total, double skin, int threads) {
  // ---- keep the old rows for the history merge
  old_first_.swap(first);
  old_partner_.swap(partner);
  old_sx_.swap(sx);
  old_sy_.swap(sy);
  const int old_rows = n_mobile_;
  n_mobile_ = n_mobile;
  const CellGrid grid = bin_disks(box, x, y, r, n_total, skin);
  // ---- rows, per thread block
  const int nt = std::max(1, threads);
  thread_partner_.resize(nt);
  thread_count_.resize(nt);
  // rows [lo, hi) of thread t of nth
  auto rows = [&](int t, int nth) {
    const int lo = static_cast<int>(static_cast<std::int64_t>(n_mobile) * t / nth);
    const int hi = static_cast<int>(static_cast<std::int64_t>(n_mobile) * (t + 1) / nth);
    list_rows(box, grid, x, y, r, skin, t, lo, hi);
  };
  // one thread: no OpenMP region at all (a region started from a thread that is not OpenMP's,
  // such as a --replicas worker, would bind that thread to the first place under OMP_PROC_BIND)
  if (nt == 1) {
    rows(0, 1);
  } else {
#pragma omp parallel num_threads(nt)
    rows(omp_get_thread_num(), omp_get_num_threads());
  }
  concatenate_rows(n_mobile, nt);
  carry_history(old_rows, nt);
  build_reverse_index(n_total);
}

NeighborList::CellGrid NeighborList::bin_disks(const PeriodicBox& box, const double* x,
                                               const double* y, const double* r, int n_total,
                                               double skin) {
  double rmax = 0;
  double bxmin = box.xmin, bxmax = box.xmax, bymin = box.ymin, bymax = box.ymax;
  for (int i = 0; i < n_total; ++i) {
    rmax = std::max(rmax, r[i]);
    if (!box.periodic_x) {
      bxmin = std::min(bxmin, x[i]);
      bxmax = std::max(bxmax, x[i]);
    }
    if (!box.periodic_y) {
      bymin = std::min(bymin, y[i]);
      bymax = std::max(bymax, y[i]);
    }
  }
  const double cell = std::max(2.0 * rmax + skin, 1e-300);
  const double wx = bxmax - bxmin, wy = bymax - bymin;
  CellGrid g;
  g.xmin = bxmin;
  g.ymin = bymin;
  g.ncx = std::max(1, std::min(4096, static_cast<int>(std::floor(wx / cell))));
  g.ncy = std::max(1, std::min(4096, static_cast<int>(std::floor(wy / cell))));
  g.hx = wx / g.ncx;
  g.hy = wy / g.ncy;
  const int ncell = g.ncx * g.ncy;
  cell_start_.assign(static_cast<std::size_t>(ncell) + 1, 0);
  cell_of_.resize(n_total);
  for (int i = 0; i < n_total; ++i) {
    int cx = static_cast<int>(std::floor((x[i] - bxmin) / g.hx));
    int cy = static_cast<int>(std::floor((y[i] - bymin) / g.hy));
    cx = std::min(std::max(cx, 0), g.ncx - 1);
    cy = std::min(std::max(cy, 0), g.ncy - 1);
    cell_of_[i] = cy * g.ncx + cx;
    ++cell_start_[cell_of_[i] + 1];
  }
  for (int c = 0; c < ncell; ++c) cell_start_[c + 1] += cell_start_[c];
  cell_items_.resize(n_total);
  // counting-sort fill (index order inside each cell)
  cursor_.assign(cell_start_.begin(), cell_start_.end() - 1);
  for (int i = 0; i < n_total; ++i) cell_items_[cursor_[cell_of_[i]]++] = i;
  return g;
}

void NeighborList::list_rows(const PeriodicBox& box, const CellGrid& g, const double* x,
                             const double* y, const double* r, double skin, int t, int lo,
                             int hi) {
  const int ncx = g.ncx, ncy = g.ncy;
  // local vectors (swapped in and out, keeping their capacity): the headers of neighbouring
  // threads' vectors share a cache line, which every push_back would bounce between cores
  std::vector<int> out;
  std::vector<std::int64_t> counts;
  out.swap(thread_partner_[t]);
  counts.swap(thread_count_[t]);
  out.clear();
  counts.clear();
  for (int i = lo; i < hi; ++i) {
    const int c = cell_of_[i];
    const int cx = c % ncx, cy = c / ncx;
    const std::size_t row_begin = out.size();
    for (int oy = -1; oy <= 1; ++oy) {
      int ky = cy + oy;
      if (ky < 0 || ky >= ncy) {
        if (!box.periodic_y) continue;
        ky = (ky + ncy) % ncy;
      }
      for (int ox = -1; ox <= 1; ++ox) {
        int kx = cx + ox;
        if (kx < 0 || kx >= ncx) {
          if (!box.periodic_x) continue;
          kx = (kx + ncx) % ncx;
        }
        const int k = ky * ncx + kx;
        for (int s = cell_start_[k]; s < cell_start_[k + 1]; ++s) {
          const int j = cell_items_[s];
          if (j <= i) continue;
          double dx = x[i] - x[j], dy = y[i] - y[j];
          box.min_image(dx, dy);
          const double cut = r[i] + r[j] + skin;
          if (dx * dx + dy * dy < cut * cut) out.push_back(j);
        }
      }
    }
    // sort the row by j and drop duplicates (small grids visit a cell twice)
    std::sort(out.begin() + row_begin, out.end());
    out.erase(std::unique(out.begin() + row_begin, out.end()), out.end());
    counts.push_back(static_cast<std::int64_t>(out.size() - row_begin));
  }
  out.swap(thread_partner_[t]);
  counts.swap(thread_count_[t]);
}

void NeighborList::concatenate_rows(int n_mobile, int nt) {
  first.resize(static_cast<std::size_t>(n_mobile) + 1);
  first[0] = 0;
  int row = 0;
  for (int t = 0; t < nt; ++t) {
    for (std::int64_t c : thread_count_[t]) {
      first[row + 1] = first[row] + c;
      ++row;
    }
  }
  const std::size_t np = static_cast<std::size_t>(first[n_mobile]);
  partner.resize(np);
  std::size_t pos = 0;
  for (int t = 0; t < nt; ++t) {
    std::copy(thread_partner_[t].begin(), thread_partner_[t].end(), partner.begin() + pos);
    pos += thread_partner_[t].size();
  }
  owner.resize(np);
  for (int i = 0; i < n_mobile; ++i) {
    for (std::int64_t k = first[i]; k < first[i + 1]; ++k) owner[k] = i;
  }
  sx.assign(np, 0.0);
  sy.assign(np, 0.0);
  fx.assign(np, 0.0);
  fy.assign(np, 0.0);
  q.assign(np, 0.0);
}

void NeighborList::carry_history(int old_rows, int nt) {
  const int merge_rows = std::min(old_rows, n_mobile_);
  auto merge_row = [&](int i) {
    std::int64_t a = old_first_[i];
    const std::int64_t ae = old_first_[i + 1];
    for (std::int64_t b = first[i]; b < first[i + 1] && a < ae; ++b) {
      while (a < ae && old_partner_[a] < partner[b]) ++a;
      if (a < ae && old_partner_[a] == partner[b]) {
        sx[b] = old_sx_[a];
        sy[b] = old_sy_[a];
      }
    }
  };
  if (!old_partner_.empty() && nt == 1) {
    for (int i = 0; i < merge_rows; ++i) merge_row(i);
  } else if (!old_partner_.empty()) {
#pragma omp parallel for schedule(static) num_threads(nt)
    for (int i = 0; i < merge_rows; ++i) merge_row(i);
  }
}

void NeighborList::build_reverse_index(int n_total) {
  const std::size_t np = partner.size();
  rfirst.assign(static_cast<std::size_t>(n_total) + 1, 0);
  for (std::size_t k = 0; k < np; ++k) ++rfirst[partner[k] + 1];
  for (int j = 0; j < n_total; ++j) rfirst[j + 1] += rfirst[j];
  rpair.resize(np);
  rcursor_.assign(rfirst.begin(), rfirst.end() - 1);
  for (int i = 0; i < n_mobile_; ++i) {
    for (std::int64_t k = first[i]; k < first[i + 1]; ++k) rpair[rcursor_[partner[k]]++] = k;
  }
}

void NeighborList::renumber(const std::vector<int>& new_of_old) {
  const int n = n_mobile_;
  if (n == 0) return;  // no list yet: no history to renumber
  const std::size_t np = partner.size();
  auto renamed = [&](int b) { return b < n ? new_of_old[static_cast<std::size_t>(b)] : b; };
  std::vector<std::int64_t> nfirst(static_cast<std::size_t>(n) + 1, 0);
  for (int i = 0; i < n; ++i) {
    for (std::int64_t k = first[i]; k < first[i + 1]; ++k) {
      const int a = renamed(i), b = renamed(partner[k]);
      ++nfirst[static_cast<std::size_t>(std::min(a, b)) + 1];
    }
  }
  for (int i = 0; i < n; ++i) nfirst[i + 1] += nfirst[i];
  std::vector<std::int64_t> at(nfirst.begin(), nfirst.end() - 1);
  std::vector<int> npartner(np), nowner(np);
  std::vector<double> nsx(np), nsy(np);
  for (int i = 0; i < n; ++i) {
    for (std::int64_t k = first[i]; k < first[i + 1]; ++k) {
      const int a = renamed(i), b = renamed(partner[k]);
      const bool turned = b < a;
      const auto m = static_cast<std::size_t>(at[static_cast<std::size_t>(turned ? b : a)]++);
      nowner[m] = turned ? b : a;
      npartner[m] = turned ? a : b;
      // 0.0 - s: -s for a spring, +0.0 (not -0.0) for none
      nsx[m] = turned ? 0.0 - sx[k] : sx[k];
      nsy[m] = turned ? 0.0 - sy[k] : sy[k];
    }
  }
  // each row by partner (rows hold a few pairs: insertion sort)
  for (int i = 0; i < n; ++i) {
    for (std::int64_t k = nfirst[i] + 1; k < nfirst[i + 1]; ++k) {
      for (std::int64_t m = k; m > nfirst[i] && npartner[m - 1] > npartner[m]; --m) {
        std::swap(npartner[m - 1], npartner[m]);
        std::swap(nsx[m - 1], nsx[m]);
        std::swap(nsy[m - 1], nsy[m]);
      }
    }
  }
  first.swap(nfirst);
  partner.swap(npartner);
  owner.swap(nowner);
  sx.swap(nsx);
  sy.swap(nsy);
  for (auto* v : {&fx, &fy, &q}) v->assign(np, 0.0);
  build_reverse_index(static_cast<int>(rfirst.size()) - 1);
}

std::size_t NeighborList::drop_dormant_pairs(const std::uint8_t* dormant) {
  const std::size_t np = partner.size();
  std::size_t out = 0;
  std::int64_t row_begin = 0;
  for (int i = 0; i < n_mobile_; ++i) {
    const std::int64_t b = first[i], e = first[i + 1];
    first[i] = row_begin;
    for (std::int64_t k = b; k < e; ++k) {
      if (dormant[i] && dormant[partner[k]]) continue;
      partner[out] = partner[k];
      owner[out] = i;
      sx[out] = sx[k];
      sy[out] = sy[k];
      fx[out] = fx[k];
      fy[out] = fy[k];
      q[out] = q[k];
      ++out;
    }
    row_begin = static_cast<std::int64_t>(out);
  }
  first[n_mobile_] = row_begin;
  for (auto* v : {&sx, &sy, &fx, &fy, &q}) v->resize(out);
  partner.resize(out);
  owner.resize(out);
  build_reverse_index(static_cast<int>(rfirst.size()) - 1);
  return np - out;
}

}  // namespace grainlift::dem
