// Files appear complete or not at all: write to a temporary name in the same folder, then
// rename over the final name (atomic on POSIX file systems). A crash or Ctrl-C leaves the old
// file (or none) under the final name, never a half-written one.
#pragma once

#include <cstddef>
#include <string>

namespace grainlift {

/// A unique temporary path beside @p final_path (same folder, so rename is atomic).
std::string temporary_path_for(const std::string& final_path);

/// Renames @p temporary over @p final_path; throws RunError on failure.
void commit_file(const std::string& temporary, const std::string& final_path);

/// Writes @p text to @p final_path atomically (temp + fsync + rename).
void write_text_atomically(const std::string& final_path, const std::string& text);

/// Writes @p size bytes at @p data to @p final_path atomically (temp + fsync + rename). On any
/// failure the temporary file is removed, the file at @p final_path (if any) is left as it was,
/// and RunError names the file, the cause (no space, read-only, permission: strerror) and what
/// to do. The test hook GRAINLIFT_TEST_WRITE_FAULT=ENOSPC[:PREFIX] (or EROFS, EACCES) in the
/// environment makes such writes (to paths under PREFIX) fail with that cause (`faults` tests).
void write_bytes_atomically(const std::string& final_path, const void* data, std::size_t size);

/// Creates a directory and its parents; throws InputError when that is impossible.
void make_directories(const std::string& path);

}  // namespace grainlift
