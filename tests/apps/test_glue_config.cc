// What the glues make of a case. One source of truth per case key: the key registry
// (case_keys.cc) holds the only default.
// The loader fills every absent key from it, and the glues turn the case into the engines'
// configurations. An engine configuration's own member defaults (used when an engine is run
// without a case file, e.g. in its unit tests) must then agree with what a case that leaves
// the key out gets; this test lists every key whose two defaults differ.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "grainlift/continuum/continuum_solver.h"
#include "grainlift/dem/dem_solver.h"
#include "grainlift/shared/case_keys.h"
#include "grainlift/shared/case_loader.h"

namespace {

/// A case with the required keys only (and a confining pressure, without which the continuum
/// configuration is refused). Every other key takes the registry's default.
grainlift::Case minimal_case() {
  const std::string text = R"(
[domain]
x_range = [-0.5, 0.5]
y_range = [-0.4, 0.4]
[intruder]
diameter = 0.1
velocity = [0.25, 0.0]
[grains]
diameter = 0.01
density = 20.0
area_fraction = 0.8
)";
  return grainlift::parse_case(text, "minimal.toml", {"continuum.ambient_pressure=1000"});
}

struct Mismatch {
  std::vector<std::string> keys;
  template <class T>
  void check(const std::string& key, const T& from_case, const T& engine_default) {
    if (!(from_case == engine_default)) keys.push_back(key);
  }
  std::string text() const {
    std::string s;
    for (const auto& k : keys) s += " " + k;
    return s;
  }
};

}  // namespace

// The DEM engine's defaults (DemConfig{}) equal the registry's, key by key, as the glue maps
// them (exact equality: a default is a number written once).
TEST(KeyDefaults, DemConfigAgreesWithTheRegistry) {
  namespace gd = grainlift::dem;
  const gd::DemConfig d = gd::make_dem_config(minimal_case(), 1);
  const gd::DemConfig e{};
  Mismatch m;
  m.check("domain.periodic[0]", d.periodic_x, e.periodic_x);
  m.check("domain.periodic[1]", d.periodic_y, e.periodic_y);
  m.check("domain.walls(bottom)", d.wall_bottom, e.wall_bottom);
  m.check("domain.walls(top)", d.wall_top, e.wall_top);
  m.check("domain.lid_pressure", d.lid_pressure, e.lid_pressure);
  m.check("scene.gravity", d.gravity, e.gravity);
  m.check("grains.polydispersity", d.polydispersity, e.polydispersity);
  m.check("grains.friction", d.contact.friction, e.contact.friction);
  m.check("intruder.friction", d.contact.intruder_friction, e.contact.intruder_friction);
  m.check("grains.contact.law", d.contact.law, e.contact.law);
  m.check("grains.contact.kn", d.contact.kn, e.contact.kn);
  m.check("grains.contact.kt", d.contact.kt, e.contact.kt);
  m.check("grains.contact.gamma_n", d.contact.gamma_n, e.contact.gamma_n);
  m.check("grains.contact.gamma_t", d.contact.gamma_t, e.contact.gamma_t);
  m.check("grains.contact.youngs_modulus", d.contact.youngs_modulus, e.contact.youngs_modulus);
  m.check("grains.contact.poisson_ratio", d.contact.poisson_ratio, e.contact.poisson_ratio);
  m.check("grains.contact.restitution", d.contact.restitution, e.contact.restitution);
  m.check("intruder.position", d.intruder_position, e.intruder_position);
  m.check("intruder.omega", d.intruder_omega, e.intruder_omega);
  m.check("intruder.spin_ramp_time", d.spin_ramp_time, e.spin_ramp_time);
  m.check("dem.dt", d.dt, e.dt);
  m.check("dem.max_dt_fraction", d.max_dt_fraction, e.max_dt_fraction);
  m.check("dem.travel", d.travel, e.travel);
  m.check("dem.steady_travel", d.steady_travel, e.steady_travel);
  m.check("dem.seed", d.seed, e.seed);
  m.check("dem.sample_every", d.sample_every, e.sample_every);
  m.check("dem.field_every", d.field_every, e.field_every);
  m.check("dem.relax_ke", d.relax_ke_per_grain, e.relax_ke_per_grain);
  EXPECT_TRUE(m.keys.empty()) << "DemConfig defaults differ from the registry for:" << m.text();
}

// The continuum engine's defaults (ContinuumConfig{}, RheologyParams{}) equal the registry's.
// Not compared, because the glue derives them from other keys: the box (domain), the bulk
// density, grain diameter and solid density (grains), the confining pressure (ambient +
// lithostatic), the intruder's kinematics.
TEST(KeyDefaults, ContinuumConfigAgreesWithTheRegistry) {
  namespace gc = grainlift::continuum;
  const gc::ContinuumConfig f = gc::make_continuum_config(minimal_case(), "out");
  const gc::ContinuumConfig e{};
  Mismatch m;
  m.check("continuum.mu_s", f.rheology.mu_s, e.rheology.mu_s);
  m.check("continuum.mu_2", f.rheology.mu_2, e.rheology.mu_2);
  m.check("continuum.I0", f.rheology.I0, e.rheology.I0);
  m.check("continuum.regularisation", f.rheology.regularisation, e.rheology.regularisation);
  m.check("continuum.delta", f.rheology.delta, e.rheology.delta);
  m.check("continuum.eta_max", f.rheology.eta_max, e.rheology.eta_max);
  m.check("continuum.barker_gray_IN", f.rheology.barker_gray_IN, e.rheology.barker_gray_IN);
  m.check("continuum.pressure_smoothing", f.rheology.pressure_smoothing,
          e.rheology.pressure_smoothing);
  m.check("continuum.gravity_treatment", f.linearised_gravity, e.linearised_gravity);
  m.check("continuum.wall", f.wall, e.wall);
  m.check("continuum.wall_friction", f.wall_friction, e.wall_friction);
  m.check("continuum.inertia", f.inertia, e.inertia);
  m.check("continuum.refinement", f.refinement, e.refinement);
  m.check("continuum.adaptive_cycles", f.adaptive_cycles, e.adaptive_cycles);
  m.check("continuum.tolerance", f.nonlinear_tolerance, e.nonlinear_tolerance);
  m.check("continuum.max_iterations", f.max_nonlinear_iterations, e.max_nonlinear_iterations);
  m.check("continuum.picard_iterations", f.picard_iterations, e.picard_iterations);
  m.check("continuum.linear_solver", f.linear_solver, e.linear_solver);
  EXPECT_TRUE(m.keys.empty()) << "ContinuumConfig defaults differ from the registry for:"
                              << m.text();
}

// A key whose default names another key takes that key's value (intruder.friction from
// grains.friction, continuum.wall_friction from intruder.friction); a literal default is the
// registry's text, parsed.
TEST(KeyDefaults, LoaderFillsTheRegistryDefaults) {
  const grainlift::Case c = grainlift::parse_case(
      "[domain]\nx_range = [-0.5, 0.5]\ny_range = [-0.4, 0.4]\n[intruder]\ndiameter = 0.1\n"
      "velocity = [0.25, 0.0]\n[grains]\ndiameter = 0.01\ndensity = 20.0\narea_fraction = 0.8\n"
      "friction = 0.3\n",
      "friction.toml", {});
  EXPECT_EQ(c.intruder.friction, 0.3);
  EXPECT_EQ(c.continuum.wall_friction, 0.3);
  EXPECT_EQ(grainlift::find_key("continuum.refinement")->default_text,
            std::to_string(c.continuum.refinement));
  EXPECT_EQ(grainlift::find_key("output.angles")->default_text, std::to_string(c.output.angles));
  EXPECT_EQ(grainlift::find_key("grains.contact.law")->default_text,
            "\"" + c.grains.contact.law + "\"");
}

// The continuum engine measures the surface angles from V (CylinderProblem::boundary_outputs
// adds V's heading itself); the glue hands it the shared grid theta_m = (m + 1/2) 2 pi / M as
// it is, whatever the direction of V: a case moving along +y gets the same angles, bit for bit,
// as one moving along +x (before, the glue added the heading too and the traces of a case not
// moving along +x were rotated twice).
TEST(ContinuumGlue, SurfaceAnglesAreMeasuredFromV) {
  namespace gc = grainlift::continuum;
  const grainlift::Case along_x = minimal_case();
  grainlift::Case along_y = along_x;
  along_y.intruder.velocity = {0.0, 0.25};
  const gc::ContinuumConfig fx = gc::make_continuum_config(along_x, "out");
  const gc::ContinuumConfig fy = gc::make_continuum_config(along_y, "out");
  ASSERT_GE(fx.surface_theta.size(), 64u);
  EXPECT_EQ(fx.surface_theta, fy.surface_theta);
  const double pi = 3.14159265358979323846;
  EXPECT_NEAR(fx.surface_theta[0], pi / 64, 1e-15);  // theta_0 = (1/2) 2 pi / M, M = 64
}
