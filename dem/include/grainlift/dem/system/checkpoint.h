// Checkpoints of a DEM run: everything a run needs to go on, bit for bit, from the step where
// it was taken (the state of the system between two advance() calls, the outputs gathered so
// far, the field sums). Encoded into bytes with a format version and a checksum; no file I/O
// here (the glue writes the bytes atomically and checks that they belong to the case).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "grainlift/dem/dem_output.h"
#include "grainlift/dem/system/dem_system.h"
#include "grainlift/dem/measure/field_accumulator.h"
#include "grainlift/dem/boundaries/lid.h"

namespace grainlift::dem {

/// A checkpoint that cannot be read: wrong format or version, truncated, corrupt.
struct CheckpointError : std::runtime_error {
  explicit CheckpointError(const std::string& what) : std::runtime_error(what) {}
};

/// The state of a DemSystem between two advance() calls (DemSystem::snapshot, restore).
struct SystemSnapshot {
  std::vector<Disk> grains, frozen;       ///< positions, radii, masses, velocities
  std::vector<double> ax, ay, alpha;      ///< grains: accelerations of the last step
  double time = 0;
  std::int64_t steps = 0;
  Intruder intruder;
  /// listed pairs (grain i, body j) with a tangential spring (touching at the last step)
  std::vector<std::int32_t> pair_i, pair_j;
  std::vector<double> pair_sx, pair_sy;
  /// intruder contacts with a spring
  std::vector<std::int32_t> ic_grain;
  std::vector<double> ic_sx, ic_sy;
  bool has_lid = false;
  LidState lid;
  std::vector<double> lid_disk_y, lid_disk_velocity;  ///< free-disk lid only
  double max_overlap = 0;
  std::int32_t builds = 0;
  std::int64_t steps_on_one = 0, steps_on_team = 0;
  double sleep_grain_steps = 0;
  std::int32_t wake_builds = 0;
  std::int64_t woken = 0;
};

/// A run at the end of step @c step: what run_simulation needs to go on from there.
struct RunCheckpoint {
  std::string case_tag;  ///< set by the caller (the glue: the case hash), checked on resume
  std::int64_t step = 0;
  std::int64_t planned_steps = 0;
  SystemSnapshot system;
  DemOutput out;  ///< samples, contacts, lid and far-field series, bed facts so far
  FieldSums fields;
};

/// @brief The checkpoint as bytes: magic, format version, payload, FNV-1a 64 checksum.
std::vector<unsigned char> encode_checkpoint(const RunCheckpoint& c);
/// @brief Read bytes of encode_checkpoint back. @throws CheckpointError (not a checkpoint,
/// another format version, truncated, checksum mismatch, inconsistent sizes).
RunCheckpoint decode_checkpoint(const std::vector<unsigned char>& bytes);

}  // namespace grainlift::dem
