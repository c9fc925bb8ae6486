// Pressure-controlled lid: the top wall of frozen disks as a rigid body moving along y under a
// target pressure, and along x at an imposed speed (lid.h, docs/dem-model.md).
#include "grainlift/dem/boundaries/lid.h"

#include <cmath>
#include <string>
#include <tuple>

#include "grainlift/dem/contact/contact_law.h"
#include "grainlift/dem/system/dem_system.h"
#include "grainlift/dem/errors.h"
#include "grainlift/dem/bed/packing.h"

namespace grainlift::dem {

double PressureLid::default_damping(const DemConfig& c, double mass) {
  const LawCoefficients law = LawCoefficients::from(c.contact);
  const double d = c.grain_diameter;
  const double k = law.hertz_stiffness(0.25 * d);
  const double load = c.lid_pressure * d;  // N, per contact of a column of pitch d
  const double k_lin = 1.5 * std::cbrt(k * k * load);
  const double stiffness = k_lin * (c.xmax - c.xmin) / (c.ymax - c.ymin);
  return 2.0 * std::sqrt(stiffness * mass);
}

PressureLid::PressureLid(const DemConfig& c, const DemSystem& s, double shear_velocity)
    : shear_velocity_(shear_velocity) {
  if (!(c.lid_pressure > 0) || !c.wall_top || c.periodic_y) {
    throw ConfigError("the pressure lid needs lid_pressure > 0, a top wall and y not periodic");
  }
  if (!std::isfinite(shear_velocity) || (shear_velocity != 0 && !c.periodic_x)) {
    throw ConfigError("a shearing lid needs a finite speed and a box periodic in x");
  }
  // The top wall disks: centres at ymax - d/2 (make_wall_disks puts them in one run).
  const std::vector<Disk> walls = make_wall_disks(c);
  const double y_top = c.ymax - 0.5 * c.grain_diameter;
  std::tie(begin_, end_) = wall_row(walls, y_top);
  if (begin_ < 0 || s.frozen() != static_cast<int>(walls.size())) {
    throw ConfigError("the pressure lid found no top wall among the frozen disks");
  }
  begin_ += s.grains();
  end_ += s.grains();
  width_ = c.xmax - c.xmin;
  force_target_ = c.lid_pressure * width_;
  mass_ = c.lid_mass > 0 ? c.lid_mass : default_mass(s.grain_mass());
  damping_ = c.lid_damping > 0 ? c.lid_damping : default_damping(c, mass_);
  state_.y = y_top;
  free_disks_ = c.lid_free_disks;
  if (free_disks_) {
    disk_y_.assign(std::size_t(disks()), y_top);
    disk_velocity_.assign(std::size_t(disks()), 0.0);
  }
}

void PressureLid::restore(const LidState& state, const std::vector<double>& disk_y,
                          const std::vector<double>& disk_velocity) {
  if (disk_y.size() != disk_y_.size() || disk_velocity.size() != disk_velocity_.size()) {
    throw ConfigError("the saved lid has " + std::to_string(disk_y.size()) +
                      " free disks, this one " + std::to_string(disk_y_.size()));
  }
  state_ = state;
  disk_y_ = disk_y;
  disk_velocity_ = disk_velocity;
}

namespace {
/// One damped step of m dv/dt = f - target - c v (symplectic Euler, damping implicit).
double damped_velocity(double v, double f, double target, double m, double c, double dt) {
  return (v + dt * (f - target) / m) / (1.0 + c * dt / m);
}
}  // namespace

LidMove PressureLid::record(double force_x, double force_y, double dt, double velocity, double y) {
  const LidMove move{shear_velocity_ * dt, y - state_.y};
  state_.velocity = velocity;
  state_.y = y;
  state_.x_shift += move.dx;
  state_.pressure = force_y / width_;
  state_.shear_stress = force_x / width_;
  state_.impulse_x += force_x * dt;
  state_.impulse_y += force_y * dt;
  return move;
}

LidMove PressureLid::advance_disks(double force_x, const std::vector<double>& force_y,
                                   double dt, std::vector<double>& dy) {
  const std::size_t n = disk_y_.size();
  if (force_y.size() != n) throw ConfigError("advance_disks: one force per lid disk");
  const double m = mass_ / double(n), c = damping_ / double(n), target = force_target_ / double(n);
  dy.resize(n);
  double f_total = 0, y_sum = 0, v_sum = 0;
  for (std::size_t k = 0; k < n; ++k) {
    disk_velocity_[k] = damped_velocity(disk_velocity_[k], force_y[k], target, m, c, dt);
    dy[k] = dt * disk_velocity_[k];
    disk_y_[k] += dy[k];
    f_total += force_y[k];
    y_sum += disk_y_[k];
    v_sum += disk_velocity_[k];
  }
  return record(force_x, f_total, dt, v_sum / double(n), y_sum / double(n));
}

LidMove PressureLid::advance(double force_x, double force_y, double dt) {
  const double v = damped_velocity(state_.velocity, force_y, force_target_, mass_, damping_, dt);
  LidMove move = record(force_x, force_y, dt, v, state_.y + dt * v);
  move.dy = dt * v;  // exactly, not through the difference of heights
  return move;
}

}  // namespace grainlift::dem
