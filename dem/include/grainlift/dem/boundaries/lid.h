// Pressure-controlled lid (Guillard 2014 method iii in 2D): the top wall of frozen disks moves
// as one rigid body along y under a prescribed confining pressure and, optionally, along x at an
// imposed speed U (a simple-shear cell, shear_cell.h). A boundary that owns its state (position,
// velocity, measured pressure and shear stress, mass, damping); DemSystem moves its disks after
// the forces of every step (DemSystem::attach_lid). See docs/dem-model.md.
#pragma once

#include <vector>

#include "grainlift/dem/dem_config.h"

namespace grainlift::dem {

class DemSystem;

/// One sample of the lid.
struct LidState {
  double y = 0;         ///< m, height of the lid disks' centres (their mean for free disks)
  double velocity = 0;  ///< m/s
  double pressure = 0;  ///< N/m (2D pressure, = Pa per unit depth): grain force on the lid / width
  /// N/m: x force of the grains on the lid / width (the shear stress the lid feels; with U > 0
  /// the grains drag the lid back, so it is negative)
  double shear_stress = 0;
  double x_shift = 0;   ///< m, x travelled by the lid since it was made (U t, not wrapped)
  /// N s: time integrals of the grains' force on the lid since it was made (sum of F dt over
  /// the steps): their differences give the exact mean force between two samples
  double impulse_x = 0, impulse_y = 0;
};

/// The lid's displacement over one step (m).
struct LidMove {
  double dx = 0, dy = 0;
};

/// The top wall as a rigid lid with mass M and linear damping c:
///   M dv/dt = F_grains - P W - c v,   dy/dt = v,
/// F_grains the y force of the grains on the lid disks (N in the engine's units), W the box
/// width (m), P the target pressure (N/m). Integrated once per step, after the forces, by
/// symplectic Euler with the damping implicit:
///   v' = (v + dt (F_grains - P W) / M) / (1 + c dt / M),   y' = y + dt v'.
/// Along x the lid's velocity is imposed, U (m/s): it moves by U dt per step, whatever the
/// force (a shear-rate-controlled wall). The lid disks are moved by (U dt, dt v') and carry
/// (U, v') as their velocity in the contact law.
class PressureLid {
 public:
  /// @brief Take the top-wall disks of cfg (frozen indices in s) as the lid. cfg.lid_pressure
  /// > 0, cfg.wall_top, !cfg.periodic_y (validate_config checks). Mass and damping from cfg or,
  /// when 0 there, default_mass() and default_damping() below. s must hold the bodies already.
  /// @param shear_velocity m/s, the imposed x velocity U of the lid (0: the lid moves along y
  /// only, bit for bit the lid without this parameter).
  PressureLid(const DemConfig& cfg, const DemSystem& s, double shear_velocity = 0);

  /// @brief One step of the lid's equation of motion under the grain force (@p force_x,
  /// @p force_y) (N) over @p dt (s). Returns the lid's displacement (U dt, dt v') (m); state()
  /// then holds y', v', the pressure force_y / W and the shear stress force_x / W.
  LidMove advance(double force_x, double force_y, double dt);

  /// @brief Free disks (cfg.lid_free_disks): one step of every disk's equation of motion,
  ///   (M/N) dv_k/dt = F_k - P W / N - (c/N) v_k,
  /// integrated as advance() does, under the grains' y force @p force_y on each disk (N,
  /// disks() entries) and their total x force @p force_x. Fills @p dy with each disk's
  /// displacement (m); returns (U dt, mean dy). state() holds the mean height and velocity.
  LidMove advance_disks(double force_x, const std::vector<double>& force_y, double dt,
                        std::vector<double>& dy);
  bool free_disks() const { return free_disks_; }
  /// Height of each disk (free disks only).
  const std::vector<double>& disk_y() const { return disk_y_; }
  /// @brief Go on from a saved state (a checkpoint): @p disk_y and @p disk_velocity of the free
  /// disks (empty otherwise). @throws ConfigError when their number does not fit.
  void restore(const LidState& state, const std::vector<double>& disk_y,
               const std::vector<double>& disk_velocity);
  /// m/s, velocity of each disk after the last advance_disks() (free disks only)
  const std::vector<double>& disk_velocity() const { return disk_velocity_; }

  /// Lid state after the last advance() (pressure: the force measured in that call).
  const LidState& state() const { return state_; }
  double mass() const { return mass_; }        ///< kg
  double damping() const { return damping_; }  ///< kg/s
  double shear_velocity() const { return shear_velocity_; }  ///< m/s, U
  double width() const { return width_; }      ///< m, W
  int begin() const { return begin_; }         ///< first particle index of the lid disks
  int end() const { return end_; }             ///< one past the last
  int disks() const { return end_ - begin_; }

  /// @brief Default lid mass: the mass of the grains of the bed (kg), a heavy lid whose
  /// fluctuations are small. @param grain_mass kg, total mass of the mobile grains.
  static double default_mass(double grain_mass) { return grain_mass; }
  /// @brief Default damping: critical, c = 2 sqrt(K M), for the bed's estimated stiffness
  /// K = k_lin W / H: columns of mean grains in series, each contact linearised at the
  /// load P d of the target pressure: k_lin = (3/2) k^(2/3) (P d)^(1/3) with F = k delta^(3/2)
  /// (LawCoefficients::hertz_stiffness, R_eff = d/4). kg/s.
  static double default_damping(const DemConfig& cfg, double mass);

 private:
  /// Stores the step's outcome in state_ (velocity, height y, measured forces) and returns the
  /// move (U dt, y - previous height).
  LidMove record(double force_x, double force_y, double dt, double velocity, double y);

  int begin_ = 0, end_ = 0;  ///< lid disks: particle indices [begin_, end_)
  double width_ = 0;         ///< m, box width W
  double force_target_ = 0;  ///< N, P W
  double mass_ = 0, damping_ = 0;
  double shear_velocity_ = 0;  ///< m/s, U
  bool free_disks_ = false;
  std::vector<double> disk_y_, disk_velocity_;  ///< m, m/s: each disk (free disks only)
  LidState state_;
};

}  // namespace grainlift::dem
