// The DEM system's state (grains, frozen wall disks, the intruder, the lid) and advance().
//
// One synchronised velocity-Verlet step from t to t+dt, each stage in its own file:
//   1. half kick and drift, v(t+dt/2) = v(t) + dt/2 a(t), x(t+dt) = x(t) + dt v(t+dt/2)
//      (velocity_verlet.cc); when a grain may have moved by half the skin the Verlet lists are
//      rebuilt first (list_rebuild.cc, neighbor_list.cc);
//   2. contact forces at t+dt: grain-grain and grain-wall pairs (pair_forces.cc), grain-intruder
//      (intruder_contacts.cc), one contact law for all (contact_law.h). The tangential spring
//      grows by the relative displacement of the contact point over the step, dt v(t+dt/2)
//      (exactly the displacement the positions made), and the damping and slip direction use
//      the predicted velocity at the same time level, v(t+dt) ~ v(t+dt/2) + dt/2 a(t)
//      (contact_point_motion() in contact_law.h). For the intruder, whose motion is
//      prescribed, they are exact;
//   3. the boundaries that move with the forces (the pressure lid, lid.cc) and the second half
//      kick, v(t+dt) = v(t+dt/2) + dt/2 a(t+dt) (velocity_verlet.cc).
// Without velocity-dependent forces this is plain velocity Verlet (symplectic).
//
// advance(n) runs n steps as segments between list rebuilds (step_schedule.cc): on one thread
// a plain loop; on a team, each thread on its own range of rows. The team does not change a bit
// of the results (every per-grain sum is taken in pair order). Inside advance(), stage 3 of one
// step and stage 1 of the next are one pass over the particle arrays; the last step of a call ends
// with stage 3 alone, so the state between calls is that of single steps.
#include "grainlift/dem/system/dem_system.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>

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
  drives_.clear();
  n_grains_ = static_cast<int>(grains.size());
  n_total_ = n_grains_ + static_cast<int>(frozen.size());
  const std::size_t n = static_cast<std::size_t>(n_total_);
  for (auto* v : {&p_.x, &p_.y, &p_.vx, &p_.vy, &p_.w, &p_.ax, &p_.ay, &p_.alpha, &p_.r,
                  &p_.inv_m, &p_.inv_i, &p_.mass, &tq_}) {
    v->assign(n, 0.0);
  }
  fxy_.assign(2 * n, 0.0);
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
      if (!(d.mass > 0) || !(d.r > 0))
        throw ConfigError("every grain needs mass > 0 and radius > 0");
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
  team_max_ = std::max(1, std::min({opt_.threads, n_grains_ / kMinGrainsPerThread, kMaxTeam}));
  team_ = team_max_;
  tune_phase_ = 0;
  tune_left_ = kWarmSteps + kTrialSteps;
  tune_seconds_[0] = tune_seconds_[1] = 0;
  tune_steps_[0] = tune_steps_[1] = 0;
  tune_early_seconds_ = 0;
  tune_early_steps_ = 0;
  tune_backoff_ = 0;
  nl_.clear();
  ic_ = IntruderContacts{};
  ic_old_ = IntruderContacts{};
  ic_slot_.assign(static_cast<std::size_t>(n_grains_), -1);
  growth_since_build_ = 0;
  sleep_active_ = false;
  wake_pending_ = 0;
  sleeping_now_ = 0;
  primed_ = false;
}

double DemSystem::grain_mass() const {
  std::vector<double> m(p_.mass.begin(), p_.mass.begin() + n_grains_);
  if (opt_.sort_every > 0) std::sort(m.begin(), m.end());
  double sum = 0;
  for (double v : m) sum += v;
  return sum;
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

void DemSystem::attach_lid(const PressureLid& lid) {
  lid_ = lid;
  set_store_pair_forces(true);
}

std::array<double, 2> DemSystem::frozen_force(int begin, int end) const {
  std::array<double, 2> f{0, 0};
  for (int j = begin; j < end; ++j) {
    // pairs (i, j) list the force on the grain i; the frozen disk feels its opposite
    for (std::int64_t s = nl_.rfirst[j]; s < nl_.rfirst[j + 1]; ++s) {
      f[0] -= nl_.fx[nl_.rpair[s]];
      f[1] -= nl_.fy[nl_.rpair[s]];
    }
  }
  return f;
}

void DemSystem::move_frozen(int begin, int end, double dx, double dy, double vx, double vy) {
  for (int j = begin; j < end; ++j) {
    p_.x[j] += dx;
    p_.y[j] += dy;
    opt_.box.wrap(p_.x[j], p_.y[j]);
    p_.vx[j] = vx;
    p_.vy[j] = vy;
  }
  // A frozen disk that moved by |(dx, dy)| changes a pair distance by at most that much: the
  // same bound as a radius growth, so the Verlet-list rebuild test counts it there.
  growth_since_build_ += std::hypot(dx, dy);
}

void DemSystem::move_frozen_each(int begin, int end, double dx, const std::vector<double>& dy,
                                 double vx, const std::vector<double>& vy) {
  double largest = 0;
  for (int j = begin; j < end; ++j) {
    const std::size_t k = std::size_t(j - begin);
    p_.x[j] += dx;
    p_.y[j] += dy[k];
    opt_.box.wrap(p_.x[j], p_.y[j]);
    p_.vx[j] = vx;
    p_.vy[j] = vy[k];
    largest = std::max(largest, std::abs(dy[k]));
  }
  growth_since_build_ += std::hypot(dx, largest);  // the bound of move_frozen, per disk
}

void DemSystem::drive_frozen(int begin, int end, double dx, double dy, double vx, double vy,
                             long long steps) {
  if (begin < n_grains_ || end > n_total_ || begin > end)
    throw std::invalid_argument("drive_frozen: not a range of frozen disks");
  if (steps > 0) drives_.push_back({begin, end, dx, dy, vx, vy, steps});
}

void DemSystem::step_boundaries() {
  if (!drives_.empty()) {
    for (FrozenDrive& d : drives_) {
      if (d.left-- > 0) move_frozen(d.begin, d.end, d.dx, d.dy, d.vx, d.vy);
    }
    drives_.erase(std::remove_if(drives_.begin(), drives_.end(),
                                 [](const FrozenDrive& d) { return d.left <= 0; }),
                  drives_.end());
  }
  if (!lid_) return;
  if (lid_->free_disks()) {
    lid_force_y_.resize(std::size_t(lid_->disks()));
    double fx = 0;
    for (int j = lid_->begin(); j < lid_->end(); ++j) {
      const std::array<double, 2> f = frozen_force(j, j + 1);
      fx += f[0];
      lid_force_y_[std::size_t(j - lid_->begin())] = f[1];
    }
    const LidMove m = lid_->advance_disks(fx, lid_force_y_, opt_.dt, lid_dy_);
    move_frozen_each(lid_->begin(), lid_->end(), m.dx, lid_dy_, lid_->shear_velocity(),
                     lid_->disk_velocity());
    return;
  }
  const std::array<double, 2> f = frozen_force(lid_->begin(), lid_->end());
  const LidMove m = lid_->advance(f[0], f[1], opt_.dt);
  move_frozen(lid_->begin(), lid_->end(), m.dx, m.dy, lid_->shear_velocity(),
              lid_->state().velocity);
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
  // (2/5) A_n delta^2 with A_n = k sqrt(delta) of F_n = A_n delta
  double e = 0;
  for_each_gap([&](double delta, double ri, double rj, int, int) {
    if (delta > 0)
      e += 0.4 * law_.hertz_stiffness(ri * rj / (ri + rj)) * std::sqrt(delta) * delta * delta;
  });
  return e;
}

void DemSystem::prepare() {
  if (primed_) return;
  build_lists();
  double max_ov = max_overlap_;
  intruder_forces(0.0, max_ov);
  for (int c = 0; c < chunks(); ++c) chunk_forces(c, 0.0, max_ov, full_history_check_, true);
  full_history_check_ = false;
  max_overlap_ = max_ov;
  finish_rows(0, n_grains_, Kick::first, false);
  drifted_ = false;
  primed_ = true;
}

DemSystem::WorstOverlap DemSystem::worst_overlap() const {
  WorstOverlap w;
  for_each_gap([&](double delta, double ri, double rj, int i, int j) {
    // against the grain's diameter for the intruder (j < 0), the smaller one for a pair
    const double f = delta / (2.0 * (j < 0 ? ri : std::min(ri, rj)));
    if (f > w.fraction) w = {i, j, f};
  });
  return w;
}

int DemSystem::first_non_finite_grain() const {
  for (int i = 0; i < n_grains_; ++i) {
    if (!std::isfinite(p_.x[i]) || !std::isfinite(p_.y[i]) || !std::isfinite(p_.vx[i]) ||
        !std::isfinite(p_.vy[i]) || !std::isfinite(p_.w[i])) {
      return i;
    }
  }
  return -1;
}

int DemSystem::fastest_grain() const {
  int best = -1;
  double top = -1;
  for (int i = 0; i < n_grains_; ++i) {
    const double v = std::hypot(p_.vx[i], p_.vy[i]) + std::fabs(p_.w[i]) * p_.r[i];
    if (v > top) {
      top = v;
      best = i;
    }
  }
  return best;
}

double DemSystem::current_max_overlap_fraction() const { return worst_overlap().fraction; }

void DemSystem::choose_team() {
  int want = team_max_;
  // GRAINLIFT_TEAM=fixed: always the whole team (benchmarks of the threaded step itself)
  static const bool fixed = [] {
    const char* v = std::getenv("GRAINLIFT_TEAM");
    return v && std::string(v) == "fixed";
  }();
  if (team_max_ > 1 && !fixed && !team_fixed_) {
    if (tune_left_ <= 0) {
      if (tune_phase_ == 1) {
        // both trials done: the faster per step (a tie goes to one thread: it frees a core)
        const double one = tune_seconds_[0] / double(std::max(1LL, tune_steps_[0]));
        const double team = tune_seconds_[1] / double(std::max(1LL, tune_steps_[1]));
        tune_best_ = team < one ? team_max_ : 1;
        tune_backoff_ = tune_best_ > 1 ? 0 : std::min(kMaxBackoff, tune_backoff_ + 1);
        ++tune_trials_;
      }
      tune_phase_ = (tune_phase_ + 1) % 3;
      tune_left_ = tune_phase_ == 2 ? kExploitSteps << tune_backoff_ : kWarmSteps + kTrialSteps;
      tune_exploit_elapsed_ = 0;
      tune_exploit_steps_ = 0;
      if (tune_phase_ == 0) {
        tune_seconds_[0] = tune_seconds_[1] = 0;
        tune_steps_[0] = tune_steps_[1] = 0;
        tune_early_seconds_ = 0;
        tune_early_steps_ = 0;
      }
    }
    want = tune_phase_ == 0 ? 1 : tune_phase_ == 1 ? team_max_ : tune_best_;
  }
  // the two paths keep different per-pair state between steps (one thread sums forces in the
  // pair loop and may skip the per-pair stores): the first step after a change checks every pair
  if (want != team_) full_history_check_ = true;
  team_ = want;
}

void DemSystem::account_segment(long long steps, double seconds) {
  (team_ > 1 ? steps_on_team_ : steps_on_one_) += steps;
  if (team_max_ == 1) return;
  // The team's trial ends early when its first kEarlySteps or more steps (warm-up included)
  // took more than three times as long per step as the one-thread trial: another process
  // holds a core, and waiting out 2,500 such steps would cost more than the trial can win.
  if (tune_phase_ == 1) {
    tune_early_seconds_ += seconds;
    tune_early_steps_ += steps;
    if (tune_early_steps_ >= kEarlySteps && tune_steps_[0] > 0 &&
        tune_early_seconds_ / double(tune_early_steps_) >
            3.0 * tune_seconds_[0] / double(tune_steps_[0])) {
      tune_seconds_[1] = tune_early_seconds_;
      tune_steps_[1] = tune_early_steps_;
      tune_left_ = 0;
      return;
    }
  }
  if (tune_phase_ == 2) {
    tune_exploit_elapsed_ += seconds;
    tune_exploit_steps_ += steps;
    if (exploit_is_over()) {
      tune_left_ = 0;
      return;
    }
  }
  if (tune_phase_ < 2 && kWarmSteps + kTrialSteps - tune_left_ >= kWarmSteps) {
    tune_seconds_[tune_phase_] += seconds;
    tune_steps_[tune_phase_] += steps;
  }
  tune_left_ -= steps;
}

bool DemSystem::exploit_is_over() const {
  // After opt_.tune_exploit_seconds (large beds: many seconds per thousand steps).
  if (tune_exploit_elapsed_ >= opt_.tune_exploit_seconds) return true;
  // After opt_.tune_trial_multiple times the trials' time, so that a verdict is tried again
  // within seconds (the demo, two threads, AVX-512: 4 of 10 runs kept one thread on 19-99% of
  // the steps, 18.5-28.9 s against 18.2-20.2 s with the team).
  const double trials = tune_seconds_[0] + tune_seconds_[1];
  if (opt_.tune_trial_multiple > 0 && tune_exploit_elapsed_ > opt_.tune_trial_multiple * trials)
    return true;
  // When its time per step leaves the trial's by opt_.tune_stale_ratio (reduced Kumar bed
  // widened to 6,883 grains, 10 d, two threads, AVX-512: the run's first trials, on a bed at
  // rest, found the team slower, 9.3 against 8.6 us a step, and the exploit phase kept one
  // thread to the end, 9.7 s, where the team alone takes 5.5 s).
  const int side = tune_best_ > 1 ? 1 : 0;
  if (!(opt_.tune_stale_ratio > 0) || tune_exploit_steps_ < kTrialSteps || tune_steps_[side] <= 0)
    return false;
  const double now = tune_exploit_elapsed_ / double(tune_exploit_steps_);
  const double then = tune_seconds_[side] / double(tune_steps_[side]);
  return now > opt_.tune_stale_ratio * then || now * opt_.tune_stale_ratio < then;
}

void DemSystem::advance(long long n) {
  prepare();
  long long done = 0;
  const long long every = opt_.sort_every;
  while (done < n) {
    choose_team();
    // a segment ends at the next renumbering (at steps that are multiples of sort_every, so
    // that any run of the same steps renumbers at the same ones)
    const long long m = every > 0 ? std::min(n - done, every - steps_ % every) : n - done;
    const auto t0 = std::chrono::steady_clock::now();
    const long long k = team_ > 1 ? run_segment_team(m) : run_segment(m);
    account_segment(k,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    done += k;
    sleep_grain_steps_ += static_cast<double>(sleeping_now_) * static_cast<double>(k);
    if (every > 0 && k > 0 && steps_ % every == 0) {
      build_lists(true);
    } else if (drifted_) {
      build_lists();
    }
  }
}

}  // namespace grainlift::dem
