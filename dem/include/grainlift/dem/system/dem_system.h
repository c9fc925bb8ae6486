// The state of a DEM system (grains, frozen wall disks, one prescribed intruder, an optional
// pressure lid) and its synchronised velocity-Verlet time step, whose stages live in their own
// files (see dem_system.cc). No I/O; no allocation inside step() once the neighbour list has
// reached its working size.
#pragma once

#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "grainlift/dem/contact/contact_law.h"
#include "grainlift/dem/dem_config.h"
#include "grainlift/dem/boundaries/lid.h"
#include "grainlift/dem/step/neighbor_list.h"
#include "grainlift/dem/periodic_box.h"

namespace grainlift::dem {

struct SystemSnapshot;  // checkpoint.h

/// One disk handed to DemSystem::set_bodies.
struct Disk {
  double x = 0, y = 0;   ///< m
  double r = 0;          ///< m
  double mass = 0;       ///< kg (ignored for frozen disks: infinite mass)
  double vx = 0, vy = 0, w = 0;  ///< m/s, rad/s
};

struct SystemOptions {
  PeriodicBox box;
  ContactParams contact;
  double dt = 2e-6;       ///< s
  double skin = 0;        ///< m, Verlet skin (0: 0.1 of the largest diameter)
  int threads = 1;        ///< OpenMP threads (at most one per kMinGrainsPerThread grains)
  /// s: the thread tuner's exploit phase ends after this much wall time even when its steps
  /// (DemSystem::kExploitSteps << backoff) are not done: on a bed of 60,000 grains 1.6 M steps
  /// on one thread are more than an hour after the load that made the team lose has gone.
  double tune_exploit_seconds = 120;
  /// the exploit phase also ends when its time per step leaves the trial's (of the side
  /// chosen) by more than this factor either way: the trials' verdict is stale (0: never).
  /// A run's first trials see a bed at rest, largely asleep; its front builds later.
  double tune_stale_ratio = 1.5;
  /// the exploit phase also ends once its wall time exceeds this multiple of its two trials'
  /// timed wall time (0: never): a wrong verdict lasts at most that long, and the trials cost
  /// at most about 1/multiple of the run (the demo: trials of ~0.1 s, a verdict kept ~4 s)
  double tune_trial_multiple = 40;
  std::array<double, 2> gravity{0, 0};  ///< m/s^2, on grains only
  /// Every this many steps (at multiples of it) the grains are renumbered into rows of cells
  /// (DemSystem::sort_grains_into_rows): new bits, the same for any team or resume; 0: never.
  long long sort_every = 0;
};

/// Structure of arrays of all disks: grains [0, n_grains), frozen disks after them.
struct ParticleArrays {
  std::vector<double> x, y, vx, vy, w, ax, ay, alpha, r, inv_m, inv_i, mass;
  /// Positions at the last neighbour-list build, rounded to float (the displacement check
  /// adds a bound on the rounding, DemSystem::build_round_; half the memory traffic).
  std::vector<float> x_build, y_build;
};

/// The intruder: a disk with prescribed velocity and angular velocity.
struct Intruder {
  bool present = false;
  double x = 0, y = 0, r = 0;
  double vx = 0, vy = 0;        ///< m/s, constant
  double omega_target = 0;      ///< rad/s
  double spin_ramp_time = 0;    ///< s, omega rises linearly from 0 over this time
  double x_build = 0, y_build = 0;
  double t0 = 0;                ///< s, system time when the prescribed motion started
  /// @brief omega at time t after the start of the motion (rad/s).
  double omega(double t) const {
    if (spin_ramp_time <= 0 || t >= spin_ramp_time) return omega_target;
    return omega_target * (t > 0 ? t / spin_ramp_time : 0.0);
  }
};

/// Grain-intruder contact candidates with their history and last-step outputs.
struct IntruderContacts {
  std::vector<int> grain;        ///< sorted grain indices within R + r + skin at the last build
  std::vector<double> sx, sy;    ///< m, tangential springs
  std::vector<double> fx, fy;    ///< N, force on the grain
  std::vector<double> fn;        ///< N, normal force on the grain (positive repulsive)
  std::vector<double>
      ft;  ///< N, tangential force on the grain along (-n_y, n_x), n intruder->grain
  std::vector<double> nx, ny;    ///< unit normal from the intruder to the grain
  /// m/s, tangential velocity of the grain's contact point relative to the intruder's surface
  /// along (-n_y, n_x), at t+dt (the law's v_t): recorded, never used by the step
  std::vector<double> vt;
  std::vector<std::uint8_t> touching, slipping;
};

class DemSystem {
 public:
  /// Fewer grains per thread than this and the step runs on fewer threads (same results).
  static constexpr int kMinGrainsPerThread = 250;
  /// At most this many threads.
  static constexpr int kMaxTeam = 64;

  explicit DemSystem(const SystemOptions& options);

  /// @brief Replace all bodies. Velocities as given, histories cleared, accelerations
  /// recomputed at the first step.
  void set_bodies(const std::vector<Disk>& grains, const std::vector<Disk>& frozen);

  /// @brief Place the intruder (m, m/s, rad/s); its motion is prescribed from time() on.
  void set_intruder(double x, double y, double r, double vx, double vy, double omega,
                    double spin_ramp_time);
  void remove_intruder() { intruder_.present = false; }

  /// @brief Advance by one time step dt (synchronised velocity Verlet).
  void step() { advance(1); }

  /// @brief Advance by n time steps. The same results as n calls of step(), bit for bit, but
  /// faster: one OpenMP parallel region per n steps (per list rebuild), each thread on its own
  /// range of rows, and the second half kick of a step fused with the half kick and drift of the
  /// next (one pass over the particle arrays). The state is only observable between calls.
  void advance(long long n);

  /// @brief The state between two advance() calls, for a checkpoint (system_snapshot.cc).
  SystemSnapshot snapshot() const;
  /// @brief Go on from @p s, a snapshot of a system set up the same way (options, intruder,
  /// lid attached, switches): bodies, accelerations, springs, clock, intruder and lid are
  /// restored and the lists rebuilt, so that the next advance() gives the bits the
  /// snapshotted system would have given. Replaces prepare(). @throws ConfigError when the
  /// snapshot does not fit this system (another number of bodies, a lid missing).
  void restore(const SystemSnapshot& s);

  /// @brief Build the lists and compute the accelerations of the current state (done by the
  /// first step() otherwise; calling it first changes nothing in the results).
  void prepare();

  /// @brief Largest overlap / smaller diameter of the current positions (lists must be built:
  /// call prepare() first). The intruder counts with the grain's diameter.
  double current_max_overlap_fraction() const;

  /// @brief Change the Coulomb coefficients (packing preparation runs frictionless).
  void set_friction(double mu, double mu_intruder);
  /// @brief While mu = 0, evaluate the grain-grain contacts by their normal force only (no
  /// tangential kinematics, no spring history): the same forces and trajectories as the
  /// general law; the pair-force stage takes ~20% less time (docs/performance.md, Skips).
  /// Off by default: the general law stores springs even at mu = 0, which a later
  /// set_friction(mu > 0) would start from (a bed prepared frictionless, for example).
  void set_frictionless_path(bool on) { frictionless_ = on; }
  /// Whether the contacts are now evaluated by the frictionless path.
  bool frictionless_path_active() const { return frictionless_ && mu_ == 0.0; }
  /// @brief Sleeping grains (sleeping.cc): at every list build, a grain that moves at most
  /// @p speed (m/s; |v_x|, |v_y| and |omega| r each), felt no force at the last step, lies
  /// farther than kSleepReach intruder radii from the intruder's surface and whose neighbours
  /// within kSleepHops list hops are likewise quiet is stopped (v = omega = 0) and put to
  /// sleep: its pairs with other sleepers and static walls leave the list, so the step does
  /// not screen them. A sleeper touched by an awake grain wakes, and the lists are rebuilt
  /// before the next step, so no contact is ever missed. @p speed = 0 puts only grains exactly
  /// at rest to sleep (the same bits as without sleeping); < 0 turns sleeping off (default).
  /// Inactive under gravity or background damping (a grain at rest there bears contacts).
  void set_sleep(double speed) { sleep_speed_ = speed; }
  /// Grains asleep after the last list build.
  int sleeping() const { return sleeping_now_; }
  /// Grain-steps spent asleep so far (a grain woken inside a segment counts to its end).
  double sleeping_grain_steps() const { return sleep_grain_steps_; }
  /// List builds forced by a sleeper woken by contact.
  int wake_builds() const { return wake_builds_; }
  /// Grains woken by contact so far.
  long long woken() const { return woken_; }
  /// @brief Extra viscous drag on grains, dv/dt = -rate v (packing preparation only; 1/s).
  void set_background_damping(double rate) { damping_rate_ = rate; }
  /// @brief Multiply every grain radius by factor (soft compression by radius growth).
  void scale_grain_radii(double factor);
  /// @brief Keep the per-pair forces in neighbors().fx/fy/q (default on; the contact stress
  /// of the fields reads them): those of the last step of each advance() call (what is read
  /// after it), and every step those of the pairs with a frozen disk (the lid's force, read
  /// inside it); the other pairs hold zero. Off, a one-thread run skips those stores; the
  /// forces on the bodies are the same bits either way.
  void set_store_pair_forces(bool on) {
    on = on || lid_.has_value();  // the lid reads them
    if (on != store_pair_forces_) full_history_check_ = true;
    store_pair_forces_ = on;
  }
  /// @brief Set every grain velocity and angular velocity to zero.
  void zero_velocities();
  /// @brief Make @p lid a boundary of the system: after the forces of every step it moves its
  /// frozen disks under the force the grains exert on them (stage 3, see dem_system.cc). Keeps
  /// the per-pair forces (the lid's force is read from them).
  void attach_lid(const PressureLid& lid);
  /// @brief Move the frozen disks [begin, end) (indices among all bodies: grains first) by
  /// (dx, dy) m, wrapped into the box, with (vx, vy) m/s as their velocity in the contact law
  /// (a prescribed wall; the lid and the bed preparation's closing wall use it).
  void move_frozen(int begin, int end, double dx, double dy, double vx, double vy);
  /// @brief The same move after the forces of each of the next @p steps steps (before the
  /// kick), inside advance(): a wall closing at a constant speed without one advance() call
  /// per step. n calls of move_frozen each followed by step() give the bits of one move_frozen,
  /// drive_frozen(..., n - 1) and advance(n). Drives act in the order they were added;
  /// set_bodies() drops them; a snapshot (system_snapshot.cc) does not hold them.
  void drive_frozen(int begin, int end, double dx, double dy, double vx, double vy,
                    long long steps);
  /// The lid, or nullptr without one.
  const PressureLid* lid() const { return lid_ ? &*lid_ : nullptr; }
  /// @brief Force (N; x, y) of the grains on the frozen disks [begin, end) at the last step,
  /// from the stored pair forces (set_store_pair_forces(true) is needed).
  std::array<double, 2> frozen_force(int begin, int end) const;

  // ---- measurements
  double time() const { return time_; }
  std::int64_t steps() const { return steps_; }
  /// kg (per unit length), the grains' total mass: in the grains' order, or with sort_every in
  /// increasing order of mass (the same bits whatever the numbering: a resumed run's lid).
  double grain_mass() const;
  int grains() const { return n_grains_; }
  int frozen() const { return n_total_ - n_grains_; }
  const ParticleArrays& particles() const { return p_; }
  const Intruder& intruder() const { return intruder_; }
  const IntruderContacts& intruder_contacts() const { return ic_; }
  const NeighborList& neighbors() const { return nl_; }
  const PeriodicBox& box() const { return opt_.box; }
  const LawCoefficients& law() const { return law_; }
  double dt() const { return opt_.dt; }
  /// Force (N) and torque (N m) exerted by the grains on the intruder at the last step.
  double intruder_fx() const { return ifx_; }
  double intruder_fy() const { return ify_; }
  double intruder_torque() const { return itq_; }
  int intruder_touching() const { return intruder_touching_; }
  /// @brief Largest overlap / smaller diameter seen since the last call (then reset).
  double take_max_overlap_fraction();
  /// The pair with the largest overlap now: grain i, partner j (a grain, a frozen disk >=
  /// grains(), or -1 for the intruder), overlap / smaller diameter (the intruder: / the grain's).
  struct WorstOverlap {
    int i = -1, j = -1;
    double fraction = 0;
  };
  /// @brief The largest overlap of the current positions (lists built: after prepare()).
  WorstOverlap worst_overlap() const;
  /// @brief The first grain (index order) with a non-finite position or velocity, -1 if none.
  int first_non_finite_grain() const;
  /// @brief The fastest grain (largest |v| + |omega| r), -1 without grains.
  int fastest_grain() const;
  /// @brief Translational + rotational kinetic energy of the grains (J), summed in index order.
  double kinetic_energy() const;
  /// @brief Elastic energy of the normal springs, sum of (2/5) A_n delta^2 (J); tangential
  /// springs are not included (use it with mu = 0).
  double normal_elastic_energy() const;
  /// Number of neighbour-list builds so far.
  int list_builds() const { return builds_; }
  /// Threads the step may run on: min(threads, grains / kMinGrainsPerThread), at least 1.
  int threads_allowed() const { return team_max_; }
  /// Threads the step ran on for most of its steps: with more than one allowed, advance()
  /// times the step on one thread and on threads_allowed() now and then and runs on the faster
  /// (the same bits either way); see choose_team().
  int threads_used() const { return steps_on_team_ > steps_on_one_ ? team_max_ : 1; }
  /// @brief Run every step on the whole team, without the timed trials (benchmarks and tests
  /// of the threaded step; the environment variable GRAINLIFT_TEAM=fixed does the same).
  void set_team_fixed(bool on) { team_fixed_ = on; }
  /// Steps run on one thread and on the team so far.
  std::int64_t steps_on_one_thread() const { return steps_on_one_; }
  std::int64_t steps_on_team() const { return steps_on_team_; }
  /// Pairs of trials (one thread, then the team) the tuner has finished.
  std::int64_t tuner_trials() const { return tune_trials_; }

 private:
  /// The lists built again; with @p sort, the grains renumbered into rows of cells first.
  void build_lists(bool sort = false);
  /// The grains renumbered into rows of cells (bottom row first, x order within a row), every
  /// per-grain array, the list's histories and the intruder candidates with them: the order
  /// the threads' slabs of rows want, which the flow's mixing decays (grain_order.cc).
  void sort_grains_into_rows();
  /// Calls f(delta, r_i, r_j, i, j) for every listed pair (grain i, body j: a grain or a
  /// frozen disk >= grains()) and every intruder candidate (grain i, r_j = R, j = -1),
  /// delta = r_i + r_j - |x_i - x_j| of the current positions (any sign).
  template <class F>
  void for_each_gap(F f) const;
  /// Touching pairs of a range of rows: k[0, n) (k has room for every pair of the range + 1).
  struct TouchList {
    std::vector<std::int64_t> k;
    std::vector<double> dx, dy;  ///< the minimum-image x_i - x_j of each (the screen's bits)
    std::size_t n = 0;
    /// Room for @p np pairs (the screen writes before it counts), none listed.
    void size_for(std::size_t np) {
      k.resize(np + 1);
      dx.resize(np + 1);
      dy.resize(np + 1);
      n = 0;
    }
  };
  /// Pair forces of the rows of one chunk (one thread; pass 1: distance checks, pass 2:
  /// contact law), summed per grain in the pair loop. @p last_step: the last step of an
  /// advance() call, whose per-pair forces are kept (with store_pair_forces_).
  void chunk_forces(int chunk, double spring_dt, double& max_ov, bool full_check,
                    bool last_step);
  /// The same for rows [lo, hi) with their touch lists (swapped: @p now gets this step's
  /// touching pairs, @p before holds the last step's). Grains with @p shared set (a team's
  /// grains that pairs of other threads' rows reach; nullptr: none) get no sum in the pair
  /// loop: the pair forces of their pairs are stored and the kick sums them in pair order.
  void range_forces(int lo, int hi, TouchList& now, TouchList& before, double spring_dt,
                    double& max_ov, bool full_check, bool last_step,
                    const std::uint8_t* shared);
  template <bool kTeam>
  void range_forces_impl(int lo, int hi, TouchList& now, TouchList& before, double spring_dt,
                         double& max_ov, bool full_check, bool last_step,
                         const std::uint8_t* shared);
  /// The intruder's own contacts (serial, fixed order).
  void intruder_forces(double spring_dt, double& max_ov);
  enum class Kick { first, sync, drift };
  /// Accelerations of rows [lo, hi) from the forces; with Kick::sync/drift the second half
  /// kick, with Kick::drift also the half kick and drift of the next step. Returns the
  /// largest squared displacement since the last build (drift only).
  /// On a team (@p team), the team's shared grains (shared_rows_) first sum their stored pair
  /// forces (range_forces) into fxy_, tq_, where the kick then finds them as any grain's.
  double finish_rows(int lo, int hi, Kick mode, bool team);
  template <Kick kMode>
  double finish_impl(int lo, int hi);
  /// Half kick and drift of rows [lo, hi); returns the largest squared displacement.
  double drift_rows(int lo, int hi);
  /// Move the intruder by one step; returns its displacement since the last build.
  double drift_intruder();
  /// Work item @p c of the drift that opens a segment: 0 the intruder (its displacement into
  /// @p idisp; returns 0), 1 + k the rows of chunk k (returns their largest squared displacement).
  double drift_item(int c, double& idisp);
  /// Whether the lists must be rebuilt before the next step: some grain may have moved by
  /// half the skin since the build (max_d2: largest squared displacement, m^2, plus the
  /// rounding of the build positions, radius growth and frozen-disk motion), or the intruder
  /// and a grain by the skin together. Never right after a build (fresh).
  bool rebuild_due(double max_d2, double intruder_disp, bool fresh) const;
  /// Sleeping grains (set_sleep): choose the sleepers from the new, full list and remove
  /// their pairs from it (sleeping.cc). Called by build_lists() right after the list build.
  void update_sleep();
  /// Wake the sleepers among the grains of touching pair (i, j) (pair loop; any thread).
  void wake(int i, int j);
  /// Intruder radii beyond its surface within which no grain sleeps, and the list hops over
  /// which a moving grain keeps its neighbours awake.
  static constexpr double kSleepReach = 2.0;
  static constexpr int kSleepHops = 2;
  /// The boundaries of stage 3: the lid, from the pair forces of this step.
  void step_boundaries();
  /// The clock, and the intruder's drift of the next step unless @p last (its displacement
  /// since the build into @p intruder_disp).
  void advance_clock(bool last, double& intruder_disp);
  /// The free-disk lid: each frozen disk j of [begin, end) moves by (dx, dy[j - begin]) and
  /// carries (vx, vy[j - begin]).
  void move_frozen_each(int begin, int end, double dx, const std::vector<double>& dy, double vx,
                        const std::vector<double>& vy);
  std::vector<double> lid_force_y_, lid_dy_;  ///< scratch of the free-disk lid
  /// Runs up to m steps on one thread; stops early (state drifted) when the lists need a
  /// rebuild. Returns the steps completed.
  long long run_segment(long long m);
  /// The same on a team of threads: thread t owns the rows [split_[t], split_[t + 1]) (their
  /// pairs and kicks); one barrier per step (step_schedule.cc).
  long long run_segment_team(long long m);
  /// The team's rows, its shared grains and touch lists, for the current lists
  /// (step_schedule.cc): the rows are split by the work of their pairs at the current
  /// positions, in proportion to each thread's measured speed on its last ranges.
  void plan_split();
  int chunks() const { return (n_grains_ + kChunkRows - 1) / kChunkRows; }
  static constexpr int kChunkRows = 1024;

  SystemOptions opt_;
  LawCoefficients law_;
  double mu_ = 0, mu_intruder_ = 0;
  bool frictionless_ = false;  ///< set_frictionless_path()
  double skin_ = 0;
  int team_ = 1;      ///< threads of the current segment (1 or team_max_)
  int team_max_ = 1;  ///< threads allowed
  /// The team size of the next segment: measured trials of one thread and of team_max_
  /// (kTrialSteps each), then the faster for kExploitSteps, again and again (the work per step
  /// changes as the intruder builds its front). Sets full_history_check_ on a change. The
  /// environment variable GRAINLIFT_TEAM=fixed keeps the whole team (benchmarks of the threaded
  /// step itself).
  void choose_team();
  /// Whether the exploit phase is over: its time (opt_.tune_exploit_seconds, or
  /// opt_.tune_trial_multiple times the trials'), or its time per step left its trial's
  /// (opt_.tune_stale_ratio).
  bool exploit_is_over() const;
  /// Adds a segment's steps and wall time to the current trial.
  void account_segment(long long steps, double seconds);
  /// Each trial runs kWarmSteps untimed (the other core's caches are cold and its thread asleep
  /// after a long phase on one thread), then kTrialSteps timed.
  static constexpr long long kWarmSteps = 500, kTrialSteps = 2000, kExploitSteps = 100000;
  int tune_phase_ = 0;            ///< 0: trial on one thread, 1: trial on the team, 2: exploit
  long long tune_left_ = kWarmSteps + kTrialSteps;  ///< steps left in the phase
  double tune_seconds_[2] = {0, 0};    ///< wall time of the trials (one thread, team)
  long long tune_steps_[2] = {0, 0};   ///< their steps
  int tune_best_ = 1;                  ///< team size of the exploit phase
  /// The exploit phase lasts kExploitSteps << tune_backoff_: each trial the team loses doubles
  /// it (up to kMaxBackoff), a win resets it, so that under lasting load from another process
  /// (where a team step can take ten times a one-thread step) the trials become rare.
  int tune_backoff_ = 0;
  double tune_exploit_elapsed_ = 0;  ///< s of the current exploit phase (opt_.tune_exploit_seconds)
  long long tune_exploit_steps_ = 0;  ///< its steps (opt_.tune_stale_ratio)
  std::int64_t tune_trials_ = 0;     ///< tuner_trials()
  static constexpr int kMaxBackoff = 4;
  /// seconds and steps of the team trial so far, warm-up included (account_segment's early end)
  double tune_early_seconds_ = 0;
  long long tune_early_steps_ = 0;
  static constexpr long long kEarlySteps = 200;
  bool team_fixed_ = false;            ///< set_team_fixed()
  std::int64_t steps_on_one_ = 0, steps_on_team_ = 0;
  bool store_pair_forces_ = true;
  double damping_rate_ = 0;
  double growth_since_build_ = 0;  ///< m, largest radius increase since the last build
  int n_grains_ = 0, n_total_ = 0;
  ParticleArrays p_;
  /// Per-particle sums of the pair forces, fx and fy side by side (one 16-byte addition per
  /// grain and pair), and of n x F_t, filled directly by the pair loop (in pair order; a team's
  /// shared grains are summed at the kick instead, in the same order).
  std::vector<double> fxy_, tq_;
  std::vector<TouchList> touch_;  ///< per chunk: touching pairs of the step
  std::vector<TouchList> touch_prev_;  ///< per chunk: those of the step before
  /// The history (and stored force) of a listed pair is non-zero only if the pair touched at
  /// the step before (touch_prev_), except after a list build or a change of
  /// store_pair_forces_: then the next force pass checks every pair.
  bool full_history_check_ = true;
  /// per listed pair: r_i r_j / (r_i + r_j) and 1 / (1/m_i + 1/m_j), set at the build
  std::vector<double> pair_reff_, pair_meff_;
  std::vector<double> pair_rs2_;  ///< per listed pair: (r_i + r_j)^2, set at the build
  /// Threaded step (run_segment_team, plan_split): the first row of each thread's range
  /// (team_ + 1 entries, the last n_grains_); per grain, 1 if a pair owned by another
  /// thread's rows reaches it; per thread, the touch lists of its range; the list build they
  /// were planned for.
  std::vector<int> split_;
  std::vector<std::uint8_t> shared_;
  std::vector<int> shared_rows_;  ///< the shared grains, in increasing order
  /// per thread: the rows of its range below this are read by the pairs of lower ranges; the
  /// first row of its top band (the rows from the first one owning a pair that reaches a
  /// higher range)
  std::vector<int> split_reach_, split_cross_;
  std::vector<TouchList> split_touch_, split_touch_prev_;
  int split_build_ = -1;
  /// Per thread: the estimated work of its range per step (plan_split's units), the busy
  /// seconds (pair forces and kick, not waiting) and steps run on it since the plan, and its
  /// speed (work per second, a running mean over plans; the two cores of a VM need not run
  /// at the same speed, and the cost model is approximate).
  std::vector<double> split_work_, split_busy_, split_speed_;
  long long split_steps_ = 0;
  bool radii_scaled_ = false;  ///< a radius changed since the build: pair constants stale
  bool drifted_ = false;  ///< inside advance(): the next step's kick and drift are done
  NeighborList nl_;
  std::optional<PressureLid> lid_;
  struct FrozenDrive {
    int begin, end;
    double dx, dy, vx, vy;
    long long left;  ///< steps still to move
  };
  std::vector<FrozenDrive> drives_;  ///< drive_frozen(), applied by step_boundaries()
  Intruder intruder_;
  IntruderContacts ic_;
  IntruderContacts ic_old_;
  std::vector<int> ic_slot_;  ///< per grain: index in ic_ or -1
  /// per grain: kCandidate if ic_slot_ >= 0; kAccelSet unless ax, ay, alpha hold exactly the
  /// accelerations of a grain without any force (then the final kick need not store them)
  std::vector<std::uint8_t> grain_flags_;
  static constexpr std::uint8_t kCandidate = 1, kAccelSet = 2;
  /// per grain: 1 if a listed pair of the grain touches at this step (set by the pair loop,
  /// cleared by the final kick; the kick of a grain without contact reads no pair force)
  std::vector<std::uint8_t> touched_;
  double build_round_ = 0;  ///< m, bound on the float rounding of x_build, y_build
  // ---- sleeping grains (set_sleep, sleeping.cc)
  double sleep_speed_ = -1;   ///< m/s; < 0: off
  bool sleep_active_ = false;  ///< some body is dormant in the current list
  /// per body (grains, then frozen disks): 1 if asleep (grains) or static (frozen disks):
  /// the pairs of two dormant bodies are not in the list
  std::vector<std::uint8_t> dormant_;
  std::vector<std::uint8_t> sleep_near_, sleep_next_;  ///< scratch of update_sleep()
  std::uint8_t wake_pending_ = 0;  ///< a sleeper woke: rebuild before the next step (atomic access)
  int sleeping_now_ = 0;
  double sleep_grain_steps_ = 0;
  int wake_builds_ = 0;
  long long woken_ = 0;
  double ifx_ = 0, ify_ = 0, itq_ = 0;
  int intruder_touching_ = 0;
  double max_overlap_ = 0;
  double time_ = 0;
  std::int64_t steps_ = 0;
  bool primed_ = false;
  int builds_ = 0;
};

template <class F>
inline void DemSystem::for_each_gap(F f) const {
  for (int i = 0; i < n_grains_; ++i) {
    for (std::int64_t k = nl_.first[i]; k < nl_.first[i + 1]; ++k) {
      const int j = nl_.partner[k];
      double dx = p_.x[i] - p_.x[j], dy = p_.y[i] - p_.y[j];
      opt_.box.min_image(dx, dy);
      const double rs = p_.r[i] + p_.r[j];
      f(rs - std::sqrt(dx * dx + dy * dy), p_.r[i], p_.r[j], i, j);
    }
  }
  if (!intruder_.present) return;
  for (int g : ic_.grain) {
    double dx = p_.x[g] - intruder_.x, dy = p_.y[g] - intruder_.y;
    opt_.box.min_image(dx, dy);
    const double rs = p_.r[g] + intruder_.r;
    f(rs - std::sqrt(dx * dx + dy * dy), p_.r[g], intruder_.r, g, -1);
  }
}

}  // namespace grainlift::dem
