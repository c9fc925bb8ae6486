// What memory a process may still take: the tightest of its address-space limit (ulimit -v),
// its data limit (ulimit -d), its control group's limit (memory.max) and the machine's
// MemAvailable. Standard library and Linux's /proc and /sys only, so that the engines may link
// it (grainlift_machine) without seeing TOML, HDF5 or deal.II.
#pragma once

#include <string>

namespace grainlift {

/// The room left for new allocations, and what sets it.
struct MemoryRoom {
  double bytes = -1;   ///< bytes this process may still allocate; < 0: unknown (no limit found)
  std::string limit;   ///< what sets it, for a sentence: "ulimit -v (address space)", ...
};

/// @brief The tightest limit on what this process may still allocate, now.
/// Reads getrlimit(RLIMIT_AS, RLIMIT_DATA) against /proc/self/status (VmSize, VmData), the
/// control group's memory.max against memory.current, and /proc/meminfo's MemAvailable.
/// The test hook GRAINLIFT_TEST_MEMORY_MB=N stands for a limit of N MB ("test limit").
MemoryRoom memory_room();

/// @brief @p bytes for a sentence: "850 MB", "3.2 GB".
std::string format_bytes(double bytes);

/// @brief "" when @p need_bytes fits in memory_room() with @p margin (need * margin <= room),
/// else one sentence: "<what> needs about X; Y are left (<limit>)".
std::string memory_shortfall(const std::string& what, double need_bytes, double margin = 1.0);

}  // namespace grainlift
