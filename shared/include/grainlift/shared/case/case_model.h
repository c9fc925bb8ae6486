// The typed, validated image of one case file (docs/case-format.md). Everything here has
// been range-checked by the loader, which fills every absent key with the default of the key
// registry (case_keys.cc), the only place a default is written: the members here are only
// zero-initialised. SI units throughout unless a field says otherwise.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace grainlift {

using Vec2 = std::array<double, 2>;

struct SceneSection {
  Vec2 gravity{};            ///< m/s^2 on the grains (zero in lid_only mode)
  /// "box" | "free_surface" | "heavy_lid" | "lid_only" (Guillard et al. 2014's three ways of
  /// making a depth; the loader derives domain.lid_pressure, the top of the box and gravity)
  std::string depth_mode;
  double depth{};            ///< m, equivalent depth h of scene.depth (0 in box mode)
  double lid_gravity{};      ///< m/s^2, |g| of the lid in lid_only mode (0 otherwise)
};

struct DomainSection {
  Vec2 x_range{}, y_range{};  ///< m
  std::array<bool, 2> periodic{};
  bool wall_bottom{}, wall_top{}, wall_left{}, wall_right{};
  double
      lid_pressure{};  ///< Pa (2D reading), confining pressure on the top-wall lid; 0 = fixed wall
  std::string lid;        ///< "rigid" | "free_disks" (DEM)
};

struct IntruderSection {
  double diameter{};        ///< m
  Vec2 position{};        ///< m
  Vec2 velocity{};        ///< m/s
  double omega{};           ///< rad/s, counter-clockwise positive
  double spin_ramp_time{};  ///< s
  double friction{};        ///< grain-intruder Coulomb coefficient (default: grains.friction)
};

struct ContactSection {
  std::string law;  ///< "kumar2019" | "guillard2014"
  double kn{}, kt{};   ///< Pa (Kumar Table I)
  double gamma_n{}, gamma_t{};  ///< 1/(m s)
  double youngs_modulus{};    ///< Pa (Guillard Table I)
  double poisson_ratio{};
  double restitution{};
};

struct GrainsSection {
  double diameter{};          ///< m, mean
  double polydispersity{};  ///< relative half-width of the uniform size distribution
  double density{};           ///< kg/m^3 per unit length = 2D mass per area kg/m^2
  double area_fraction{};
  double friction{};
  ContactSection contact;
};

struct DemSection {
  double dt{};             ///< s
  double max_dt_fraction{};
  double travel{};          ///< mean grain diameters
  double steady_travel{};    ///< mean grain diameters
  double target_error{};     ///< relative standard error of drag and lift that ends a run (0: off)
  std::uint64_t seed{};
  int sample_every{};
  long long sort_every{};    ///< steps between renumberings into rows of cells (0: never)
  int field_every{};
  bool frictionless_path{};  ///< grains.friction = 0: normal forces only
  bool sleep{};              ///< sleeping grains
  double checkpoint_minutes{};  ///< wall time between checkpoints (0: only when interrupted)
  long long checkpoint_steps{};  ///< steps between checkpoints (0: by time only)
  double sleep_speed{};      ///< fraction of |V0| below which a grain may sleep
  double relax_ke{};       ///< J per grain
  std::string preparation;  ///< "radius_growth" | "wall_compression" (packing.h)
  double compression_speed{};  ///< m/s, the top wall's speed in wall_compression
  bool compression_drag{true};  ///< wall_compression under the relaxation's background drag
  std::string packing_cache;
};

struct ContinuumSection {
  double ambient_pressure{};  ///< Pa, P0 at the intruder centre on top of the lithostatic part
  double mu_s{}, mu_2{}, I0{};   ///< from rheology_file when it names one
  std::string rheology_file;  ///< "" or the calibrated law's file, resolved from the case's folder
  /// Where mu_s, mu_2, I0 came from: "case" (the case names them), "rheology file"
  /// (continuum.rheology_file), "calibration cache" (rheology_cache.h) or "default" (the key
  /// registry's Jop et al. 2006 glass beads).
  std::string law_source;
  std::string regularisation;
  double delta{};          ///< 1/s
  double eta_max{};         ///< Pa s
  double pressure_smoothing{};  ///< p_eps / P0 (0 = hard clamp max(p, 0))
  double barker_gray_IN{};      ///< 0 = automatic (see continuum.barker_gray_IN)
  std::string gravity_treatment;  ///< "full" or "linearised"
  std::string wall;
  double wall_friction{};     ///< default: intruder.friction; the [wall] friction if measured
  std::string wall_law;       ///< "coulomb" (wall_friction), "measured", "measured_slip" ([wall])
  /// measured_slip: the [wall] slip law, mu_w(s) = mu_a + (mu_b - mu_a) |s| / (|s| + v0);
  /// wall_v0 = 0 (m/s) otherwise
  double wall_mu_a{}, wall_mu_b{}, wall_v0{};
  std::string inertia;
  Vec2 box_half_size{};     ///< m; 0 = the case's domain (solver_box)
  double bed_top{};         ///< m, the FE box's top edge; NaN = the domain's (solver_box)
  std::string far_field;    ///< "auto" | "periodic" | "open" (continuum_far_field resolves auto)
  Vec2 open_length{};       ///< D upstream, downstream of the intruder's centre (open far field)
  int refinement{};
  int adaptive_cycles{};
  int wall_layers{};
  double target_error{};        ///< relative force change that ends the nested levels (0: off)
  bool nested{};                ///< nested iteration from refinement 0
  bool mesh_error_estimate{};   ///< solve refinement - 1 first: the forces' mesh-error estimate
  double tolerance{};
  int max_iterations{};
  int picard_iterations{};
  std::string linear_solver;
  std::string model;              ///< "local" | "nonlocal_fluidity"
  double nonlocal_amplitude{};    ///< A (nonlocal_fluidity)
  /// where A comes from: "continuum.nonlocal_amplitude" (stated or its default) or the
  /// rheology file's [nonlocal] table (when the case does not state A)
  std::string nonlocal_amplitude_source = "continuum.nonlocal_amplitude";
  int nonlocal_iterations{};      ///< splitting iterations at most (nonlocal_fluidity)
  double nonlocal_relaxation{};   ///< w of the splitting (nonlocal_fluidity)
  double nonlocal_tolerance{};    ///< relative force change at which the splitting stops
  std::string dilatancy;  ///< "auto" | "none" | "phi_i" (the rheology file's Phi(I))
  /// Phi(I) = phi_max - a I of the calibrated law (rheology_file or the calibration cache),
  /// I_max the top of its calibrated range; phi_max = 0 when no calibrated law was read
  double phi_max{}, phi_a{}, phi_I_max{};
};

struct OutputSection {
  int angles{};              ///< M of Guillard eq. (A4)
  double kernel_width_deg{};  ///< Gaussian standard deviation
  int histogram_bins{};      ///< pi/12 bins as in Kumar Fig. 6
  int blocks{};              ///< blocks for standard errors
  bool fields{};
  double field_spacing{};   ///< mean grain diameters
  Vec2 field_half_size{};   ///< intruder diameters
  bool vtu{};
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
  /// |g| that sets the pressure scale: the grains' gravity, or the lid's in lid_only mode.
  double reference_gravity() const;
  /// Equivalent depth h = P0 / (rho g) of the intruder centre with P0 = stated_pressure() and
  /// g = reference_gravity(), m; 0 without gravity. Equals scene.depth in the depth modes.
  double equivalent_depth() const;
  /// Lithostatic pressure at the intruder centre, rho |g| (depth below the top of the box), Pa.
  double lithostatic_pressure() const;
  /// The confining pressure at the intruder centre that both solvers see, Pa: the lid's
  /// (domain.lid_pressure) plus the lithostatic pressure, 0 when the case has neither (a
  /// volume-controlled DEM bed: its own pressure is measured, /far_field).
  double stated_pressure() const { return domain.lid_pressure + lithostatic_pressure(); }
  /// Confining pressure the continuum uses at the intruder centre, Pa: stated_pressure(), or
  /// continuum.ambient_pressure on top of the lithostatic part for a continuum-only scene
  /// without a lid (the loader refuses both a lid and an ambient pressure).
  double continuum_pressure() const { return continuum.ambient_pressure + stated_pressure(); }
  /// Whether the DEM bed and the continuum are confined by the same pressure: the pressure
  /// comes from the lid or gravity, not from continuum.ambient_pressure alone.
  bool pressure_matched() const { return stated_pressure() > 0 && continuum.ambient_pressure == 0; }
};

}  // namespace grainlift
