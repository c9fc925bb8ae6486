// Velocity Verlet stages 1 and 3 of the step: the half kick and drift of the grains and the
// intruder, the accelerations from the summed contact forces and the second half kick (fused
// with the next step's half kick and drift inside advance(); see dem_system.cc).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "grainlift/dem/system/dem_system.h"
#include "step/simd_target.h"
#include "step/step_kernels.h"

namespace grainlift::dem {

namespace {
/// The bits of a double (a comparison that tells -0.0 from +0.0).
inline std::uint64_t bits(double v) {
  std::uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}
/// The pair-force sum of grain @p i shared by a team's threads, added to @p fx, @p fy, @p qs
/// (+0.0 on entry): the pairs where i is the partner (by pair index), then i's own row, the
/// order in which range_forces sums the others.
inline void gather_shared_sum(int i, const NeighborList& nl, double& fx, double& fy,
                              double& qs) {
  for (std::int64_t s = nl.rfirst[i]; s < nl.rfirst[i + 1]; ++s) {
    const std::int64_t k = nl.rpair[s];
    fx -= nl.fx[k];
    fy -= nl.fy[k];
    qs += nl.q[k];
  }
  for (std::int64_t k = nl.first[i]; k < nl.first[i + 1]; ++k) {
    fx += nl.fx[k];
    fy += nl.fy[k];
    qs += nl.q[k];
  }
}

/// The second half kick v(t+dt) = (v + h a) damp of grain @p i with accelerations (axn, ayn,
/// aln); with @p kDrift also the next step's half kick and drift (the same operations as
/// drift_rows), its squared displacement since the list build raising @p maxd2. A grain in
/// free flight keeps its velocity bit for bit: no store, no dirty cache line.
template <bool kDrift>
inline void second_kick(const detail::PlainKick& k, int i, double axn, double ayn, double aln,
                        double& maxd2) {
  const double h = k.h, damp = k.damp;
  double vxi = (k.vx[i] + h * axn) * damp;
  double vyi = (k.vy[i] + h * ayn) * damp;
  double wi = (k.w[i] + h * aln) * damp;
  if (kDrift) {
    vxi += h * axn;
    vyi += h * ayn;
    wi += h * aln;
    double xi = k.x[i] + k.dt * vxi, yi = k.y[i] + k.dt * vyi;
    k.box.wrap(xi, yi);
    k.x[i] = xi;
    k.y[i] = yi;
    double dx = xi - k.xb[i], dy = yi - k.yb[i];
    k.box.min_image(dx, dy);
    const double d2 = dx * dx + dy * dy;
    if (d2 > maxd2) maxd2 = d2;
  }
  if (bits(k.vx[i]) != bits(vxi)) k.vx[i] = vxi;
  if (bits(k.vy[i]) != bits(vyi)) k.vy[i] = vyi;
  if (bits(k.w[i]) != bits(wi)) k.w[i] = wi;
}
}  // namespace

template <DemSystem::Kick kMode>
double DemSystem::finish_impl(int lo, int hi) {
  const double dt = opt_.dt, h = 0.5 * dt;
  const double gx = opt_.gravity[0], gy = opt_.gravity[1];
  const double damp = damping_rate_ > 0 ? std::exp(-damping_rate_ * dt) : 1.0;
  const PeriodicBox box = opt_.box;
  const int* slot = ic_slot_.data();
  std::uint8_t* touched = touched_.data();
  std::uint8_t* flags = grain_flags_.data();
  double* sfxy = fxy_.data();
  double* sq = tq_.data();
  const double* icfx = ic_.fx.data();
  const double* icfy = ic_.fy.data();
  const double* icft = ic_.ft.data();
  double* __restrict px = p_.x.data();
  double* __restrict py = p_.y.data();
  double* __restrict vx = p_.vx.data();
  double* __restrict vy = p_.vy.data();
  double* __restrict w = p_.w.data();
  double* __restrict ax = p_.ax.data();
  double* __restrict ay = p_.ay.data();
  double* __restrict al = p_.alpha.data();
  const double* r = p_.r.data();
  const double* inv_m = p_.inv_m.data();
  const double* inv_i = p_.inv_i.data();
  const float* xb = p_.x_build.data();
  const float* yb = p_.y_build.data();
  // The accelerations of a grain with no contact at all (no touching pair, not touching the
  // intruder), bit for bit what the general expressions give for zero forces: fx = +0.0,
  // so fx / m + gx = +0.0 + gx; torque -r (+0.0) = -0.0, so alpha = -0.0 (m, r, 1/m and 1/I
  // are positive and finite, checked by set_bodies).
  const double ax0 = 0.0 + gx, ay0 = 0.0 + gy, al0 = -0.0;
  double maxd2 = 0;
  // Runs of eight grains without any force by the vector loop (the same operations), the
  // others one by one, a group of eight at a time.
  const bool simd = kMode != Kick::first && detail::vector_enabled();
  const std::uint8_t* dormant = sleep_active_ ? dormant_.data() : nullptr;
  detail::PlainKick plain{px,  py,    vx,    vy,    w,   xb,  yb,  flags, touched, dormant,
                          dt,  h,     damp,  ax0,   ay0, al0, sfxy,  sq,      inv_m,
                          inv_i, r,   ax,    ay,    al,  gx,  gy,  kCandidate, kAccelSet, box};
  for (int i = lo; i < hi;) {
    if (simd) {
      const int stop = detail::kick_plain(plain, kMode == Kick::drift, i, hi, maxd2);
      if (stop != i) {
        i = stop;
        continue;
      }
    }
    const int group_end = simd ? std::min(hi, i + 8) : hi;
    for (; i < group_end; ++i) {
    if (dormant && dormant[i]) continue;  // asleep: the kick leaves its bits (sleeping.cc)
    double axn, ayn, aln;
    const std::uint8_t fl = flags[i];
    if (!touched[i] && !(fl & kCandidate)) {
      axn = ax0;
      ayn = ay0;
      aln = al0;
      if (fl & kAccelSet) {
        ax[i] = axn;
        ay[i] = ayn;
        al[i] = aln;
        flags[i] = static_cast<std::uint8_t>(fl & ~kAccelSet);
      }
    } else {
    // a grain with no touching pair has exactly zero pair force (+0.0, as the sums below)
    double fx = 0, fy = 0, qs = 0;
    if (touched[i]) {
      // the sums of this step (range_forces, or gathered by finish_rows); zeroed for the next
      touched[i] = 0;
      fx = sfxy[2 * i];
      fy = sfxy[2 * i + 1];
      qs = sq[i];
      sfxy[2 * i] = sfxy[2 * i + 1] = sq[i] = 0;
    }
    double tq = -r[i] * qs;
    if (fl & kCandidate) {
      const int c = slot[i];
      fx += icfx[c];
      fy += icfy[c];
      tq -= r[i] * icft[c];  // n x F_t = ft for F_t = ft (-n_y, n_x)
    }
    axn = fx * inv_m[i] + gx;
    ayn = fy * inv_m[i] + gy;
    aln = tq * inv_i[i];
    ax[i] = axn;
    ay[i] = ayn;
    al[i] = aln;
    flags[i] = static_cast<std::uint8_t>(fl | kAccelSet);
    }
    if (kMode == Kick::first) continue;
    second_kick<kMode == Kick::drift>(plain, i, axn, ayn, aln, maxd2);
    }
  }
  return maxd2;
}

double DemSystem::finish_rows(int lo, int hi, Kick mode, bool team) {
  if (team) {
    // A shared grain's sums, from its stored pair forces, where the pair loop puts any other
    // grain's (which it leaves at zero for a shared one): the kick then handles it as any
    // touched grain, in the vector loop too, with the same bits.
    auto it = std::lower_bound(shared_rows_.begin(), shared_rows_.end(), lo);
    for (; it != shared_rows_.end() && *it < hi; ++it) {
      const auto u = static_cast<std::size_t>(*it);
      if (touched_[u]) gather_shared_sum(*it, nl_, fxy_[2 * u], fxy_[2 * u + 1], tq_[u]);
    }
  }
  if (mode == Kick::drift) return finish_impl<Kick::drift>(lo, hi);
  if (mode == Kick::sync) return finish_impl<Kick::sync>(lo, hi);
  return finish_impl<Kick::first>(lo, hi);
}

double DemSystem::drift_rows(int lo, int hi) {
  const double dt = opt_.dt, h = 0.5 * dt;
  const PeriodicBox box = opt_.box;
  ParticleArrays& p = p_;
  double maxd2 = 0;
  for (int i = lo; i < hi; ++i) {
    p.vx[i] += h * p.ax[i];
    p.vy[i] += h * p.ay[i];
    p.w[i] += h * p.alpha[i];
    double xi = p.x[i] + dt * p.vx[i], yi = p.y[i] + dt * p.vy[i];
    box.wrap(xi, yi);
    p.x[i] = xi;
    p.y[i] = yi;
    double dx = xi - p.x_build[i], dy = yi - p.y_build[i];
    box.min_image(dx, dy);
    const double d2 = dx * dx + dy * dy;
    if (d2 > maxd2) maxd2 = d2;
  }
  return maxd2;
}

double DemSystem::drift_intruder() {
  if (!intruder_.present) return 0;
  const double dt = opt_.dt;
  const PeriodicBox& box = opt_.box;
  double xi = intruder_.x + dt * intruder_.vx, yi = intruder_.y + dt * intruder_.vy;
  box.wrap(xi, yi);
  intruder_.x = xi;
  intruder_.y = yi;
  double dx = xi - intruder_.x_build, dy = yi - intruder_.y_build;
  box.min_image(dx, dy);
  return std::sqrt(dx * dx + dy * dy);
}

double DemSystem::drift_item(int c, double& idisp) {
  if (c == 0) {
    idisp = drift_intruder();
    return 0;
  }
  const int lo = (c - 1) * kChunkRows;
  return drift_rows(lo, std::min(n_grains_, lo + kChunkRows));
}


}  // namespace grainlift::dem
