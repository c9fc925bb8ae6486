// Calibrating mu(I) and Phi(I) on simple-shear points: the fits recover known laws from synthetic
// data (exactly without noise, within their own error bars with noise), the error bars have the
// size of the actual scatter, bad inputs are refused, and the rheology file round-trips.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <regex>

#include "grainlift/shared/errors.h"
#include "grainlift/shared/rheology/rheology_file.h"
#include "grainlift/shared/rheology/rheology_fit.h"

using namespace grainlift;
namespace fs = std::filesystem;

namespace {

struct Law {
  double mu_s, mu_2, I0;
};
constexpr Law soft_law{0.26, 0.80, 0.30};   // frictional DEM disks, wide mu range
constexpr Law jop_law{0.38, 0.64, 0.279};   // Jop, Forterre & Pouliquen 2006 (glass beads)
constexpr double phi_max = 0.81, phi_slope = 0.3;

/// @p n inertial numbers log-spaced from 1e-3 to 0.5 (the span of a DEM shear-cell campaign),
/// mu from @p law and Phi = 0.81 - 0.3 I, plus N(0, sigma^2) noise when @p rng is given.
/// The stated standard errors are the true sigmas.
std::vector<ShearPoint> synthetic(const Law& law, double sigma_mu, double sigma_phi,
                                  std::mt19937_64* rng, int n = 10) {
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<ShearPoint> pts;
  for (int k = 0; k < n; ++k) {
    const double I = 1e-3 * std::pow(0.5 / 1e-3, k / double(n - 1));
    ShearPoint p{I, jop_mu(I, law.mu_s, law.mu_2, law.I0), sigma_mu, phi_max - phi_slope * I,
                 sigma_phi};
    if (rng) {
      p.mu += sigma_mu * noise(*rng);
      p.phi += sigma_phi * noise(*rng);
    }
    pts.push_back(p);
  }
  return pts;
}

fs::path scratch_dir(const std::string& name) {
  fs::path d = fs::temp_directory_path() /
               ("grainlift_rheology_" + name + "_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST(RheologyFit, JopLawHasItsLimits) {
  // mu(0) = mu_s, mu(I0) = (mu_s + mu_2) / 2, mu -> mu_2 as I -> infinity: to round-off.
  EXPECT_DOUBLE_EQ(jop_mu(0.0, 0.38, 0.64, 0.279), 0.38);
  EXPECT_NEAR(jop_mu(0.279, 0.38, 0.64, 0.279), 0.51, 1e-15);
  EXPECT_NEAR(jop_mu(1e12, 0.38, 0.64, 0.279), 0.64, 1e-12);
}

TEST(RheologyFit, NoiseFreePointsGiveTheLawBack) {
  // Points lying on the law: the least-squares minimum is the law itself, chi2 = 0. Recovered
  // to 1e-6 relative from start values that are off by up to a factor 2 (I0 = median I).
  for (const Law& law : {soft_law, jop_law}) {
    const MuIFit f = fit_mu_i(synthetic(law, 0.005, 0.002, nullptr));
    EXPECT_TRUE(f.converged) << f.message;
    EXPECT_EQ(f.points, 10);
    EXPECT_NEAR(f.mu_s, law.mu_s, 1e-6 * law.mu_s);
    EXPECT_NEAR(f.mu_2, law.mu_2, 1e-6 * law.mu_2);
    EXPECT_NEAR(f.I0, law.I0, 1e-6 * law.I0);
    EXPECT_LT(f.chi2_per_dof, 1e-12);
  }
}

TEST(RheologyFit, NoisyPointsGiveTheLawWithinThreeSigma) {
  // Gaussian noise of the stated size (sigma_mu = 0.005, typical of a DEM shear-cell mean):
  // each parameter within 3 of its reported errors of the truth, and chi2/dof (7 degrees of
  // freedom) in [0.3, 2.5], where a fair draw lies with probability 0.94. Seeds are fixed, so
  // the test is deterministic; three seeds per law.
  for (const Law& law : {soft_law, jop_law}) {
    for (std::uint64_t seed : {11u, 12u, 13u}) {
      std::mt19937_64 rng(seed);
      const MuIFit f = fit_mu_i(synthetic(law, 0.005, 0.002, &rng));
      SCOPED_TRACE(::testing::Message() << "law mu_s " << law.mu_s << ", seed " << seed);
      std::cout << "mu_s " << f.mu_s << " +- " << f.mu_s_err << ", mu_2 " << f.mu_2 << " +- "
                << f.mu_2_err << ", I0 " << f.I0 << " +- " << f.I0_err << ", chi2/dof "
                << f.chi2_per_dof << " (truth " << law.mu_s << ", " << law.mu_2 << ", "
                << law.I0 << ")\n";
      EXPECT_TRUE(f.converged) << f.message;
      EXPECT_NEAR(f.mu_s, law.mu_s, 3 * f.mu_s_err);
      EXPECT_NEAR(f.mu_2, law.mu_2, 3 * f.mu_2_err);
      EXPECT_NEAR(f.I0, law.I0, 3 * f.I0_err);
      EXPECT_GE(f.chi2_per_dof, 0.3);
      EXPECT_LE(f.chi2_per_dof, 2.5);
      // The errors are not vacuous: each is smaller than the parameter itself.
      EXPECT_LT(f.mu_s_err, 0.1 * law.mu_s);
      EXPECT_LT(f.mu_2_err, law.mu_2);
      EXPECT_LT(f.I0_err, law.I0);
      // Covariance is symmetric and its diagonal gives the errors.
      EXPECT_DOUBLE_EQ(f.covariance[0][1], f.covariance[1][0]);
      EXPECT_DOUBLE_EQ(std::sqrt(f.covariance[2][2]), f.I0_err);
    }
  }
}

TEST(RheologyFit, ReportedErrorsMatchTheScatterOverRealisations) {
  // The reported mu_s_err must be the standard deviation of mu_s over repeated experiments.
  // 200 seeded noise realisations: the sample standard deviation of the fitted mu_s is within
  // 25 % of the mean reported mu_s_err (its own sampling error is 1/sqrt(2 * 199) = 5 %; the
  // chi2/dof > 1 rescaling inflates the mean reported error by a few %). The mean of mu_s
  // is unbiased within 3 standard errors of the mean.
  std::mt19937_64 rng(2026);
  const int n = 200;
  double sum = 0, sum2 = 0, err_sum = 0;
  double mu2_sum = 0, mu2_sum2 = 0, mu2_err_sum = 0;
  for (int r = 0; r < n; ++r) {
    const MuIFit f = fit_mu_i(synthetic(soft_law, 0.005, 0.002, &rng));
    ASSERT_TRUE(f.converged) << "realisation " << r << ": " << f.message;
    sum += f.mu_s;
    sum2 += f.mu_s * f.mu_s;
    err_sum += f.mu_s_err;
    mu2_sum += f.mu_2;
    mu2_sum2 += f.mu_2 * f.mu_2;
    mu2_err_sum += f.mu_2_err;
  }
  const double mean = sum / n;
  const double scatter = std::sqrt((sum2 - n * mean * mean) / (n - 1));
  const double reported = err_sum / n;
  const double mu2_mean = mu2_sum / n;
  const double mu2_scatter = std::sqrt((mu2_sum2 - n * mu2_mean * mu2_mean) / (n - 1));
  std::cout << "mu_s: mean " << mean << ", scatter " << scatter << ", mean reported error "
            << reported << ", ratio " << scatter / reported << "\n"
            << "mu_2: mean " << mu2_mean << ", scatter " << mu2_scatter
            << ", mean reported error " << mu2_err_sum / n << ", ratio "
            << mu2_scatter / (mu2_err_sum / n) << "\n";
  EXPECT_NEAR(scatter / reported, 1.0, 0.25);
  EXPECT_NEAR(mean, soft_law.mu_s, 3 * scatter / std::sqrt(double(n)));
}

TEST(RheologyFit, DilatancyLawWithinThreeSigma) {
  // Phi = 0.81 - 0.3 I: without noise exact to 1e-12; with sigma_phi = 0.002 noise each
  // parameter within 3 of its reported errors and chi2/dof (8 dof) in [0.3, 2.5].
  const PhiFit exact = fit_phi_i(synthetic(soft_law, 0.005, 0.002, nullptr));
  EXPECT_NEAR(exact.phi_max, phi_max, 1e-12);
  EXPECT_NEAR(exact.a, phi_slope, 1e-12);
  EXPECT_EQ(exact.points, 10);
  for (std::uint64_t seed : {5u, 6u, 7u}) {
    std::mt19937_64 rng(seed);
    const PhiFit f = fit_phi_i(synthetic(soft_law, 0.005, 0.002, &rng));
    std::cout << "phi_max " << f.phi_max << " +- " << f.phi_max_err << ", a " << f.a << " +- "
              << f.a_err << ", chi2/dof " << f.chi2_per_dof << "\n";
    EXPECT_NEAR(f.phi_max, phi_max, 3 * f.phi_max_err);
    EXPECT_NEAR(f.a, phi_slope, 3 * f.a_err);
    EXPECT_GE(f.chi2_per_dof, 0.3);
    EXPECT_LE(f.chi2_per_dof, 2.5);
    // Unweighted-equivalent error of phi_max: sigma / sqrt(n) at least (10 points).
    EXPECT_GT(f.phi_max_err, 0.002 / std::sqrt(10.0));
  }
}

TEST(RheologyFit, RefusesTooFewPointsAndBadErrors) {
  // Three parameters need >= 4 points (chi2/dof needs one degree of freedom), weights 1/se^2
  // need se > 0, and the law needs at least 3 distinct inertial numbers.
  auto pts = synthetic(soft_law, 0.005, 0.002, nullptr);
  EXPECT_THROW(fit_mu_i({pts.begin(), pts.begin() + 3}), std::invalid_argument);
  EXPECT_NO_THROW(fit_mu_i({pts.begin(), pts.begin() + 4}));
  EXPECT_THROW(fit_phi_i({pts.begin(), pts.begin() + 2}), std::invalid_argument);
  auto zero = pts;
  zero[3].mu_stderr = 0;
  EXPECT_THROW(fit_mu_i(zero), std::invalid_argument);
  zero[3].mu_stderr = -0.01;
  EXPECT_THROW(fit_mu_i(zero), std::invalid_argument);
  auto zero_phi = pts;
  zero_phi[0].phi_stderr = 0;
  EXPECT_THROW(fit_phi_i(zero_phi), std::invalid_argument);
  auto nan = pts;
  nan[2].mu = NAN;
  EXPECT_THROW(fit_mu_i(nan), std::invalid_argument);
  auto same_I = pts;
  for (auto& p : same_I) p.I = (&p - same_I.data()) % 2 ? 0.01 : 0.1;  // two distinct I only
  EXPECT_THROW(fit_mu_i(same_I), std::invalid_argument);
  try {
    fit_mu_i({pts.begin(), pts.begin() + 3});
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("at least 4"), std::string::npos) << e.what();
  }
}

TEST(RheologyFile, WriteThenReadGivesTheSameValues) {
  // Every number is written with 17 significant digits: read back bit for bit (EXPECT_EQ on
  // doubles). Strings with quotes, backslashes and newlines survive the TOML escaping.
  std::mt19937_64 rng(3);
  const RheologyFile d = make_rheology_file(
      synthetic(jop_law, 0.005, 0.002, &rng),
      {{"grains", "bidisperse disks d = 1, 1.2 mm, \"glass\"\\mu_p = 0.5\nsecond line"},
       {"grain_hash", "9f0c2a"},
       {"date", "2026-11-24"}});
  EXPECT_EQ(d.source.count("grainlift_version"), 1u);
  EXPECT_DOUBLE_EQ(d.I_min, 1e-3);
  EXPECT_DOUBLE_EQ(d.I_max, 0.5);
  const fs::path dir = scratch_dir("roundtrip");
  const std::string path = (dir / "rheology.toml").string();
  write_rheology_file(path, d);
  const RheologyFile r = read_rheology_file(path);
  EXPECT_EQ(r.source, d.source);
  EXPECT_EQ(r.mu_i.mu_s, d.mu_i.mu_s);
  EXPECT_EQ(r.mu_i.mu_2, d.mu_i.mu_2);
  EXPECT_EQ(r.mu_i.I0, d.mu_i.I0);
  EXPECT_EQ(r.mu_i.mu_s_err, d.mu_i.mu_s_err);
  EXPECT_EQ(r.mu_i.mu_2_err, d.mu_i.mu_2_err);
  EXPECT_EQ(r.mu_i.I0_err, d.mu_i.I0_err);
  EXPECT_EQ(r.mu_i.covariance, d.mu_i.covariance);
  EXPECT_EQ(r.mu_i.chi2_per_dof, d.mu_i.chi2_per_dof);
  EXPECT_EQ(r.mu_i.points, d.mu_i.points);
  EXPECT_EQ(r.I_min, d.I_min);
  EXPECT_EQ(r.I_max, d.I_max);
  EXPECT_EQ(r.phi_i.phi_max, d.phi_i.phi_max);
  EXPECT_EQ(r.phi_i.a, d.phi_i.a);
  EXPECT_EQ(r.phi_i.phi_max_err, d.phi_i.phi_max_err);
  EXPECT_EQ(r.phi_i.a_err, d.phi_i.a_err);
  EXPECT_EQ(r.phi_i.chi2_per_dof, d.phi_i.chi2_per_dof);
  EXPECT_EQ(r.phi_i.points, d.phi_i.points);
  ASSERT_EQ(r.points.size(), d.points.size());
  for (std::size_t k = 0; k < r.points.size(); ++k) {
    EXPECT_EQ(r.points[k].I, d.points[k].I);
    EXPECT_EQ(r.points[k].mu, d.points[k].mu);
    EXPECT_EQ(r.points[k].mu_stderr, d.points[k].mu_stderr);
    EXPECT_EQ(r.points[k].phi, d.points[k].phi);
    EXPECT_EQ(r.points[k].phi_stderr, d.points[k].phi_stderr);
  }
  // Atomic write: no temporary file is left beside the result.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 1);
  fs::remove_all(dir);
}

TEST(RheologyFile, WallTableIsOptionalAndReadsBackBitForBit) {
  // A file without [wall] reads with no wall law; one with it (the study's numbers,
  // studies/wall_law/README.md) reads back bit for bit; a wall law out of range (v0 <= 0, a
  // negative friction) or with a typo'd key is refused naming the table and the key.
  std::mt19937_64 rng(5);
  RheologyFile d = make_rheology_file(synthetic(jop_law, 0.005, 0.002, &rng), {});
  EXPECT_FALSE(d.wall.has_value());
  const fs::path dir = scratch_dir("wall");
  const std::string plain = (dir / "plain.toml").string();
  write_rheology_file(plain, d);
  EXPECT_FALSE(read_rheology_file(plain).wall.has_value());
  WallLaw w;
  w.friction = 0.205;
  w.friction_err = 0.038;
  w.mu_a = 0.03;
  w.mu_a_err = 0.01;
  w.mu_b = 1.0 / 3.0;
  w.mu_b_err = 0.03;
  w.v0 = 0.0791;
  w.v0_err = 0.012;
  w.chi2_per_dof = 0.78;
  w.points = 142;
  d.wall = w;
  const std::string path = (dir / "wall.toml").string();
  write_rheology_file(path, d);
  const RheologyFile r = read_rheology_file(path);
  ASSERT_TRUE(r.wall.has_value());
  EXPECT_EQ(r.wall->friction, w.friction);
  EXPECT_EQ(r.wall->friction_err, w.friction_err);
  EXPECT_EQ(r.wall->mu_a, w.mu_a);
  EXPECT_EQ(r.wall->mu_a_err, w.mu_a_err);
  EXPECT_EQ(r.wall->mu_b, w.mu_b);
  EXPECT_EQ(r.wall->mu_b_err, w.mu_b_err);
  EXPECT_EQ(r.wall->v0, w.v0);
  EXPECT_EQ(r.wall->v0_err, w.v0_err);
  EXPECT_EQ(r.wall->chi2_per_dof, w.chi2_per_dof);
  EXPECT_EQ(r.wall->points, w.points);
  EXPECT_EQ(r.mu_i.mu_s, d.mu_i.mu_s);
  const std::string text = slurp(path);
  auto refused = [&](const std::string& name, const std::string& content,
                     const std::vector<std::string>& words) {
    const std::string p = (dir / name).string();
    std::ofstream(p) << content;
    try {
      read_rheology_file(p);
      ADD_FAILURE() << name << " was accepted";
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(p), std::string::npos) << m;
      for (const auto& x : words) EXPECT_NE(m.find(x), std::string::npos) << x << " in " << m;
    }
  };
  refused("v0.toml", std::regex_replace(text, std::regex(R"(\nv0 = [^\n]*)"), "\nv0 = 0"),
          {"[wall]", "v0", "> 0"});
  refused("friction.toml",
          std::regex_replace(text, std::regex(R"(\nfriction = [^\n]*)"), "\nfriction = -0.1"),
          {"[wall]", "friction", ">= 0"});
  refused("typo.toml", std::regex_replace(text, std::regex(R"(\nmu_b_err =)"), "\nmub_err ="),
          {"[wall]", "unknown key 'mub_err'"});
  refused("missing.toml", std::regex_replace(text, std::regex(R"(\nv0_err = [^\n]*)"), ""),
          {"[wall]", "v0_err", "missing"});
  fs::remove_all(dir);
}

TEST(RheologyFile, RefusesCorruptFilesNamingFileAndKey) {
  // A law that is not a law (mu_2 < mu_s), a missing key, a typo'd key and a file that is not
  // TOML are refused with an InputError that names the file (and the key and its range).
  std::mt19937_64 rng(4);
  const RheologyFile d = make_rheology_file(synthetic(soft_law, 0.005, 0.002, &rng), {});
  const fs::path dir = scratch_dir("corrupt");
  const std::string good = (dir / "good.toml").string();
  write_rheology_file(good, d);
  const std::string text = slurp(good);

  auto expect_refused = [&](const std::string& name, const std::string& content,
                            const std::vector<std::string>& words) {
    const std::string path = (dir / name).string();
    std::ofstream(path) << content;
    try {
      read_rheology_file(path);
      ADD_FAILURE() << name << " was accepted";
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(path), std::string::npos) << m;
      for (const auto& w : words) EXPECT_NE(m.find(w), std::string::npos) << w << " in " << m;
    }
  };
  const std::regex mu_2_line(R"(\nmu_2 = [^\n]*)");
  expect_refused("swapped.toml", std::regex_replace(text, mu_2_line, "\nmu_2 = 0.1"),
                 {"mu_s", "mu_s < mu_2"});
  expect_refused("missing.toml", std::regex_replace(text, std::regex(R"(\nI0 = [^\n]*)"), ""),
                 {"I0", "missing", "> 0"});
  expect_refused("typo.toml", std::regex_replace(text, std::regex(R"(\nI0_err =)"), "\nI0err ="),
                 {"unknown key 'I0err'"});
  expect_refused("negative_I0.toml",
                 std::regex_replace(text, std::regex(R"(\nI0 = [^\n]*)"), "\nI0 = -0.2"),
                 {"I0", "> 0"});
  expect_refused("nan.toml", std::regex_replace(text, mu_2_line, "\nmu_2 = nan"),
                 {"mu_2", "finite"});
  expect_refused("fractional_points.toml",
                 std::regex_replace(text, std::regex(R"(\npoints = 10)"), "\npoints = 9.5"),
                 {"points", "integer"});
  expect_refused("not_toml.toml", "this is [not toml\n", {"TOML"});
  expect_refused("no_mu_i.toml", "[phi_i]\nphi_max = 0.8\n", {"[mu_i]"});
  EXPECT_THROW(read_rheology_file((dir / "absent.toml").string()), InputError);

  // The writer refuses what the reader would refuse.
  RheologyFile bad = d;
  bad.mu_i.mu_2 = bad.mu_i.mu_s - 0.01;
  EXPECT_THROW(write_rheology_file((dir / "bad.toml").string(), bad), InputError);
  EXPECT_FALSE(fs::exists(dir / "bad.toml"));
  fs::remove_all(dir);
}
