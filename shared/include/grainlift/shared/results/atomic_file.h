// Files appear complete or not at all: write to a temporary name in the same folder, then
// rename over the final name (atomic on POSIX file systems). A crash or Ctrl-C leaves the old
// file (or none) under the final name, never a half-written one.
#pragma once

#include <string>

namespace grainlift {

/// A unique temporary path beside @p final_path (same folder, so rename is atomic).
std::string temporary_path_for(const std::string& final_path);

/// Renames @p temporary over @p final_path; throws RunError on failure.
void commit_file(const std::string& temporary, const std::string& final_path);

/// Writes @p text to @p final_path atomically (temp + fsync + rename).
void write_text_atomically(const std::string& final_path, const std::string& text);

/// Creates a directory and its parents; throws InputError when that is impossible.
void make_directories(const std::string& path);

}  // namespace grainlift
