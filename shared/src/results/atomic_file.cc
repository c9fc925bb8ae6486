#include "grainlift/shared/results/atomic_file.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "grainlift/shared/errors.h"

namespace grainlift {

std::string temporary_path_for(const std::string& final_path) {
  static std::atomic<unsigned> counter{0};
  const std::filesystem::path p(final_path);
  const std::string name = fmt::format(".{}.tmp.{}.{}", p.filename().string(), ::getpid(),
                                       counter.fetch_add(1));
  return (p.parent_path() / name).string();
}

void commit_file(const std::string& temporary, const std::string& final_path) {
  // Flush the data to disk before the rename makes it visible.
  int fd = ::open(temporary.c_str(), O_RDONLY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
  if (std::rename(temporary.c_str(), final_path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(temporary.c_str());
    throw RunError(fmt::format("{}: cannot rename the finished file into place: {}", final_path,
                               why));
  }
}

void write_text_atomically(const std::string& final_path, const std::string& text) {
  const std::string tmp = temporary_path_for(final_path);
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f)
    throw InputError(fmt::format("{}: cannot write: {}", final_path, std::strerror(errno)));
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  if (std::fclose(f) != 0 || !ok) {
    std::remove(tmp.c_str());
    throw RunError(fmt::format("{}: write failed", final_path));
  }
  commit_file(tmp, final_path);
}

void make_directories(const std::string& path) {
  std::error_code ec;
  std::filesystem::create_directories(path, ec);
  if (ec || !std::filesystem::is_directory(path))
    throw InputError(fmt::format("{}: cannot create the output folder: {}", path,
                                 ec ? ec.message() : "not a directory"));
}

}  // namespace grainlift
