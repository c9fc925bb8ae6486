// Pressure-controlled lid: the top wall of frozen disks as a rigid body moving along y under a
// target pressure (lid.h, docs/dem-model.md), and the two DemSystem hooks it needs.
#include "grainlift/dem/lid.h"

#include <cmath>

#include "grainlift/dem/contact_law.h"
#include "grainlift/dem/errors.h"
#include "grainlift/dem/packing.h"

namespace grainlift::dem {

void DemSystem::move_frozen(int begin, int end, double dy, double vy) {
  for (int j = begin; j < end; ++j) {
    p_.y[j] += dy;
    p_.vy[j] = vy;
  }
  // A frozen disk that moved by |dy| changes a pair distance by at most |dy|: the same bound
  // as a radius growth, so the Verlet-list rebuild test counts it there.
  growth_since_build_ += std::abs(dy);
}

double DemSystem::frozen_force_y(int begin, int end) const {
  double f = 0;
  for (int j = begin; j < end; ++j) {
    // pairs (i, j) list the force on the grain i; the lid disk feels its opposite
    for (std::int64_t s = nl_.rfirst[j]; s < nl_.rfirst[j + 1]; ++s) f -= nl_.fy[nl_.rpair[s]];
  }
  return f;
}

double PressureLid::default_damping(const DemConfig& c, double mass) {
  const LawCoefficients law = LawCoefficients::from(c.contact);
  const double d = c.grain_diameter;
  const double r_eff = 0.25 * d;
  const double k = law.law == ContactLaw::kumar2019 ? law.kn * std::sqrt(r_eff)
                                                    : law.hertz_kn_factor * std::sqrt(r_eff);
  const double load = c.lid_pressure * d;  // N, per contact of a column of pitch d
  const double k_lin = 1.5 * std::cbrt(k * k * load);
  const double stiffness = k_lin * (c.xmax - c.xmin) / (c.ymax - c.ymin);
  return 2.0 * std::sqrt(stiffness * mass);
}

PressureLid::PressureLid(const DemConfig& c, DemSystem& s) {
  if (!(c.lid_pressure > 0) || !c.wall_top || c.periodic_y) {
    throw ConfigError("the pressure lid needs lid_pressure > 0, a top wall and y not periodic");
  }
  // The top wall disks: centres at ymax - d/2 (make_wall_disks puts them in one run).
  const std::vector<Disk> walls = make_wall_disks(c);
  const double y_top = c.ymax - 0.5 * c.grain_diameter;
  begin_ = end_ = -1;
  for (int k = 0; k < static_cast<int>(walls.size()); ++k) {
    if (walls[k].y != y_top) continue;
    if (begin_ < 0) begin_ = k;
    end_ = k + 1;
  }
  if (begin_ < 0 || s.frozen() != static_cast<int>(walls.size())) {
    throw ConfigError("the pressure lid found no top wall among the frozen disks");
  }
  begin_ += s.grains();
  end_ += s.grains();
  width_ = c.xmax - c.xmin;
  force_target_ = c.lid_pressure * width_;
  double grain_mass = 0;
  for (int i = 0; i < s.grains(); ++i) grain_mass += s.particles().mass[i];
  mass_ = c.lid_mass > 0 ? c.lid_mass : default_mass(grain_mass);
  damping_ = c.lid_damping > 0 ? c.lid_damping : default_damping(c, mass_);
  state_.y = y_top;
  s.set_store_pair_forces(true);  // the lid force is read from the pair forces
}

void PressureLid::advance(DemSystem& s) {
  const double dt = s.dt();
  const double f = s.frozen_force_y(begin_, end_);
  const double v = (state_.velocity + dt * (f - force_target_) / mass_) / (1.0 + damping_ * dt / mass_);
  const double dy = dt * v;
  s.move_frozen(begin_, end_, dy, v);
  state_.velocity = v;
  state_.y += dy;
  state_.pressure = f / width_;
}

}  // namespace grainlift::dem
