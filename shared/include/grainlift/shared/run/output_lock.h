// One writer per result folder: two grainlift processes given the same --out would overwrite
// each other's files, and a summary.json could list the other's run.
#pragma once

#include <string>

namespace grainlift {

/// @brief Holds an exclusive lock (flock) on DIR/.grainlift.lock while a run writes into DIR.
/// The lock goes with the process: a killed run leaves no stale lock behind. The file holds
/// the writer's pid and start time, for the sentence another process gets.
class OutputLock {
 public:
  /// Takes the lock on @p dir (which must exist); throws RunError naming the other process
  /// when it is held. A folder where the lock file cannot be made (read-only) is not locked:
  /// its writes fail with their own sentence.
  explicit OutputLock(const std::string& dir);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

 private:
  int fd_ = -1;
  std::string path_;
};

}  // namespace grainlift
