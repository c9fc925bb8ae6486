// Tests of run_simulation: the dt check, reproducibility, fields that do not perturb the
// forces, the packing cache and the area fractions the packing reaches.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include <unistd.h>

#include "grainlift/dem/system/checkpoint.h"
#include "grainlift/dem/contact/contact_law.h"
#include "grainlift/dem/system/dem_system.h"
#include "grainlift/dem/bed/packing.h"
#include "grainlift/dem/scenes/simulation.h"
#include "grainlift/dem/step/vector_kernels.h"
#include "grainlift/shared/statistics/statistics.h"
#include "dem_beds.h"

namespace gd = grainlift::dem;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// A small Kumar-like bed: W x H grain diameters, walls top and bottom, periodic in x.
gd::DemConfig small_case(double w, double h, double phi) {
  gd::DemConfig c = grainlift::test_support::walled_bed(w, h, phi);
  const double d = c.grain_diameter;
  c.intruder_omega = 2.0 * 1.0 / (2.5 * d);  // Omega = omega R / V = 2
  c.travel = 1.0;
  c.steady_travel = 0.25;
  c.sample_every = 50;
  return c;
}

std::string temp_cache_dir(const std::string& tag) {
  return (std::filesystem::temp_directory_path() /
          ("grainlift_dem_test_" + tag + "_" + std::to_string(::getpid())))
      .string();
}

void expect_same_samples(const gd::DemOutput& a, const gd::DemOutput& b) {
  ASSERT_EQ(a.samples.size(), b.samples.size());
  ASSERT_GT(a.samples.size(), 0u);
  for (std::size_t k = 0; k < a.samples.size(); ++k) {
    ASSERT_EQ(a.samples[k].fx, b.samples[k].fx) << "sample " << k;
    ASSERT_EQ(a.samples[k].fy, b.samples[k].fy) << "sample " << k;
    ASSERT_EQ(a.samples[k].torque, b.samples[k].torque) << "sample " << k;
    ASSERT_EQ(a.samples[k].contacts, b.samples[k].contacts) << "sample " << k;
  }
  ASSERT_EQ(a.contacts.size(), b.contacts.size());
  ASSERT_EQ(a.run_max_overlap, b.run_max_overlap);  // the pair loop's largest overlap
}

/// Runs @p c with a checkpoint every 1,000 steps; returns them encoded (and the run's output
/// in @p out).
std::vector<std::vector<unsigned char>> run_with_checkpoints(const gd::DemConfig& c,
                                                             gd::DemOutput* out = nullptr) {
  std::vector<std::vector<unsigned char>> saved;
  gd::RunControl control;
  control.checkpoint_steps = 1000;
  control.checkpoint = [&](const gd::RunCheckpoint& ck) {
    saved.push_back(gd::encode_checkpoint(ck));
  };
  gd::DemOutput o = gd::run_simulation(c, {}, {}, control);
  if (out) *out = std::move(o);
  return saved;
}

/// Runs @p c from the checkpoint @p ck.
gd::DemOutput resume_from(const gd::DemConfig& c, const gd::RunCheckpoint& ck) {
  gd::RunControl go_on;
  go_on.resume = &ck;
  return gd::run_simulation(c, {}, {}, go_on);
}

}  // namespace

// Physics: dt must not exceed max_dt_fraction (0.1) of the Hertz binary collision time of two
// mean grains at the intruder's fastest surface speed (Kumar grains, 3 m/s: t_c ~ 1.4e-4 s).
// dt = 5e-5 s is refused with a ConfigError that names both numbers; Kumar's 2e-6 s passes.
TEST(Simulation, DtCheckRefusesTooLargeDt) {
  auto c = small_case(30, 20, 0.8);
  c.dt = 5e-5;
  try {
    gd::validate_config(c);
    FAIL() << "dt = 5e-5 s was accepted";
  } catch (const gd::ConfigError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("dt = 5e-05 s exceeds 0.1 of the binary collision time"), std::string::npos)
        << m;
    EXPECT_NE(m.find("use dt <="), std::string::npos) << m;
  }
  EXPECT_THROW(gd::run_simulation(c), gd::ConfigError);
  c.dt = 2e-6;
  const double tc = gd::validate_config(c);
  EXPECT_GT(tc, 1e-4);
  EXPECT_LT(tc, 2e-4);
}

// Physics: the collision time used by the dt check, t_c = 2.94328 delta_max / v, is the
// duration of an undamped head-on Hertz collision: the DEM contact of two grains at 1 m/s
// lasts t_c within 1%.
TEST(Simulation, CollisionTimeFormulaMatchesAnElasticCollision) {
  gd::ContactParams p;
  p.gamma_n = p.gamma_t = 0;
  const auto law = gd::LawCoefficients::from(p);
  const double r = 0.01, m = 20 * kPi * r * r, v = 1.0;
  const double tc = gd::hertz_collision_time(law, r, r, m, m, v);
  gd::SystemOptions o;
  o.box = {-0.5, 0.5, -0.5, 0.5, true, true};
  o.contact = p;
  o.dt = 1e-7;
  gd::DemSystem s(o);
  gd::Disk a, b;
  a.r = b.r = r;
  a.mass = b.mass = m;
  a.x = -r;
  b.x = r;
  a.vx = 0.5 * v;
  b.vx = -0.5 * v;
  s.set_bodies({a, b}, {});
  int in_contact = 0;
  for (int n = 0; n < 100000; ++n) {
    s.step();
    if (s.particles().x[1] - s.particles().x[0] < 2 * r) ++in_contact;
    else if (in_contact > 0) break;
  }
  EXPECT_NEAR(in_contact * o.dt, tc, 0.01 * tc);
}

namespace {
/// A 60 d x 40 d bed at Phi 0.8 (~2300 grains, enough for two threads), seed 11, a short run
/// (travel 0.4 d, steady from 0.1 d), its packing cached under a fresh directory named @p tag.
/// A second bed for the vector kernels: 30 d x 20 d at Phi 0.8, seed 22, 1.5 d of travel.
gd::DemConfig longer_small_case(const char* tag) {
  auto c = small_case(30, 20, 0.8);
  c.seed = 22;
  c.travel = 1.5;
  c.steady_travel = 0.5;
  c.packing_cache_dir = temp_cache_dir(tag);
  return c;
}

gd::DemConfig short_seeded_case(const char* tag) {
  auto c = small_case(60, 40, 0.8);
  c.travel = 0.4;
  c.steady_travel = 0.1;
  c.seed = 11;
  c.packing_cache_dir = temp_cache_dir(tag);
  return c;
}
}  // namespace

// Physics: the run is a deterministic function of the configuration and seed: the same seed
// gives bit-identical forces, with 1 or 2 threads (per-pair forces are summed per particle in a
// fixed order); another seed gives another bed. Tolerance: exact equality. The bed (60 d x 40 d,
// ~2300 grains) is large enough for the step to really run on 2 threads: its 4000 steps are the
// step's timing trials (DemSystem::choose_team), 2500 on one thread then the rest on two, so
// the switch of team size in the middle of a run is covered too.
TEST(Simulation, SameSeedGivesSameForcesWithAnyThreadCount) {
  auto c = short_seeded_case("seed");
  const auto a = gd::run_simulation(c);
  const auto b = gd::run_simulation(c);
  expect_same_samples(a, b);
  c.threads = 2;
  {
    // the bed really runs on two threads
    gd::SystemOptions o;
    o.threads = 2;
    gd::DemSystem s(o);
    std::vector<gd::Disk> g(a.grains);
    for (auto& disk : g) {
      disk.r = 0.01;
      disk.mass = 1;
    }
    s.set_bodies(g, {});
    EXPECT_EQ(s.threads_allowed(), 2);
  }
  const auto t2 = gd::run_simulation(c);
  expect_same_samples(a, t2);
  c.threads = 1;
  c.seed = 12;
  const auto other = gd::run_simulation(c);
  ASSERT_EQ(other.samples.size(), a.samples.size());
  bool differs = false;
  for (std::size_t k = 0; k < a.samples.size(); ++k)
    differs |= other.samples[k].fx != a.samples[k].fx;
  EXPECT_TRUE(differs);
  std::filesystem::remove_all(c.packing_cache_dir);
}

// The vector loops of the step (pair screen, kick and drift, the contact law) give the bits of
// the scalar code on every SIMD target this build and CPU run (avx2 and avx512 on a recent x86,
// neon or sve on Arm): the same run with each target and with the vector loops forbidden, on
// 1 and 2 threads, gives the same intruder samples, on two beds periodic in x, one boxed in by
// four walls and one periodic both ways (the loops have a copy per periodicity), with Kumar's
// law, and one bed with Guillard's. Tolerance: exact equality. (Without a vector target only
// the scalar runs are made.)
TEST(Simulation, VectorKernelsGiveTheBitsOfTheScalarCode) {
  auto plain = short_seeded_case("simd");
  auto longer = longer_small_case("simd_longer");
  auto walled = longer_small_case("simd_walled");
  walled.periodic_x = false;
  walled.wall_left = walled.wall_right = true;
  auto periodic = longer_small_case("simd_periodic");
  periodic.periodic_y = true;
  periodic.wall_top = periodic.wall_bottom = false;
  auto guillard = longer_small_case("simd_guillard");
  guillard.contact.law = gd::ContactLaw::guillard2014;
  guillard.contact.youngs_modulus = 5e9;  // as stiff as Kumar's grains at their dt and speed
  const std::string before = gd::simd_target();
  std::vector<std::string> targets = gd::runnable_simd_targets();
  targets.erase(targets.begin());  // "scalar", the reference
  std::printf("vector targets on this CPU: %zu\n", targets.size());
  for (gd::DemConfig* c : {&plain, &longer, &walled, &periodic, &guillard}) {
    SCOPED_TRACE(c == &plain      ? "60 d x 40 d"
                 : c == &longer   ? "30 d x 20 d"
                 : c == &walled   ? "walled"
                 : c == &periodic ? "periodic x and y"
                                  : "Guillard's law");
    for (int threads : {1, 2}) {
      c->threads = threads;
      gd::set_vector_kernels(false);
      const auto scalar = gd::run_simulation(*c);
      gd::set_vector_kernels(true);
      for (const std::string& t : targets) {
        SCOPED_TRACE(t);
        ASSERT_TRUE(gd::set_simd_target(t));
        EXPECT_EQ(gd::simd_target(), t);  // the code the dispatch calls names itself so
        expect_same_samples(gd::run_simulation(*c), scalar);
      }
    }
    std::filesystem::remove_all(c->packing_cache_dir);
  }
  gd::set_simd_target(before);
}

// Physics: with mu = 0 between grains the Coulomb cap makes every tangential force zero, so
// the frictionless path (normal forces only, no spring history) gives the same trajectories:
// the intruder's samples are bit-identical to the general law's (exact equality), on one and
// on two threads, with the per-pair forces stored (fields on) or not. The intruder keeps
// its friction (0.5): grains it spins carry angular velocity into grain-grain contacts.
TEST(Simulation, FrictionlessPathGivesTheBitsOfTheGeneralLaw) {
  auto c = small_case(30, 20, 0.8);
  c.seed = 9;
  c.contact.friction = 0.0;
  c.packing_cache_dir = temp_cache_dir("frictionless");
  for (int threads : {1, 2}) {
    for (bool fields : {false, true}) {
      c.threads = threads;
      c.fields.enabled = fields;
      c.fields.spacing = 0.5 * c.grain_diameter;
      c.fields.x0 = c.fields.y0 = -4 * c.grain_diameter;
      c.fields.nx = c.fields.ny = 16;
      c.frictionless_path = true;
      const auto fast = gd::run_simulation(c);
      c.frictionless_path = false;
      const auto general = gd::run_simulation(c);
      EXPECT_TRUE(fast.frictionless_path);
      EXPECT_FALSE(general.frictionless_path);
      expect_same_samples(fast, general);
    }
  }
  c.contact.friction = 0.5;  // with friction the switch does nothing
  c.frictionless_path = true;
  EXPECT_FALSE(gd::run_simulation(c).frictionless_path);
  std::filesystem::remove_all(c.packing_cache_dir);
}

// Physics: a grain at rest with no force and neighbours at rest stays exactly where it is until
// something touches it; sleeping at speed 0 stops no grain that moves, so the run must give the
// trajectories of a run without sleeping: the intruder's samples bit-identical (exact
// equality), on one and two threads, and with a pressure lid (whose disks move: grains by it
// stay awake). The scene must really exercise the path: over the run at least 5% of the
// grain-steps asleep (10-13% measured), and grains woken by contact (the front reaching them).
TEST(Simulation, SleepingAtZeroSpeedGivesTheBitsOfARunWithout) {
  auto c = small_case(60, 24, 0.8);
  c.seed = 13;
  c.travel = 3.0;
  c.steady_travel = 0.5;
  c.packing_cache_dir = temp_cache_dir("sleep");
  for (double lid : {0.0, 200.0}) {
    for (int threads : {1, 2}) {
      c.lid_pressure = lid;
      c.threads = threads;
      c.sleep_speed = 0.0;
      const auto asleep = gd::run_simulation(c);
      c.sleep_speed = -1.0;
      const auto awake = gd::run_simulation(c);
      SCOPED_TRACE("lid " + std::to_string(lid) + " N/m, threads " + std::to_string(threads));
      EXPECT_GT(asleep.sleeping_fraction, 0.05);
      EXPECT_GT(asleep.sleep_wakes, 0);
      EXPECT_EQ(awake.sleeping_fraction, 0.0);
      expect_same_samples(asleep, awake);
    }
  }
  std::filesystem::remove_all(c.packing_cache_dir);
}

// Physics: with sleep_speed > 0 grains that still creep (at most 5% of V0 here, far above the
// default 0) are stopped when they fall asleep: an approximation of the far field only, so
// the mean drag and lift over the steady part must stay within three combined standard
// errors (block averages) of the run without sleeping, while at least 5% of the grain-steps are
// asleep.
TEST(Simulation, SleepingSlowGrainsKeepsTheForcesWithinTheirErrors) {
  auto c = small_case(60, 24, 0.8);
  c.seed = 14;
  c.travel = 4.0;
  c.steady_travel = 1.0;
  c.packing_cache_dir = temp_cache_dir("sleep_slow");
  c.sleep_speed = 0.05 * std::hypot(c.intruder_velocity[0], c.intruder_velocity[1]);
  const auto asleep = gd::run_simulation(c);
  c.sleep_speed = -1.0;
  const auto awake = gd::run_simulation(c);
  EXPECT_GT(asleep.sleeping_fraction, 0.05);
  for (int axis : {0, 1}) {
    const auto stats = [&](const gd::DemOutput& o) {
      std::vector<double> v;
      for (std::size_t k = o.steady_start_index; k < o.samples.size(); ++k) {
        v.push_back(axis == 0 ? o.samples[k].fx : o.samples[k].fy);
      }
      return grainlift::block_mean(v, 10);
    };
    const auto a = stats(asleep), b = stats(awake);
    const double ea = a.stderr_corrected, eb = b.stderr_corrected, combined = std::hypot(ea, eb);
    EXPECT_LE(std::abs(a.mean - b.mean), 3.0 * combined)
        << (axis == 0 ? "drag" : "lift") << ": " << a.mean << " +- " << ea << " asleep against "
        << b.mean << " +- " << eb;
    EXPECT_GT(combined, 0.0);
    std::printf("%s: %.4g +- %.2g N/m asleep (%.1f%% of grain-steps), %.4g +- %.2g N/m awake\n",
                axis == 0 ? "fx" : "fy", a.mean, ea, 100 * asleep.sleeping_fraction, b.mean,
                eb);
  }
  std::filesystem::remove_all(c.packing_cache_dir);
}

// Physics: a checkpoint holds the whole state between two steps (grains, accelerations,
// springs, intruder, lid, outputs and field sums so far), so a run resumed from it must give
// what the uninterrupted run gives: the same samples, contacts, lid and field sums, bit for
// bit (exact equality), on one and two threads, with fields and a lid (its disks move), and
// with the grains renumbered every 700 steps (dem.sort_every). The checkpoint goes through its
// byte encoding, and a flipped byte or a cut file is refused.
TEST(Simulation, ResumedRunGivesTheBitsOfTheUninterruptedRun) {
  auto c = small_case(30, 20, 0.8);
  c.seed = 21;
  c.travel = 1.5;
  c.steady_travel = 0.5;
  c.fields.enabled = true;
  c.fields.spacing = 0.5 * c.grain_diameter;
  c.fields.x0 = c.fields.y0 = -4 * c.grain_diameter;
  c.fields.nx = c.fields.ny = 16;
  c.field_every = 100;
  c.packing_cache_dir = temp_cache_dir("resume");
  for (double lid : {0.0, 300.0}) {
    for (int threads : {1, 2}) {
      SCOPED_TRACE("lid " + std::to_string(lid) + " N/m, threads " + std::to_string(threads));
      c.lid_pressure = lid;
      c.threads = threads;
      // with the lid on two threads, the grains renumbered every 700 steps (not at the
      // checkpoint's step: the resumed run's list build there must not renumber)
      c.sort_every = lid > 0 && threads == 2 ? 700 : 0;
      const auto whole = gd::run_simulation(c);
      // a checkpoint every 1,000 steps; keep the second (past the steady start: contacts, fields)
      gd::DemOutput with_checkpoints;
      const auto saved = run_with_checkpoints(c, &with_checkpoints);
      expect_same_samples(whole, with_checkpoints);
      ASSERT_GE(saved.size(), 2u);
      const gd::RunCheckpoint ck = gd::decode_checkpoint(saved[1]);
      EXPECT_EQ(ck.step, 2000);
      const auto resumed = resume_from(c, ck);
      EXPECT_EQ(resumed.resumed_from_step, 2000);
      expect_same_samples(whole, resumed);
      ASSERT_EQ(whole.contacts.size(), resumed.contacts.size());
      for (std::size_t k = 0; k < whole.contacts.size(); ++k) {
        ASSERT_EQ(whole.contacts[k].fn, resumed.contacts[k].fn) << "contact " << k;
        ASSERT_EQ(whole.contacts[k].theta, resumed.contacts[k].theta) << "contact " << k;
        ASSERT_EQ(whole.contacts[k].vt, resumed.contacts[k].vt) << "contact " << k;
      }
      ASSERT_EQ(whole.lid.size(), resumed.lid.size());
      for (std::size_t k = 0; k < whole.lid.size(); ++k) {
        ASSERT_EQ(whole.lid[k].y, resumed.lid[k].y) << "lid sample " << k;
      }
      EXPECT_EQ(whole.fields.snapshots, resumed.fields.snapshots);
      EXPECT_EQ(whole.fields.sxx, resumed.fields.sxx);
      EXPECT_EQ(whole.fields.area_fraction, resumed.fields.area_fraction);
      // damaged bytes are refused, never read
      auto flipped = saved[1];
      flipped[flipped.size() / 2] ^= 0x10;
      EXPECT_THROW(gd::decode_checkpoint(flipped), gd::CheckpointError);
      auto cut = saved[1];
      cut.resize(cut.size() / 3);
      EXPECT_THROW(gd::decode_checkpoint(cut), gd::CheckpointError);
    }
  }
  // a checkpoint of another run length is refused
  c.lid_pressure = 0;
  c.threads = 1;
  const gd::RunCheckpoint ck = gd::decode_checkpoint(run_with_checkpoints(c).at(0));
  c.travel = 2.0;
  EXPECT_THROW(resume_from(c, ck), gd::ConfigError);
  std::filesystem::remove_all(c.packing_cache_dir);
}

// Physics: without gravity a bed at rest overlaps only when it is compressed beyond jamming
// (these disks jam near Phi 0.84). At Phi 0.9 the prepared bed overlaps by ~6% of a diameter at
// rest, more than half of max_overlap_fraction (0.1): the run is refused before its first step
// (ConfigError naming jamming, the overlap and the limit), where it used to fail on an overlap
// a few thousand steps in. Phi 0.86, jammed but with headroom, still runs.
TEST(Simulation, BedBeyondJammingIsRefusedBeforeTheRun) {
  auto c = small_case(30, 20, 0.9);
  c.seed = 3;
  c.travel = 0.2;
  c.steady_travel = 0.05;
  c.packing_cache_dir = temp_cache_dir("jam");
  try {
    gd::run_simulation(c);
    ADD_FAILURE() << "a bed at Phi 0.9 without gravity ran";
  } catch (const gd::ConfigError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("beyond jamming"), std::string::npos) << m;
    EXPECT_NE(m.find("max_overlap_fraction = 0.1"), std::string::npos) << m;
  }
  c.area_fraction = 0.86;
  const auto out = gd::run_simulation(c);
  EXPECT_GT(out.bed_max_overlap, 1e-3);  // jammed: it overlaps at rest
  EXPECT_LT(out.bed_max_overlap, 0.05);
  std::filesystem::remove_all(c.packing_cache_dir);
}

// Physics: coarse graining only reads the state, so turning the fields on leaves the forces
// bit-identical (exact equality). The fields themselves are sane: no grain inside the intruder
// (area fraction 0 within 0.9 R), the far field near the bed's Phi (within 0.15), and the
// contact stress compressive (negative trace) in front of the intruder.
TEST(Simulation, FieldsOnOrOffLeaveForcesBitIdentical) {
  auto c = small_case(30, 20, 0.8);
  c.seed = 5;
  const auto off = gd::run_simulation(c);
  const double d = c.grain_diameter;
  c.fields.enabled = true;
  c.fields.spacing = 0.25 * d;
  c.fields.x0 = -6 * d;
  c.fields.y0 = -6 * d;
  c.fields.nx = 48;
  c.fields.ny = 48;
  c.field_every = 100;
  const auto on = gd::run_simulation(c);
  expect_same_samples(off, on);
  const auto& f = on.fields;
  ASSERT_EQ(f.nx, 48);
  ASSERT_GT(f.snapshots, 0);
  auto bin = [&](double x, double y) {
    const int i = static_cast<int>(std::floor((x - c.fields.x0) / c.fields.spacing));
    const int j = static_cast<int>(std::floor((y - c.fields.y0) / c.fields.spacing));
    return static_cast<std::size_t>(j) * f.nx + i;
  };
  EXPECT_EQ(f.area_fraction[bin(0.1 * d, 0.1 * d)], 0.0);
  double far = 0;
  int n = 0;
  for (double y = -5.5 * d; y <= 5.5 * d; y += 0.25 * d) {
    far += f.area_fraction[bin(-5.8 * d, y)];
    ++n;
  }
  EXPECT_NEAR(far / n, 0.8, 0.15);
  double trace = 0;
  for (double y = -2 * d; y <= 2 * d; y += 0.25 * d) {
    for (double x = 2.6 * d; x <= 3.6 * d; x += 0.25 * d) {
      trace += f.sxx[bin(x, y)] + f.syy[bin(x, y)];
    }
  }
  EXPECT_LT(trace, 0.0);
}

// Physics: a prepared bed is saved under packing_cache_dir and reused; the run from the cache
// gives bit-identical forces (the run always starts from rest with empty contact history).
TEST(Simulation, PackingCacheIsReusedWithIdenticalForces) {
  auto c = small_case(30, 20, 0.6);
  c.packing_cache_dir = temp_cache_dir("cache");
  std::filesystem::remove_all(c.packing_cache_dir);
  const auto first = gd::run_simulation(c);
  EXPECT_FALSE(first.packing_from_cache);
  EXPECT_TRUE(std::filesystem::exists(gd::packing_cache_path(c)));
  const auto second = gd::run_simulation(c);
  EXPECT_TRUE(second.packing_from_cache);
  expect_same_samples(first, second);
  std::filesystem::remove_all(c.packing_cache_dir);
}

// A damaged cache entry (one byte flipped in its positions), a truncated one and one of the
// older format without a checksum (issue 37) are each reported as a cache problem naming the
// file, removed and rebuilt; the run's forces equal those of a clean cache bit for bit, and the
// rebuilt entry is used again by the next run.
TEST(Simulation, DamagedPackingCacheIsReportedRemovedAndRebuilt) {
  auto c = small_case(30, 20, 0.6);
  c.packing_cache_dir = temp_cache_dir("damaged_cache");
  std::filesystem::remove_all(c.packing_cache_dir);
  const auto clean = gd::run_simulation(c);
  const std::string path = gd::packing_cache_path(c);
  const auto rewrite = [&](const std::function<void(std::string&)>& damage) {
    std::ifstream in(path, std::ios::binary);
    std::string b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    in.close();
    damage(b);
    std::ofstream(path, std::ios::binary | std::ios::trunc) << b;
  };
  const std::vector<std::pair<std::string, std::function<void(std::string&)>>> damages{
      {"damaged (checksum mismatch)", [](std::string& b) { b[b.size() / 2] ^= 0x5a; }},
      {"damaged (its length", [](std::string& b) { b.resize(b.size() - 100); }},
      {"of an older format", [](std::string& b) { b[7] = '1'; }}};
  for (const auto& [why, damage] : damages) {
    SCOPED_TRACE(why);
    rewrite(damage);
    const auto again = gd::run_simulation(c);
    EXPECT_FALSE(again.packing_from_cache);
    EXPECT_NE(again.packing_cache_note.find(path), std::string::npos) << again.packing_cache_note;
    EXPECT_NE(again.packing_cache_note.find(why), std::string::npos) << again.packing_cache_note;
    expect_same_samples(clean, again);
    const auto reused = gd::run_simulation(c);
    EXPECT_TRUE(reused.packing_from_cache);
    EXPECT_TRUE(reused.packing_cache_note.empty());
  }
  std::filesystem::remove_all(c.packing_cache_dir);
}

// Physics: the packing reaches the requested area fraction (grain area over the box minus the
// wall strips and the intruder) within 0.01 for a dilute (insertion), intermediate (0.78 then
// removal) and dense (radius growth) bed, and leaves it relaxed: no overlap above 1% of d.
TEST(Simulation, PackingReachesTheAreaFraction) {
  for (double phi : {0.35, 0.6, 0.82}) {
    auto c = small_case(30, 20, phi);
    const auto bed = gd::prepare_packing(c);
    EXPECT_NEAR(bed.area_fraction, phi, 0.01) << "Phi = " << phi;
    double worst = 0;
    for (std::size_t i = 0; i < bed.r.size(); ++i) {
      for (std::size_t j = i + 1; j < bed.r.size(); ++j) {
        double dx = bed.x[i] - bed.x[j];
        const double lx = c.xmax - c.xmin;
        dx -= lx * std::round(dx / lx);
        const double dy = bed.y[i] - bed.y[j];
        const double ov = bed.r[i] + bed.r[j] - std::hypot(dx, dy);
        worst = std::max(worst, ov / c.grain_diameter);
      }
    }
    EXPECT_LT(worst, 0.01) << "Phi = " << phi;
  }
}

// Physics: a run that violates the soft-contact assumption fails loudly. An intruder at
// 200 m/s (the dt check told to assume 0.5 m/s impacts) presses grains by ~0.2 d, above
// max_overlap_fraction = 0.1: RunFailure, naming the overlap and the limit.
TEST(Simulation, ExcessiveOverlapIsARunFailure) {
  auto c = small_case(30, 20, 0.6);
  c.intruder_velocity = {200.0, 0.0};
  c.intruder_omega = 0;
  c.dt_check_velocity = 0.5;
  c.travel = 3;
  c.sample_every = 5;
  try {
    gd::run_simulation(c);
    FAIL() << "the run did not fail";
  } catch (const gd::RunFailure& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("max_overlap_fraction = 0.1"), std::string::npos) << m;
  }
}

// Physics (sign conventions of DemOutput::contacts, Kumar Sec. III): an intruder moving along
// +x spinning counter-clockwise with Omega = 2 slides against every grain it meets
// (V_t,P = V (Omega - sin theta) > 0), so the friction on the intruder is clockwise: ft < 0 for
// (at least 90% of) the slipping contacts, ft ~ -mu fn there (1e-6 relative). Contacts sit on the
// front (|theta| < pi/2 for at least 80% of them) and are compressive (mean fn > 0). The
// torque of the grains opposes the spin (mean torque < 0). The slip velocity vt (the surface
// against the grain) is counter-clockwise (> 0) at 90% of the slipping contacts, and the
// friction on the intruder opposes it (ft vt < 0) at 90% of them: a Coulomb contact.
TEST(Simulation, IntruderContactSignConventions) {
  auto c = small_case(30, 20, 0.3);
  c.travel = 4;
  c.steady_travel = 0.5;
  c.sample_every = 10;
  const auto out = gd::run_simulation(c);
  ASSERT_GT(out.contacts.size(), 50u);
  int front = 0, slipping = 0, clockwise = 0, ccw_slip = 0, opposing = 0;
  double fn_sum = 0;
  for (const auto& k : out.contacts) {
    if (std::abs(k.theta) < 0.5 * kPi) ++front;
    fn_sum += k.fn;
    EXPECT_GT(k.theta, -kPi);
    EXPECT_LE(k.theta, kPi);
    if (k.slipping) {
      ++slipping;
      if (k.ft < 0) ++clockwise;
      if (k.vt > 0) ++ccw_slip;
      if (k.ft * k.vt < 0) ++opposing;
      EXPECT_NEAR(std::abs(k.ft), 0.5 * std::abs(k.fn), 1e-6 * std::abs(k.fn));
    }
  }
  const double n = static_cast<double>(out.contacts.size());
  EXPECT_GT(front / n, 0.8);
  EXPECT_GT(fn_sum, 0.0);
  ASSERT_GT(slipping, 10);
  EXPECT_GT(clockwise, 0.9 * slipping);
  EXPECT_GT(ccw_slip, 0.9 * slipping);
  EXPECT_GT(opposing, 0.9 * slipping);
  double torque = 0;
  for (std::size_t i = out.steady_start_index; i < out.samples.size(); ++i)
    torque += out.samples[i].torque;
  EXPECT_LT(torque, 0.0);
}

// Physics: a bed prepared under gravity (Guillard grains, 40 d x 30 d, periodic in x, bottom
// wall, free surface) with a strict relax_ke = 1e-12 J per grain is at rest and lithostatic:
// the bottom wall and the fixed intruder together carry the weight of the grains within 2%
// (measured 0.7%; no side walls, so no Janssen screening), and over 1000 steps at rest the grains
// move by less than 0.01 d on average. (Relaxed only to the default 1e-9 J, the same bed is not
// settled yet: its supports carry 72% of its weight.)
// The frictionless stage stops at 1e-9 J and the frictional one reaches 1e-12 J (packing.cc).
TEST(Simulation, PackingUnderGravityIsAtRestAndCarriesItsWeight) {
  gd::DemConfig c;
  const double d = 0.0015;
  c.grain_diameter = d;
  c.density = 2.5;
  c.xmin = -20 * d;
  c.xmax = 20 * d;
  c.ymin = -15 * d;
  c.ymax = 15 * d;
  c.wall_bottom = true;
  c.gravity = {0.0, -9.81};
  c.area_fraction = 0.82;
  c.contact.law = gd::ContactLaw::guillard2014;
  c.intruder_diameter = 5 * d;
  c.dt = 1e-5;
  c.relax_ke_per_grain = 1e-12;
  const auto bed = gd::prepare_packing(c);
  gd::SystemOptions o;
  o.box = {c.xmin, c.xmax, c.ymin, c.ymax, true, false};
  o.contact = c.contact;
  o.dt = c.dt;
  o.gravity = c.gravity;
  gd::DemSystem s(o);
  std::vector<gd::Disk> grains(bed.r.size());
  double weight = 0;
  for (std::size_t n = 0; n < grains.size(); ++n) {
    grains[n].x = bed.x[n];
    grains[n].y = bed.y[n];
    grains[n].r = bed.r[n];
    grains[n].mass = c.density * kPi * bed.r[n] * bed.r[n];
    weight += grains[n].mass * 9.81;
  }
  const auto walls = gd::make_wall_disks(c);
  s.set_bodies(grains, walls);
  s.set_intruder(0, 0, 0.5 * c.intruder_diameter, 0, 0, 0, 0);
  s.prepare();
  // Forces on the grains balance: bottom wall (-bottom, up) + intruder (-fy) = weight. The fixed
  // intruder is pushed up by the grains grown under it (fy > 0): the wall carries that too.
  const double bottom = s.frozen_force(s.grains(), s.grains() + static_cast<int>(walls.size()))[1];
  EXPECT_NEAR(-bottom - s.intruder_fy(), weight, 0.02 * weight);
  for (int k = 0; k < 1000; ++k) s.step();
  double moved = 0;
  for (int i = 0; i < s.grains(); ++i) {
    double dx = s.particles().x[i] - bed.x[i];
    dx -= (c.xmax - c.xmin) * std::round(dx / (c.xmax - c.xmin));
    moved += std::hypot(dx, s.particles().y[i] - bed.y[i]);
  }
  EXPECT_LT(moved / s.grains(), 0.01 * d);
}
