// The typed, validated image of one case file (docs/case-format.md). Everything here has
// been range-checked by the loader; defaults are filled in. SI units throughout unless a
// field says otherwise.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace grainlift {

using Vec2 = std::array<double, 2>;

struct SceneSection {
  Vec2 gravity{0, 0};            ///< m/s^2
};

struct DomainSection {
  Vec2 x_range{0, 0}, y_range{0, 0};  ///< m
  std::array<bool, 2> periodic{true, false};
  bool wall_bottom = false, wall_top = false, wall_left = false, wall_right = false;
  double lid_pressure = 0;  ///< Pa (2D reading), confining pressure on the top-wall lid; 0 = fixed wall
};

struct IntruderSection {
  double diameter = 0;        ///< m
  Vec2 position{0, 0};        ///< m
  Vec2 velocity{0, 0};        ///< m/s
  double omega = 0;           ///< rad/s, counter-clockwise positive
  double spin_ramp_time = 0;  ///< s
  double friction = 0;        ///< grain-intruder Coulomb coefficient (default: grains.friction)
};

struct ContactSection {
  std::string law = "kumar2019";  ///< "kumar2019" | "guillard2014"
  double kn = 2e9, kt = 2.45e9;   ///< Pa (Kumar Table I)
  double gamma_n = 8e6, gamma_t = 8e6;  ///< 1/(m s)
  double youngs_modulus = 5e6;    ///< Pa (Guillard Table I)
  double poisson_ratio = 0.45;
  double restitution = 0.6;
};

struct GrainsSection {
  double diameter = 0;          ///< m, mean
  double polydispersity = 0.1;  ///< relative half-width of the uniform size distribution
  double density = 0;           ///< kg/m^3 per unit length = 2D mass per area kg/m^2
  double area_fraction = 0;
  double friction = 0.5;
  ContactSection contact;
};

struct DemSection {
  double dt = 2e-6;             ///< s
  double max_dt_fraction = 0.1;
  double travel = 300;          ///< mean grain diameters
  double steady_travel = 30;    ///< mean grain diameters
  std::uint64_t seed = 1;
  int sample_every = 50;
  int field_every = 500;
  double relax_ke = 1e-9;       ///< J per grain
  std::string packing_cache = "auto";
};

struct ContinuumSection {
  double ambient_pressure = 0;  ///< Pa, P0 at the intruder centre on top of the lithostatic part
  double mu_s = 0.38, mu_2 = 0.64, I0 = 0.279;
  std::string regularisation = "barker_gray";
  double delta = 1e-3;          ///< 1/s
  double eta_max = 1e4;         ///< Pa s
  double pressure_smoothing = 0;  ///< p_eps / P0 (0 = hard clamp max(p, 0))
  double barker_gray_IN = 0;      ///< 0 = automatic (see continuum.barker_gray_IN)
  std::string gravity_treatment = "full";  ///< "full" or "linearised"
  std::string wall = "no_slip";
  double wall_friction = 0;     ///< default: intruder.friction
  std::string inertia = "auto";
  Vec2 box_half_size{0, 0};     ///< m; 0 = from the domain
  int refinement = 2;
  int adaptive_cycles = 0;
  double tolerance = 1e-8;
  int max_iterations = 50;
  int picard_iterations = 5;
  std::string linear_solver = "direct";
};

struct OutputSection {
  int angles = 64;              ///< M of Guillard eq. (A4)
  double kernel_width_deg = 8;  ///< Gaussian standard deviation
  int histogram_bins = 24;      ///< pi/12 bins as in Kumar Fig. 6
  int blocks = 20;              ///< blocks for standard errors
  bool fields = true;
  double field_spacing = 0.5;   ///< mean grain diameters
  Vec2 field_half_size{3, 3};   ///< intruder diameters
  bool vtu = true;
};

/// Where a case came from, kept verbatim for the output file.
struct CaseSource {
  std::string path;
  std::string text;                      ///< the file verbatim
  std::vector<std::string> overrides;    ///< "--set" arguments in order, "key=value"
  std::string effective_toml;            ///< the validated case with overrides applied, as TOML
  std::string hash;                      ///< FNV-1a 64 (hex) of text + overrides
};

struct Case {
  CaseSource source;
  SceneSection scene;
  DomainSection domain;
  IntruderSection intruder;
  GrainsSection grains;
  DemSection dem;
  ContinuumSection continuum;
  OutputSection output;

  /// Bulk density rho = Phi rho_s (kg/m^3 per unit length).
  double bulk_density() const { return grains.area_fraction * grains.density; }
  /// Intruder speed |V| (m/s).
  double speed() const;
  /// Spin ratio Omega = omega R / |V| (Kumar eq. 4).
  double spin_ratio() const;
  /// Lithostatic pressure at the intruder centre, rho |g| (depth below the top of the box), Pa.
  double lithostatic_pressure() const;
  /// Confining pressure the continuum uses at the intruder centre:
  /// continuum.ambient_pressure + lithostatic_pressure(), Pa.
  double continuum_pressure() const { return continuum.ambient_pressure + lithostatic_pressure(); }
};

}  // namespace grainlift
