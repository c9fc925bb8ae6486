// Scratch files of the fuzz targets whose reader takes a path: one name per process and
// purpose, in $GRAINLIFT_FUZZ_SCRATCH (run_fuzzer.sh sets it), else /dev/shm (memory, fast),
// else $TMPDIR or /tmp. The file is removed when the process exits normally.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <string>

namespace grainlift::fuzz {

inline std::string scratch_folder() {
  if (const char* v = std::getenv("GRAINLIFT_FUZZ_SCRATCH"); v && *v) return v;
  if (access("/dev/shm", W_OK) == 0) return "/dev/shm";
  if (const char* v = std::getenv("TMPDIR"); v && *v) return v;
  return "/tmp";
}

/// The one scratch file of this process, named after @p name at the first call (a target
/// needs one); removed at exit.
inline std::string scratch_path(const std::string& name) {
  struct Removed {
    std::string path;
    ~Removed() { std::remove(path.c_str()); }
  };
  static Removed file{scratch_folder() + "/grainlift-fuzz-" + std::to_string(getpid()) + "-" +
                      name};
  return file.path;
}

inline void write_file(const std::string& path, const std::string& bytes) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) {
    std::perror(path.c_str());
    std::abort();  // the harness cannot run: not a finding of the reader
  }
  std::fwrite(bytes.data(), 1, bytes.size(), f);
  std::fclose(f);
}

}  // namespace grainlift::fuzz
