// Synchronised velocity-Verlet time step of grains, frozen disks and the intruder.
//
// One step from t to t+dt:
//   1. half kick and drift: v(t+dt/2) = v(t) + dt/2 a(t), x(t+dt) = x(t) + dt v(t+dt/2);
//   2. contact forces at t+dt. The tangential spring grows by the relative displacement of
//      the contact point over the step, dt v(t+dt/2) (exactly the displacement the positions
//      made), and the damping and slip direction use the predicted velocity at the same
//      time level, v(t+dt) ~ v(t+dt/2) + dt/2 a(t). Spring, overlap and velocity in the law
//      are therefore all at t+dt (for the intruder, whose motion is prescribed, they are exact);
//   3. second half kick: v(t+dt) = v(t+dt/2) + dt/2 a(t+dt).
// Without velocity-dependent forces this is plain velocity Verlet (symplectic).
//
// How it runs (advance(n); step() is advance(1)): one OpenMP parallel region per n steps, or
// per list rebuild. Work is handed out in chunks of kChunkRows grains (item 0: the intruder)
// from a shared counter; which thread takes which chunk does not change a bit of the results
// (every per-grain sum is taken in pair order, see chunk_forces and finish_impl). One thread
// runs run_segment (two phases per step); a team runs run_segment_team, where the items of
// all steps form one sequence and wait only for the items they depend on (no team barrier
// inside a segment). Inside advance(), stage 3 of one step and stage 1 of the
// next are one pass over the particle arrays (finish_impl<.., Kick::drift>); the last step
// of a call ends with stage 3 alone, so the state between calls is that of single steps.
#include "grainlift/dem/dem_system.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>

#include <omp.h>
#include <sched.h>
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

#include "grainlift/dem/contact_law_batch.h"
#include "grainlift/dem/errors.h"
#include "step_kernels.h"
#include "team_barrier.h"

namespace grainlift::dem {

namespace {
/// The bits of a double (a comparison that tells -0.0 from +0.0).
inline std::uint64_t bits(double v) {
  std::uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}
}  // namespace

DemSystem::DemSystem(const SystemOptions& options) : opt_(options) {
  law_ = LawCoefficients::from(options.contact);
  mu_ = options.contact.friction;
  mu_intruder_ = options.contact.intruder_friction;
  if (!(opt_.dt > 0)) throw ConfigError("dt must be > 0 s");
  if (opt_.threads < 1) opt_.threads = 1;
  nl_.clear();
}

void DemSystem::set_bodies(const std::vector<Disk>& grains, const std::vector<Disk>& frozen) {
  n_grains_ = static_cast<int>(grains.size());
  n_total_ = n_grains_ + static_cast<int>(frozen.size());
  const std::size_t n = static_cast<std::size_t>(n_total_);
  for (auto* v : {&p_.x, &p_.y, &p_.vx, &p_.vy, &p_.w, &p_.ax, &p_.ay, &p_.alpha, &p_.r,
                  &p_.inv_m, &p_.inv_i, &p_.mass, &fx_, &fy_, &tq_}) {
    v->assign(n, 0.0);
  }
  p_.x_build.assign(n, 0.0f);
  p_.y_build.assign(n, 0.0f);
  touched_.assign(static_cast<std::size_t>(n_grains_), 0);
  // accelerations are 0 now, not the no-force values: mark them all as "set"
  grain_flags_.assign(static_cast<std::size_t>(n_grains_), kAccelSet);
  double rmax = 0;
  for (int i = 0; i < n_total_; ++i) {
    const bool is_grain = i < n_grains_;
    const Disk& d = is_grain ? grains[i] : frozen[i - n_grains_];
    double x = d.x, y = d.y;
    opt_.box.wrap(x, y);
    p_.x[i] = x;
    p_.y[i] = y;
    p_.r[i] = d.r;
    rmax = std::max(rmax, d.r);
    if (is_grain) {
      if (!(d.mass > 0) || !(d.r > 0)) throw ConfigError("every grain needs mass > 0 and radius > 0");
      p_.vx[i] = d.vx;
      p_.vy[i] = d.vy;
      p_.w[i] = d.w;
      p_.mass[i] = d.mass;
      p_.inv_m[i] = 1.0 / d.mass;
      p_.inv_i[i] = 2.0 / (d.mass * d.r * d.r);  // disk: I = m r^2 / 2
      if (!std::isfinite(d.mass) || !std::isfinite(d.r) || !std::isfinite(p_.inv_m[i]) ||
          !std::isfinite(p_.inv_i[i])) {
        throw ConfigError("every grain needs a finite mass, radius, 1/mass and 1/inertia");
      }
    }
  }
  skin_ = opt_.skin > 0 ? opt_.skin : 0.2 * rmax;
  // Below ~kMinGrainsPerThread grains per thread the fork-join costs more than it saves.
  team_ = std::max(1, std::min({opt_.threads, n_grains_ / kMinGrainsPerThread, kMaxTeam}));
  nl_.clear();
  ic_ = IntruderContacts{};
  ic_old_ = IntruderContacts{};
  ic_slot_.assign(static_cast<std::size_t>(n_grains_), -1);
  growth_since_build_ = 0;
  primed_ = false;
}

void DemSystem::set_intruder(double x, double y, double r, double vx, double vy, double omega,
                             double spin_ramp_time) {
  opt_.box.wrap(x, y);
  intruder_.present = true;
  intruder_.x = x;
  intruder_.y = y;
  intruder_.r = r;
  intruder_.vx = vx;
  intruder_.vy = vy;
  intruder_.omega_target = omega;
  intruder_.spin_ramp_time = spin_ramp_time;
  intruder_.t0 = time_;
  primed_ = false;
}

void DemSystem::set_friction(double mu, double mu_intruder) {
  mu_ = mu;
  mu_intruder_ = mu_intruder;
}

void DemSystem::scale_grain_radii(double factor) {
  double rmax = 0;
  for (int i = 0; i < n_grains_; ++i) {
    p_.r[i] *= factor;
    p_.inv_i[i] = 2.0 / (p_.mass[i] * p_.r[i] * p_.r[i]);
    rmax = std::max(rmax, p_.r[i]);
  }
  if (factor > 1) growth_since_build_ += rmax * (1.0 - 1.0 / factor);
  radii_scaled_ = true;  // the pair constants of the list are stale until the next build
}

void DemSystem::zero_velocities() {
  for (int i = 0; i < n_grains_; ++i) p_.vx[i] = p_.vy[i] = p_.w[i] = 0;
}

double DemSystem::take_max_overlap_fraction() {
  const double m = max_overlap_;
  max_overlap_ = 0;
  return m;
}

double DemSystem::kinetic_energy() const {
  double e = 0;
  for (int i = 0; i < n_grains_; ++i) {
    e += 0.5 * p_.mass[i] * (p_.vx[i] * p_.vx[i] + p_.vy[i] * p_.vy[i]) +
         0.5 / p_.inv_i[i] * p_.w[i] * p_.w[i];
  }
  return e;
}

double DemSystem::normal_elastic_energy() const {
  auto spring = [this](double r_eff, double delta) {
    if (law_.law == ContactLaw::kumar2019) return law_.kn * std::sqrt(r_eff * delta);
    return law_.hertz_kn_factor * std::sqrt(r_eff) * std::sqrt(delta);
  };
  double e = 0;
  for (int i = 0; i < n_grains_; ++i) {
    for (std::int64_t k = nl_.first[i]; k < nl_.first[i + 1]; ++k) {
      const int j = nl_.partner[k];
      double dx = p_.x[i] - p_.x[j], dy = p_.y[i] - p_.y[j];
      opt_.box.min_image(dx, dy);
      const double rs = p_.r[i] + p_.r[j];
      const double delta = rs - std::sqrt(dx * dx + dy * dy);
      if (delta > 0) e += 0.4 * spring(p_.r[i] * p_.r[j] / rs, delta) * delta * delta;
    }
  }
  if (intruder_.present) {
    for (int g : ic_.grain) {
      double dx = p_.x[g] - intruder_.x, dy = p_.y[g] - intruder_.y;
      opt_.box.min_image(dx, dy);
      const double rs = p_.r[g] + intruder_.r;
      const double delta = rs - std::sqrt(dx * dx + dy * dy);
      if (delta > 0) e += 0.4 * spring(p_.r[g] * intruder_.r / rs, delta) * delta * delta;
    }
  }
  return e;
}

void DemSystem::build_lists() {
  nl_.build(opt_.box, p_.x.data(), p_.y.data(), p_.r.data(), n_grains_, n_total_, skin_,
            team_);
  // Build positions in float, and a bound on |float(x) - x| for the displacement check (which
  // stays conservative): half an ulp of a float relative to the largest coordinate (grains
  // need not stay in the box along a direction without walls), for both axes.
  double cmax = 0;
  for (int i = 0; i < n_total_; ++i) {
    p_.x_build[i] = static_cast<float>(p_.x[i]);
    p_.y_build[i] = static_cast<float>(p_.y[i]);
    cmax = std::max(cmax, std::max(std::fabs(p_.x[i]), std::fabs(p_.y[i])));
  }
  build_round_ = 2.0 * 0x1.0p-24 * cmax;
  // Intruder candidates: grains within R + r + skin, in index order, history carried over.
  for (int g : ic_.grain) {
    ic_slot_[g] = -1;
    grain_flags_[g] &= static_cast<std::uint8_t>(~kCandidate);
  }
  std::swap(ic_, ic_old_);
  ic_.grain.clear();
  if (intruder_.present) {
    intruder_.x_build = intruder_.x;
    intruder_.y_build = intruder_.y;
    for (int g = 0; g < n_grains_; ++g) {
      double dx = p_.x[g] - intruder_.x, dy = p_.y[g] - intruder_.y;
      opt_.box.min_image(dx, dy);
      const double cut = intruder_.r + p_.r[g] + skin_;
      if (dx * dx + dy * dy < cut * cut) ic_.grain.push_back(g);
    }
  }
  const std::size_t nc = ic_.grain.size();
  ic_.sx.assign(nc, 0.0);
  ic_.sy.assign(nc, 0.0);
  for (auto* v : {&ic_.fx, &ic_.fy, &ic_.fn, &ic_.ft, &ic_.nx, &ic_.ny}) v->assign(nc, 0.0);
  ic_.touching.assign(nc, 0);
  ic_.slipping.assign(nc, 0);
  std::size_t a = 0;
  for (std::size_t b = 0; b < nc; ++b) {
    ic_slot_[ic_.grain[b]] = static_cast<int>(b);
    grain_flags_[ic_.grain[b]] |= kCandidate;
    while (a < ic_old_.grain.size() && ic_old_.grain[a] < ic_.grain[b]) ++a;
    if (a < ic_old_.grain.size() && ic_old_.grain[a] == ic_.grain[b]) {
      ic_.sx[b] = ic_old_.sx[a];
      ic_.sy[b] = ic_old_.sy[a];
    }
  }
  // touching-pair scratch of the force loop, one list per chunk of rows: sized here so that
  // the step does not allocate
  const int nc_rows = chunks();
  touch_.resize(static_cast<std::size_t>(nc_rows));
  touch_prev_.resize(static_cast<std::size_t>(nc_rows));
  for (int c = 0; c < nc_rows; ++c) {
    const int lo = c * kChunkRows, hi = std::min(n_grains_, lo + kChunkRows);
    const auto np = static_cast<std::size_t>(nl_.first[hi] - nl_.first[lo]);
    // room for every pair of the chunk (the screening loop writes before it counts)
    touch_[c].k.resize(np + 1);
    touch_prev_[c].k.resize(np + 1);
    touch_[c].n = touch_prev_[c].n = 0;
  }
  // per chunk: the first chunk owning a pair with a partner in it (the pair loops that read
  // or add to its grains are those of chunks [kick_dep_[c], c]), for the threaded step
  kick_dep_.resize(static_cast<std::size_t>(nc_rows));
  for (int c = 0; c < nc_rows; ++c) kick_dep_[c] = c;
  for (std::size_t k = 0; k < nl_.pairs(); ++k) {
    const int j = nl_.partner[k];
    if (j >= n_grains_) continue;
    int& dep = kick_dep_[j / kChunkRows];
    dep = std::min(dep, nl_.owner[k] / kChunkRows);
  }
  if (static_cast<int>(force_done_size_) < nc_rows + 1) {
    force_done_.reset(new std::atomic<long long>[static_cast<std::size_t>(nc_rows) + 1]);
    force_done_size_ = static_cast<std::size_t>(nc_rows) + 1;
  }
  kick_d2_.resize(static_cast<std::size_t>(nc_rows) + 1);
  full_history_check_ = true;  // pair indices changed; histories were carried over
  {
    const std::size_t np = nl_.pairs();
    pair_reff_.resize(np);
    pair_meff_.resize(np);
    pair_rs2_.resize(np);
    const double* r = p_.r.data();
    const double* inv_m = p_.inv_m.data();
    for (std::size_t k = 0; k < np; ++k) {
      const int i = nl_.owner[k], j = nl_.partner[k];
      const double ri = r[i], rj = r[j];
      const double rs = ri + rj;
      pair_rs2_[k] = rs * rs;  // as the scalar screen: (r_i + r_j)^2
      pair_reff_[k] = ri * rj / rs;
      pair_meff_[k] = 1.0 / (inv_m[i] + inv_m[j]);
    }
    radii_scaled_ = false;
  }
  growth_since_build_ = 0;
  ++builds_;
}

void DemSystem::chunk_forces(int chunk, double spring_dt, double& max_ov, bool full_check) {
  const double h = 0.5 * spring_dt;  // predicted v(t+dt) = v(t+dt/2) + h a(t)
  // local copies: the compiler can keep them in registers (no aliasing with the arrays)
  const PeriodicBox box = opt_.box;
  const LawCoefficients law = law_;
  const double mu = mu_;
  const double* x = p_.x.data();
  const double* y = p_.y.data();
  const double* r = p_.r.data();
  const double* vx = p_.vx.data();
  const double* vy = p_.vy.data();
  const double* w = p_.w.data();
  const double* ax = p_.ax.data();
  const double* ay = p_.ay.data();
  const double* al = p_.alpha.data();
  const double* inv_m = p_.inv_m.data();
  const int* owner = nl_.owner.data();
  const int* partner = nl_.partner.data();
  double* sx = nl_.sx.data();
  double* sy = nl_.sy.data();
  double* pfx = nl_.fx.data();
  double* pfy = nl_.fy.data();
  double* pq = nl_.q.data();
  const int ng = n_grains_;
  // One thread: sum per particle in the pair loop itself (Newton's third law), no gather.
  // The order of the additions is that of the gather of the threaded path (pairs where the
  // particle is the partner, by pair index, then its own row), so the results are the same.
  const bool scatter = team_ == 1;
  const bool store = !scatter || store_pair_forces_;
  double* sfx = fx_.data();
  double* sfy = fy_.data();
  double* sq = tq_.data();
  std::uint8_t* touched = touched_.data();
  const int lo = chunk * kChunkRows, hi = std::min(ng, lo + kChunkRows);
  const std::int64_t k0 = nl_.first[lo], k1 = nl_.first[hi];
  std::swap(touch_[chunk], touch_prev_[chunk]);
  const TouchList& before_list = touch_prev_[chunk];
  TouchList& touch_list = touch_[chunk];
  // Pass 1: distance checks only, one flat loop over the chunk's pairs (most listed pairs of
  // a relaxed bed are apart); no stores but the list of touching pairs.
  touch_list.n = detail::screen_pairs(box, owner, partner, x, y, r,
                                      radii_scaled_ ? nullptr : pair_rs2_.data(), n_total_,
                                      k0, k1, touch_list.k.data());
  const std::int64_t* touching = touch_list.k.data();
  const std::size_t n_touching = touch_list.n;
  // A pair that is apart forgets its history (and its stored force). Only pairs that touched
  // at the step before can hold any: those that no longer touch are found by a merge of the
  // two sorted lists; after a list build every pair is checked.
  auto forget = [&](std::int64_t k) {
    if (sx[k] != 0.0 || sy[k] != 0.0) sx[k] = sy[k] = 0;
    if (store && (pfx[k] != 0.0 || pfy[k] != 0.0 || pq[k] != 0.0)) pfx[k] = pfy[k] = pq[k] = 0;
  };
  if (full_check) {
    std::size_t a = 0;
    for (std::int64_t k = k0; k < k1; ++k) {
      if (a < n_touching && touching[a] == k) {
        ++a;
        continue;
      }
      forget(k);
    }
  } else {
    std::size_t a = 0;
    for (std::size_t b = 0; b < before_list.n; ++b) {
      const std::int64_t k = before_list.k[b];
      while (a < n_touching && touching[a] < k) ++a;
      if (a < n_touching && touching[a] == k) continue;
      forget(k);
    }
  }
  // Pass 2: the contact law on the touching pairs, in pair order, in batches of kBatch: the
  // kinematics of the batch, then the law on each (independent contacts, so that the long
  // chains of divisions and square roots of several contacts overlap), then the sums. Every
  // contact goes through the same operations as one at a time: the same bits.
  constexpr std::size_t kBatch = 32;
  // r_eff and m_eff of each pair, computed by the same expressions at the list build (valid
  // until a radius changes)
  const bool pair_consts = !radii_scaled_;
  const double* reff = pair_reff_.data();
  const double* meff = pair_meff_.data();
  // the batch in structure-of-arrays form (contact_law_batch.h); value-initialised: lanes
  // past a short batch hold finite numbers
  ContactBatch cb{};
  static_assert(kBatch == ContactBatch::kLanes);
  const std::size_t nt = n_touching;
  for (std::size_t b0 = 0; b0 < nt; b0 += kBatch) {
    const std::size_t nb = std::min(kBatch, nt - b0);
    const std::int64_t* kb = touching + b0;
    for (std::size_t b = 0; b < nb; ++b) {
      const std::int64_t k = kb[b];
      const int i = owner[k], j = partner[k];
      const double ri = r[i], rj = r[j];
      double dx = x[i] - x[j], dy = y[i] - y[j];
      box.min_image(dx, dy);
      const double rs = ri + rj;
      const double dist = std::sqrt(dx * dx + dy * dy);
      const double inv_dist = 1.0 / dist;
      const double nx = dx * inv_dist, ny = dy * inv_dist;
      cb.nx[b] = nx;
      cb.ny[b] = ny;
      cb.delta[b] = rs - dist;
      if (pair_consts) {
        cb.r_eff[b] = reff[k];
        cb.m_eff[b] = meff[k];
      } else {
        cb.r_eff[b] = ri * rj / rs;
        cb.m_eff[b] = 1.0 / (inv_m[i] + inv_m[j]);
      }
      const double tx = -ny, ty = nx;
      // predicted relative velocity of the contact point at t+dt
      const double wp = (w[i] + h * al[i]) * ri + (w[j] + h * al[j]) * rj;
      const double vrx = (vx[i] + h * ax[i]) - (vx[j] + h * ax[j]) - wp * tx;
      const double vry = (vy[i] + h * ay[i]) - (vy[j] + h * ay[j]) - wp * ty;
      const double vn = vrx * nx + vry * ny;
      cb.vn[b] = vn;
      cb.vtx[b] = vrx - vn * nx;
      cb.vty[b] = vry - vn * ny;
      // displacement of the contact point over the step (half-step velocities)
      const double wh = w[i] * ri + w[j] * rj;
      cb.dsx[b] = spring_dt * (vx[i] - vx[j] - wh * tx);
      cb.dsy[b] = spring_dt * (vy[i] - vy[j] - wh * ty);
      cb.sx[b] = sx[k];
      cb.sy[b] = sy[k];
    }
    contact_force_batch(law, mu, cb, nb);
    for (std::size_t b = 0; b < nb; ++b) {
      const std::int64_t k = kb[b];
      const int i = owner[k], j = partner[k];
      sx[k] = cb.sx[b];
      sy[k] = cb.sy[b];
      const double fxb = cb.fx[b], fyb = cb.fy[b];
      const double qk = cb.nx[b] * cb.fty[b] - cb.ny[b] * cb.ftx[b];
      if (store) {
        pfx[k] = fxb;
        pfy[k] = fyb;
        pq[k] = qk;
      }
      if (scatter) {
        sfx[i] += fxb;
        sfy[i] += fyb;
        sq[i] += qk;
        touched[i] = 1;
        if (j < ng) {
          sfx[j] -= fxb;
          sfy[j] -= fyb;
          sq[j] += qk;
          touched[j] = 1;
        }
      } else {
        // several threads may mark the same grain (same value): relaxed atomic byte stores
        __atomic_store_n(&touched[i], std::uint8_t{1}, __ATOMIC_RELAXED);
        if (j < ng) __atomic_store_n(&touched[j], std::uint8_t{1}, __ATOMIC_RELAXED);
      }
      // largest overlap fraction: the division only where it can raise the maximum (the
      // pre-test has a margin far above the rounding of either side)
      const double dmin = 2.0 * std::min(r[i], r[j]);
      if (cb.delta[b] > max_ov * dmin * (1.0 - 1e-12)) {
        const double ov = cb.delta[b] / dmin;
        if (ov > max_ov) max_ov = ov;
      }
    }
  }
}

void DemSystem::intruder_forces(double spring_dt, double& max_ov) {
  const double h = 0.5 * spring_dt;
  ifx_ = ify_ = itq_ = 0;
  intruder_touching_ = 0;
  if (!intruder_.present) return;
  const PeriodicBox box = opt_.box;
  const LawCoefficients law = law_;
  const double* x = p_.x.data();
  const double* y = p_.y.data();
  const double* r = p_.r.data();
  const double* vx = p_.vx.data();
  const double* vy = p_.vy.data();
  const double* w = p_.w.data();
  const double* ax = p_.ax.data();
  const double* ay = p_.ay.data();
  const double* al = p_.alpha.data();
  const double* inv_m = p_.inv_m.data();
  const Intruder& in = intruder_;
  const double t_half = time_ - in.t0 + h;
  const double t_full = time_ - in.t0 + spring_dt;
  const double wh_in = in.omega(t_half), wp_in = in.omega(t_full);
  const double big_r = in.r;
  for (std::size_t c = 0; c < ic_.grain.size(); ++c) {
    const int g = ic_.grain[c];
    double dx = x[g] - in.x, dy = y[g] - in.y;
    box.min_image(dx, dy);
    const double rs = r[g] + big_r;
    const double d2 = dx * dx + dy * dy;
    if (d2 >= rs * rs) {
      ic_.sx[c] = ic_.sy[c] = 0;
      ic_.fx[c] = ic_.fy[c] = ic_.fn[c] = ic_.ft[c] = 0;
      ic_.touching[c] = ic_.slipping[c] = 0;
      continue;
    }
    const double dist = std::sqrt(d2);
    ContactKinematics kin;
    kin.nx = dx / dist;
    kin.ny = dy / dist;
    kin.delta = rs - dist;
    kin.r_eff = r[g] * big_r / rs;
    kin.m_eff = 1.0 / inv_m[g];  // the intruder has infinite mass
    kin.mu = mu_intruder_;
    const double tx = -kin.ny, ty = kin.nx;
    const double wp = (w[g] + h * al[g]) * r[g] + wp_in * big_r;
    const double vrx = vx[g] + h * ax[g] - in.vx - wp * tx;
    const double vry = vy[g] + h * ay[g] - in.vy - wp * ty;
    kin.vn = vrx * kin.nx + vry * kin.ny;
    kin.vtx = vrx - kin.vn * kin.nx;
    kin.vty = vry - kin.vn * kin.ny;
    const double wh = w[g] * r[g] + wh_in * big_r;
    kin.dsx = spring_dt * (vx[g] - in.vx - wh * tx);
    kin.dsy = spring_dt * (vy[g] - in.vy - wh * ty);
    ContactForce f;
    contact_force(law, kin, ic_.sx[c], ic_.sy[c], f);
    ic_.fx[c] = f.fx;
    ic_.fy[c] = f.fy;
    ic_.fn[c] = f.fn;
    ic_.ft[c] = f.ftx * tx + f.fty * ty;
    ic_.nx[c] = kin.nx;
    ic_.ny[c] = kin.ny;
    ic_.touching[c] = 1;
    ic_.slipping[c] = f.slipping ? 1 : 0;
    ifx_ -= f.fx;
    ify_ -= f.fy;
    itq_ -= big_r * (kin.nx * f.fty - kin.ny * f.ftx);
    ++intruder_touching_;
    const double ov = kin.delta / (2.0 * r[g]);
    if (ov > max_ov) max_ov = ov;
  }
}

template <bool kScatter, DemSystem::Kick kMode>
double DemSystem::finish_impl(int lo, int hi) {
  const double dt = opt_.dt, h = 0.5 * dt;
  const double gx = opt_.gravity[0], gy = opt_.gravity[1];
  const double damp = damping_rate_ > 0 ? std::exp(-damping_rate_ * dt) : 1.0;
  const PeriodicBox box = opt_.box;
  const std::int64_t* first = nl_.first.data();
  const std::int64_t* rfirst = nl_.rfirst.data();
  const std::int64_t* rpair = nl_.rpair.data();
  const double* pfx = nl_.fx.data();
  const double* pfy = nl_.fy.data();
  const double* pq = nl_.q.data();
  const int* slot = ic_slot_.data();
  std::uint8_t* touched = touched_.data();
  std::uint8_t* flags = grain_flags_.data();
  double* sfx = fx_.data();
  double* sfy = fy_.data();
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
  const bool simd = kMode != Kick::first && detail::avx512_enabled();
  detail::PlainKick plain{px,    py,    vx,     vy,     w,     xb,  yb,        flags,     touched,
                          dt,    h,     damp,   ax0,    ay0,   al0, kScatter, sfx,       sfy,
                          sq,    inv_m, inv_i,  r,      ax,    ay,  al,       gx,        gy,
                          kCandidate, kAccelSet, box};
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
      touched[i] = 0;
      if (kScatter) {
        // the sums of this step; zeroed for the next one
        fx = sfx[i];
        fy = sfy[i];
        qs = sq[i];
        sfx[i] = sfy[i] = sq[i] = 0;
      } else {
        // pairs where i is the partner (by pair index), then i's own row: the order of the
        // one-thread scatter in chunk_forces
        for (std::int64_t s = rfirst[i]; s < rfirst[i + 1]; ++s) {
          const std::int64_t k = rpair[s];
          fx -= pfx[k];
          fy -= pfy[k];
          qs += pq[k];
        }
        for (std::int64_t k = first[i]; k < first[i + 1]; ++k) {
          fx += pfx[k];
          fy += pfy[k];
          qs += pq[k];
        }
      }
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
    // second half kick: v(t+dt)
    double vxi = (vx[i] + h * axn) * damp;
    double vyi = (vy[i] + h * ayn) * damp;
    double wi = (w[i] + h * aln) * damp;
    if (kMode == Kick::drift) {
      // the next step's half kick and drift (the same operations as drift_rows)
      vxi += h * axn;
      vyi += h * ayn;
      wi += h * aln;
      double xi = px[i] + dt * vxi, yi = py[i] + dt * vyi;
      box.wrap(xi, yi);
      px[i] = xi;
      py[i] = yi;
      double dx = xi - xb[i], dy = yi - yb[i];
      box.min_image(dx, dy);
      const double d2 = dx * dx + dy * dy;
      if (d2 > maxd2) maxd2 = d2;
    }
    // a grain in free flight keeps its velocity bit for bit: no store, no dirty cache line
    if (bits(vx[i]) != bits(vxi)) vx[i] = vxi;
    if (bits(vy[i]) != bits(vyi)) vy[i] = vyi;
    if (bits(w[i]) != bits(wi)) w[i] = wi;
    }
  }
  return maxd2;
}

double DemSystem::finish_rows(int lo, int hi, Kick mode) {
  if (team_ == 1) {
    if (mode == Kick::drift) return finish_impl<true, Kick::drift>(lo, hi);
    if (mode == Kick::sync) return finish_impl<true, Kick::sync>(lo, hi);
    return finish_impl<true, Kick::first>(lo, hi);
  }
  if (mode == Kick::drift) return finish_impl<false, Kick::drift>(lo, hi);
  if (mode == Kick::sync) return finish_impl<false, Kick::sync>(lo, hi);
  return finish_impl<false, Kick::first>(lo, hi);
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

void DemSystem::prepare() {
  if (primed_) return;
  build_lists();
  double max_ov = max_overlap_;
  intruder_forces(0.0, max_ov);
  for (int c = 0; c < chunks(); ++c) chunk_forces(c, 0.0, max_ov, full_history_check_);
  full_history_check_ = false;
  max_overlap_ = max_ov;
  finish_rows(0, n_grains_, Kick::first);
  drifted_ = false;
  primed_ = true;
}

double DemSystem::current_max_overlap_fraction() const {
  double worst = 0;
  for (int i = 0; i < n_grains_; ++i) {
    for (std::int64_t k = nl_.first[i]; k < nl_.first[i + 1]; ++k) {
      const int j = nl_.partner[k];
      double dx = p_.x[i] - p_.x[j], dy = p_.y[i] - p_.y[j];
      opt_.box.min_image(dx, dy);
      const double delta = p_.r[i] + p_.r[j] - std::sqrt(dx * dx + dy * dy);
      worst = std::max(worst, delta / (2.0 * std::min(p_.r[i], p_.r[j])));
    }
  }
  if (intruder_.present) {
    for (int g : ic_.grain) {
      double dx = p_.x[g] - intruder_.x, dy = p_.y[g] - intruder_.y;
      opt_.box.min_image(dx, dy);
      const double delta = p_.r[g] + intruder_.r - std::sqrt(dx * dx + dy * dy);
      worst = std::max(worst, delta / (2.0 * p_.r[g]));
    }
  }
  return worst;
}

double DemSystem::drift_item(int c, double& idisp) {
  if (c == 0) {
    idisp = drift_intruder();
    return 0;
  }
  const int lo = (c - 1) * kChunkRows;
  return drift_rows(lo, std::min(n_grains_, lo + kChunkRows));
}

long long DemSystem::run_segment(long long m) {
  const int team = team_;
  const int nchunks = chunks();
  const int items = nchunks + 1;  // work item 0: the intruder; item 1 + c: chunk c
  const double dt = opt_.dt;
  detail::TeamBarrier barrier(team);
  std::atomic<int> next{0};  // dynamic work distribution (results do not depend on it)
  struct alignas(64) Slot {
    double d2 = 0;
  };
  Slot slot[kMaxTeam];
  double idisp = 0;
  bool was_drifted = drifted_;
  long long completed = 0;
  bool rebuild = false;
  double max_ov = max_overlap_;
  const int rows_per_chunk = kChunkRows;
  const int ng = n_grains_;
#pragma omp parallel num_threads(team) reduction(max : max_ov)
  {
    const int t = omp_get_thread_num();
    auto grab = [&] { return team == 1 ? -1 : next.fetch_add(1, std::memory_order_relaxed); };
    int serial = 0;  // one thread: work items in order without atomics
    auto take = [&]() -> int { return team == 1 ? serial++ : grab(); };
    auto reset = [&] {
      serial = 0;
      next.store(0, std::memory_order_relaxed);
    };
    double d2 = 0;
    if (!was_drifted) {
      for (int c; (c = take()) < items;) d2 = std::max(d2, drift_item(c, idisp));
    }
    slot[t].d2 = d2;
    for (long long k = 0;;) {
      barrier.wait(reset);
      // every thread takes the same decision from the same numbers
      double md2 = 0;
      for (int u = 0; u < team; ++u) md2 = std::max(md2, slot[u].d2);
      const double md = std::sqrt(md2) + build_round_ + growth_since_build_;
      // Right after a build (re-entry after a rebuild) the lists are fresh whatever the bound
      // says; without this a box so large that the float rounding of the build positions
      // (build_round_) exceeded skin / 2 would rebuild forever instead of every step.
      const bool fresh = was_drifted && k == 0;
      if (!fresh && (2.0 * md > skin_ || idisp + md > skin_)) {
        if (t == 0) rebuild = true;
        break;
      }
      for (int c; (c = take()) < items;) {
        if (c == 0) {
          intruder_forces(dt, max_ov);
        } else {
          chunk_forces(c - 1, dt, max_ov, full_history_check_);
        }
      }
      barrier.wait(reset);
      ++k;
      const bool last = k == m;
      d2 = 0;
      for (int c; (c = take()) < items;) {
        if (c == 0) {
          time_ += dt;
          ++steps_;
          full_history_check_ = false;
          if (!last) idisp = drift_intruder();
        } else {
          const int lo = (c - 1) * rows_per_chunk;
          d2 = std::max(d2, finish_rows(lo, std::min(ng, lo + rows_per_chunk),
                                        last ? Kick::sync : Kick::drift));
        }
      }
      slot[t].d2 = d2;
      if (last) {
        if (t == 0) completed = k;
        break;
      }
      if (t == 0) completed = k;
    }
  }
  max_overlap_ = max_ov;
  drifted_ = rebuild;
  return completed;
}

namespace {
/// Spin (then yield) until ready() holds.
template <class Ready>
inline void wait_until(Ready ready) {
  for (int n = 0; !ready(); ++n) {
    if (n < 2000) {
#if defined(__x86_64__) || defined(__i386__)
      _mm_pause();
#endif
    } else {
      sched_yield();
    }
  }
}
}  // namespace

// The threaded step without a team barrier inside the segment. Work items, one sequence for all
// steps, handed out from one counter: per step, the pair forces (item 0: the intruder's
// contacts, 1 + c: the pairs owned by chunk c), then the kicks (item 0: the intruder's motion
// and the clock, 1 + c: the grains of chunk c). A force item of step s waits until every kick
// item of step s - 1 is done and the list check for step s is taken (by the thread that
// completed the last of them, from the per-item displacements); a kick item of chunk c waits
// only for the force items that read or add to its grains (chunks kick_dep_[c] to c, and the
// intruder). A thread that is descheduled holds up the others only through the items it holds,
// not by having to arrive at a barrier. The operations, and so the bits, are those of
// run_segment (every per-grain sum is taken in pair order at the kick, whoever computed the
// pair forces).
long long DemSystem::run_segment_team(long long m) {
  const int team = team_;
  const int nchunks = chunks();
  const int per_phase = nchunks + 1;
  const long long per_step = 2LL * per_phase;
  const double dt = opt_.dt;
  const int ng = n_grains_;
  const int rows_per_chunk = kChunkRows;
  detail::TeamBarrier barrier(team);
  std::atomic<int> init_next{0};
  std::atomic<long long> next{0};
  std::atomic<long long> kicks_done{0};  // kick items completed in this segment
  std::atomic<long long> decided{-1};    // list check taken for steps <= decided
  std::atomic<long long> stop_step{m};   // first step not to run (a rebuild is due)
  std::atomic<long long>* fdone = force_done_.get();
  for (int q = 0; q < per_phase; ++q) fdone[q].store(0, std::memory_order_relaxed);
  double* kd2 = kick_d2_.data();
  struct alignas(64) Slot {
    double d2 = 0;
  };
  Slot slot[kMaxTeam];
  double idisp = 0;
  const bool was_drifted = drifted_;
  const bool full_check0 = full_history_check_;
  double max_ov = max_overlap_;
  // the list check before step s from the largest displacement md2 (squared) since the build
  auto rebuild_due = [&](double md2, long long s) {
    const double md = std::sqrt(md2) + build_round_ + growth_since_build_;
    // right after a build the lists are fresh whatever the bound says (see run_segment)
    const bool fresh = was_drifted && s == 0;
    return !fresh && (2.0 * md > skin_ || idisp + md > skin_);
  };
#pragma omp parallel num_threads(team) reduction(max : max_ov)
  {
    const int t = omp_get_thread_num();
    double d2 = 0;
    if (!was_drifted) {
      for (int c; (c = init_next.fetch_add(1, std::memory_order_relaxed)) < per_phase;)
        d2 = std::max(d2, drift_item(c, idisp));
    }
    slot[t].d2 = d2;
    barrier.wait([] {});
    if (t == 0) {
      double md2 = 0;
      for (int u = 0; u < team; ++u) md2 = std::max(md2, slot[u].d2);
      if (rebuild_due(md2, 0)) stop_step.store(0, std::memory_order_relaxed);
      decided.store(0, std::memory_order_release);
    }
    for (;;) {
      const long long g = next.fetch_add(1, std::memory_order_relaxed);
      const long long s = g / per_step;
      const int idx = static_cast<int>(g % per_step);
      if (s >= m) break;
      if (idx < per_phase) {
        // pair forces of step s
        wait_until([&] { return decided.load(std::memory_order_acquire) >= s; });
        if (s >= stop_step.load(std::memory_order_relaxed)) break;
        if (idx == 0) {
          intruder_forces(dt, max_ov);
        } else {
          chunk_forces(idx - 1, dt, max_ov, s == 0 && full_check0);
        }
        fdone[idx].store(s + 1, std::memory_order_release);
      } else {
        // kicks of step s
        const int c = idx - per_phase;
        const bool last = s == m - 1;
        wait_until([&] { return fdone[0].load(std::memory_order_acquire) > s; });
        if (c == 0) {
          time_ += dt;
          ++steps_;
          if (!last) idisp = drift_intruder();
        } else {
          for (int q = kick_dep_[c - 1]; q <= c - 1; ++q) {
            wait_until([&] { return fdone[q + 1].load(std::memory_order_acquire) > s; });
          }
          const int lo = (c - 1) * rows_per_chunk;
          kd2[c] = finish_rows(lo, std::min(ng, lo + rows_per_chunk),
                               last ? Kick::sync : Kick::drift);
        }
        // the thread that completes the step takes the list check for the next one
        if (kicks_done.fetch_add(1, std::memory_order_acq_rel) == (s + 1) * per_phase - 1 &&
            !last) {
          double md2 = 0;
          for (int q = 1; q <= nchunks; ++q) md2 = std::max(md2, kd2[q]);
          if (rebuild_due(md2, s + 1)) stop_step.store(s + 1, std::memory_order_relaxed);
          decided.store(s + 1, std::memory_order_release);
        }
      }
    }
  }
  const long long completed = std::min(m, stop_step.load());
  if (completed > 0) full_history_check_ = false;
  max_overlap_ = max_ov;
  drifted_ = completed < m;
  return completed;
}

void DemSystem::advance(long long n) {
  prepare();
  long long done = 0;
  while (done < n) {
    done += team_ > 1 ? run_segment_team(n - done) : run_segment(n - done);
    if (drifted_) build_lists();
  }
}

}  // namespace grainlift::dem
