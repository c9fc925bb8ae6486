// validate_config(): the ranges and the consistency of a ContinuumConfig (solver.h). deal.II-free.
#include <array>
#include <cmath>
#include <sstream>
#include <string>

#include "grainlift/continuum/errors.h"
#include "grainlift/continuum/mpi_session.h"
#include "grainlift/continuum/mu_i_rheology.h"
#include "grainlift/continuum/solver.h"

namespace grainlift::continuum {

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw ConfigError("continuum: " + what);
}

bool finite(double x) { return std::isfinite(x); }

/// The nonlocal fluidity's and the dilatancy's settings.
void validate_models(const ContinuumConfig& c) {
  if (c.model == ContinuumModel::nonlocal_fluidity) {
    const NonlocalParams& n = c.nonlocal;
    require(finite(n.amplitude) && n.amplitude > 0, "nonlocal amplitude A must be > 0");
    require(finite(n.xi_max) && n.xi_max >= 0, "nonlocal xi_max must be >= 0 (0: the intruder "
                                                 "diameter)");
    require(n.max_iterations >= 1, "nonlocal max_iterations must be >= 1");
    require(n.tolerance > 0 && n.tolerance < 1, "nonlocal tolerance must be in (0, 1)");
    require(n.relaxation > 0 && n.relaxation <= 1, "nonlocal relaxation must be in (0, 1]");
    require(!c.linearised_gravity, "the nonlocal fluidity model solves gravity in full: "
                                   "continuum.gravity_treatment = \"full\"");
    require(MpiSession::size() == 1, "the nonlocal fluidity model runs on one MPI rank (its "
                                     "fluidity solve is serial): run without mpirun");
  }
  if (c.dilatancy.enabled) {
    const DilatancyParams& d = c.dilatancy;
    require(finite(d.phi_max) && d.phi_max > 0 && d.phi_max <= 1,
            "dilatancy phi_max must be in (0, 1]");
    require(finite(d.a) && d.a >= 0, "dilatancy a (Phi(I) = phi_max - a I) must be >= 0");
    require(finite(d.phi_min) && d.phi_min > 0 && d.phi_min <= d.phi_max,
            "dilatancy phi_min must be in (0, phi_max]");
    require(c.model == ContinuumModel::local,
            "continuum.dilatancy = \"phi_i\" is built for the local mu(I) law: set "
            "continuum.model = \"local\"");
    require(!c.linearised_gravity, "continuum.dilatancy weighs the dilated medium: "
                                   "continuum.gravity_treatment = \"full\"");
  }
}

}  // namespace

void validate_config(const ContinuumConfig& c) {
  require(finite(c.intruder_diameter) && c.intruder_diameter > 0, "intruder_diameter must be > 0");
  if (c.far_field == FarField::symmetric_box) {
    require(finite(c.half_width) && c.half_width > c.intruder_diameter,
            "half_width must be > intruder_diameter");
    require(finite(c.half_height) && c.half_height > c.intruder_diameter,
            "half_height must be > intruder_diameter");
  } else {
    // every edge clear of the intruder by a tenth of its radius (the mesh's block around the
    // hole then fits inside the box)
    const double R = 0.5 * c.intruder_diameter;
    std::ostringstream box;
    box << "the box [" << c.box_left << ", " << c.box_right << "] x [" << c.box_bottom << ", "
        << c.box_top << "] m about the intruder's centre";
    require(finite(c.box_left) && finite(c.box_right) && finite(c.box_bottom) &&
                finite(c.box_top) && c.box_left < -1.1 * R && c.box_right > 1.1 * R &&
                c.box_bottom < -1.1 * R && c.box_top > 1.1 * R,
            box.str() + " must clear the intruder (radius " + std::to_string(R) +
                " m) by a tenth of its radius on every side");
  }
  require(finite(c.intruder_velocity[0]) && finite(c.intruder_velocity[1]),
          "intruder_velocity must be finite");
  require(finite(c.intruder_omega), "intruder_omega must be finite");
  require(finite(c.gravity[0]) && finite(c.gravity[1]), "gravity must be finite");
  require(finite(c.bulk_density) && c.bulk_density > 0, "bulk_density must be > 0");
  require(finite(c.ambient_pressure) && c.ambient_pressure > 0, "ambient_pressure must be > 0");
  // the lithostatic pressure P0 + rho g.x must not be negative on the box (0 is allowed: a
  // box whose top is the free surface)
  const std::array<double, 4> e = box_edges(c);
  for (const double x : {e[0], e[1]})
    for (const double y : {e[2], e[3]}) {
      const double p = c.ambient_pressure + c.bulk_density * (c.gravity[0] * x + c.gravity[1] * y);
      require(p >= -1e-9 * c.ambient_pressure,
              "ambient_pressure too small: the lithostatic pressure P0 + rho g.x is negative in a "
              "corner of the box (the box reaches above the free surface)");
    }
  const RheologyParams& r = c.rheology;
  require(r.mu_s >= 0 && r.mu_2 > r.mu_s, "rheology needs 0 <= mu_s < mu_2");
  require(r.I0 > 0, "rheology I0 must be > 0");
  require(r.grain_diameter > 0, "rheology grain_diameter must be > 0");
  require(r.solid_density > 0, "rheology solid_density must be > 0");
  require(r.delta >= 0, "rheology delta must be >= 0");
  require(
      r.regularisation != Regularisation::chauchat_medale || r.delta > 0 || r.eta_max < HUGE_VAL,
      "chauchat_medale needs delta > 0 or a finite eta_max");
  require(r.eta_min >= 0 && r.eta_max > r.eta_min, "rheology needs 0 <= eta_min < eta_max");
  if (r.regularisation == Regularisation::barker_gray) {
    // the low-I branch is well posed only when it joins mu(I) where mu(I) itself is
    const InertialRange w = well_posed_range(r);
    require(!w.empty(), "barker_gray needs mu_s, mu_2, I0 for which mu(I) is well posed in some "
                        "range of I (Barker et al. 2015); these give none");
    std::ostringstream range;
    range << "(" << w.low << ", " << w.high << ")";
    require(r.barker_gray_IN == 0 || (r.barker_gray_IN > w.low && r.barker_gray_IN < w.high),
            "barker_gray_IN must be 0 (automatic) or inside the well-posed range " + range.str() +
                " of mu(I)");
  }
  require(c.wall_friction >= 0, "wall_friction must be >= 0");
  require(c.wall_v0 >= 0 && c.wall_mu_a >= 0 && c.wall_mu_b >= 0,
          "the wall's slip law needs wall_v0 >= 0 (0 = constant wall_friction), mu_a, mu_b >= 0");
  require(c.wall_slip_regularisation >= 0, "wall_slip_regularisation must be >= 0");
  require(c.inertia_threshold >= 0, "inertia_threshold must be >= 0");
  require(c.refinement >= 0 && c.refinement <= 7, "refinement must be in [0, 7]");
  require(c.adaptive_cycles >= 0 && c.adaptive_cycles <= 5, "adaptive_cycles must be in [0, 5]");
  require(c.wall_layers >= 0 && c.wall_layers <= 6, "wall_layers must be in [0, 6]");
  require(c.nonlinear_tolerance > 0 && c.nonlinear_tolerance < 1,
          "nonlinear_tolerance must be in (0, 1)");
  require(c.max_nonlinear_iterations >= 1, "max_nonlinear_iterations must be >= 1");
  require(c.picard_iterations >= 0, "picard_iterations must be >= 0");
  for (const double t : c.surface_theta) require(finite(t), "surface_theta values must be finite");
  require(finite(c.target_error) && c.target_error >= 0 && c.target_error < 1,
          "target_error must be in [0, 1)");
  if (c.target_error > 0)
    require(c.nested,
            "target_error stops the nested levels (and the adaptive cycles after them): it needs "
            "continuum.nested = true");
  validate_models(c);
  if (c.fields.enabled)
    require(c.fields.spacing > 0 && c.fields.nx > 0 && c.fields.ny > 0,
            "fields need spacing > 0, nx > 0 and ny > 0");
}

}  // namespace grainlift::continuum
