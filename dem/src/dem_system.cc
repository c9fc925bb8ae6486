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
#include "grainlift/dem/dem_system.h"

#include <algorithm>
#include <cmath>

#include <omp.h>

#include "grainlift/dem/errors.h"

namespace grainlift::dem {

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
                  &p_.inv_m, &p_.inv_i, &p_.mass, &p_.x_build, &p_.y_build, &fx_, &fy_, &tq_}) {
    v->assign(n, 0.0);
  }
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
    }
  }
  skin_ = opt_.skin > 0 ? opt_.skin : 0.2 * rmax;
  // Below ~kMinGrainsPerThread grains per thread the fork-join costs more than it saves.
  team_ = std::max(1, std::min(opt_.threads, n_grains_ / kMinGrainsPerThread));
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
  for (int i = 0; i < n_total_; ++i) {
    p_.x_build[i] = p_.x[i];
    p_.y_build[i] = p_.y[i];
  }
  // Intruder candidates: grains within R + r + skin, in index order, history carried over.
  for (int g : ic_.grain) ic_slot_[g] = -1;
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
    while (a < ic_old_.grain.size() && ic_old_.grain[a] < ic_.grain[b]) ++a;
    if (a < ic_old_.grain.size() && ic_old_.grain[a] == ic_.grain[b]) {
      ic_.sx[b] = ic_old_.sx[a];
      ic_.sy[b] = ic_old_.sy[a];
    }
  }
  // touching-pair scratch of the force loop: sized here so that the step does not allocate
  touch_.resize(std::max<std::size_t>(touch_.size(), static_cast<std::size_t>(team_)));
  for (auto& v : touch_) v.reserve(nl_.pairs());
  growth_since_build_ = 0;
  ++builds_;
}

void DemSystem::compute_forces(double spring_dt) {
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
  const std::int64_t* first = nl_.first.data();
  const int* partner = nl_.partner.data();
  double* sx = nl_.sx.data();
  double* sy = nl_.sy.data();
  double* pfx = nl_.fx.data();
  double* pfy = nl_.fy.data();
  double* pq = nl_.q.data();
  const int ng = n_grains_;
  double max_ov = max_overlap_;
  // One thread: sum per particle in the pair loop itself (Newton's third law), no gather.
  // The order of the additions is that of the gather of the threaded path (pairs where the
  // particle is the partner, by pair index, then its own row), so the results are the same.
  const bool scatter = team_ == 1;
  const bool store = !scatter || store_pair_forces_;
  double* sfx = fx_.data();
  double* sfy = fy_.data();
  double* sq = tq_.data();
  if (scatter) {
    std::fill(fx_.begin(), fx_.begin() + ng, 0.0);
    std::fill(fy_.begin(), fy_.begin() + ng, 0.0);
    std::fill(tq_.begin(), tq_.begin() + ng, 0.0);
  }

  if (touch_.size() < static_cast<std::size_t>(team_)) touch_.resize(team_);
#pragma omp parallel num_threads(team_) reduction(max : max_ov)
  {
    // Rows in contiguous blocks, one per thread (the same blocks as a static schedule).
    const int t = omp_get_thread_num();
    const int nth = omp_get_num_threads();
    const int lo = static_cast<int>(static_cast<std::int64_t>(ng) * t / nth);
    const int hi = static_cast<int>(static_cast<std::int64_t>(ng) * (t + 1) / nth);
    std::vector<std::int64_t>& touching = touch_[t];
    touching.clear();
    // Pass 1: distance checks only (most listed pairs of a relaxed bed are apart). A pair that
    // is apart forgets its history; only words that are not zero already are written.
    for (int i = lo; i < hi; ++i) {
      const double xi = x[i], yi = y[i], ri = r[i];
      for (std::int64_t k = first[i]; k < first[i + 1]; ++k) {
        const int j = partner[k];
        double dx = xi - x[j], dy = yi - y[j];
        box.min_image(dx, dy);
        const double rs = ri + r[j];
        if (dx * dx + dy * dy < rs * rs) {
          touching.push_back(k);
          continue;
        }
        if (sx[k] != 0.0 || sy[k] != 0.0) sx[k] = sy[k] = 0;
        if (store && (pfx[k] != 0.0 || pfy[k] != 0.0 || pq[k] != 0.0)) pfx[k] = pfy[k] = pq[k] = 0;
      }
    }
    // Pass 2: the contact law on the touching pairs, in pair order.
    int i = lo;
    for (const std::int64_t k : touching) {
      while (first[i + 1] <= k) ++i;
      const int j = partner[k];
      const double ri = r[i], rj = r[j];
      double dx = x[i] - x[j], dy = y[i] - y[j];
      box.min_image(dx, dy);
      const double rs = ri + rj;
      const double dist = std::sqrt(dx * dx + dy * dy);
      const double inv_dist = 1.0 / dist;
      ContactKinematics kin;
      kin.nx = dx * inv_dist;
      kin.ny = dy * inv_dist;
      kin.delta = rs - dist;
      kin.r_eff = ri * rj / rs;
      kin.m_eff = 1.0 / (inv_m[i] + inv_m[j]);
      kin.mu = mu;
      const double tx = -kin.ny, ty = kin.nx;
      // predicted relative velocity of the contact point at t+dt
      const double wp = (w[i] + h * al[i]) * ri + (w[j] + h * al[j]) * rj;
      const double vrx = (vx[i] + h * ax[i]) - (vx[j] + h * ax[j]) - wp * tx;
      const double vry = (vy[i] + h * ay[i]) - (vy[j] + h * ay[j]) - wp * ty;
      kin.vn = vrx * kin.nx + vry * kin.ny;
      kin.vtx = vrx - kin.vn * kin.nx;
      kin.vty = vry - kin.vn * kin.ny;
      // displacement of the contact point over the step (half-step velocities)
      const double wh = w[i] * ri + w[j] * rj;
      kin.dsx = spring_dt * (vx[i] - vx[j] - wh * tx);
      kin.dsy = spring_dt * (vy[i] - vy[j] - wh * ty);
      ContactForce f;
      contact_force(law, kin, sx[k], sy[k], f);
      const double qk = kin.nx * f.fty - kin.ny * f.ftx;
      if (store) {
        pfx[k] = f.fx;
        pfy[k] = f.fy;
        pq[k] = qk;
      }
      if (scatter) {
        sfx[i] += f.fx;
        sfy[i] += f.fy;
        sq[i] += qk;
        if (j < ng) {
          sfx[j] -= f.fx;
          sfy[j] -= f.fy;
          sq[j] += qk;
        }
      }
      const double ov = kin.delta / (2.0 * std::min(ri, rj));
      if (ov > max_ov) max_ov = ov;
    }
  }

  // ---- the intruder: its own small loop over its candidates (serial, fixed order)
  ifx_ = ify_ = itq_ = 0;
  intruder_touching_ = 0;
  if (intruder_.present) {
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
  max_overlap_ = max_ov;
}

void DemSystem::finish_kick(bool first_call) {
  const double h = 0.5 * opt_.dt;
  const double gx = opt_.gravity[0], gy = opt_.gravity[1];
  const double damp = damping_rate_ > 0 ? std::exp(-damping_rate_ * opt_.dt) : 1.0;
  const std::int64_t* first = nl_.first.data();
  const std::int64_t* rfirst = nl_.rfirst.data();
  const std::int64_t* rpair = nl_.rpair.data();
  const double* pfx = nl_.fx.data();
  const double* pfy = nl_.fy.data();
  const double* pq = nl_.q.data();
  const int* slot = ic_slot_.data();
  const int ng = n_grains_;
  const bool scatter = team_ == 1;
  const double* sfx = fx_.data();
  const double* sfy = fy_.data();
  const double* sq = tq_.data();
  ParticleArrays& p = p_;
  const IntruderContacts& ic = ic_;
#pragma omp parallel for schedule(static) num_threads(team_)
  for (int i = 0; i < ng; ++i) {
    double fx = 0, fy = 0, qs = 0;
    if (scatter) {
      fx = sfx[i];
      fy = sfy[i];
      qs = sq[i];
    } else {
      // pairs where i is the partner (by pair index), then i's own row: the order of the
      // one-thread scatter in compute_forces
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
    double tq = -p.r[i] * qs;
    const int c = slot[i];
    if (c >= 0) {
      fx += ic.fx[c];
      fy += ic.fy[c];
      tq -= p.r[i] * ic.ft[c];  // n x F_t = ft for F_t = ft (-n_y, n_x)
    }
    const double axn = fx * p.inv_m[i] + gx;
    const double ayn = fy * p.inv_m[i] + gy;
    const double aln = tq * p.inv_i[i];
    if (!first_call) {
      p.vx[i] = (p.vx[i] + h * axn) * damp;
      p.vy[i] = (p.vy[i] + h * ayn) * damp;
      p.w[i] = (p.w[i] + h * aln) * damp;
    }
    p.ax[i] = axn;
    p.ay[i] = ayn;
    p.alpha[i] = aln;
  }
}

void DemSystem::prepare() {
  if (primed_) return;
  build_lists();
  compute_forces(0.0);
  finish_kick(true);
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

void DemSystem::step() {
  prepare();
  const double dt = opt_.dt, h = 0.5 * dt;
  const PeriodicBox& box = opt_.box;
  ParticleArrays& p = p_;
  const int ng = n_grains_;
  double maxd2 = 0;
#pragma omp parallel for schedule(static) num_threads(team_) reduction(max : maxd2)
  for (int i = 0; i < ng; ++i) {
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
  double idisp = 0;
  if (intruder_.present) {
    double xi = intruder_.x + dt * intruder_.vx, yi = intruder_.y + dt * intruder_.vy;
    box.wrap(xi, yi);
    intruder_.x = xi;
    intruder_.y = yi;
    double dx = xi - intruder_.x_build, dy = yi - intruder_.y_build;
    box.min_image(dx, dy);
    idisp = std::sqrt(dx * dx + dy * dy);
  }
  const double md = std::sqrt(maxd2) + growth_since_build_;
  if (2.0 * md > skin_ || idisp + md > skin_) build_lists();
  compute_forces(dt);
  finish_kick(false);
  time_ += dt;
  ++steps_;
}

}  // namespace grainlift::dem
