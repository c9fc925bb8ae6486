#include "grainlift/shared/results/atomic_file.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
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

namespace {

/// The errno the test hook GRAINLIFT_TEST_WRITE_FAULT=CAUSE[:PREFIX] asks for a write to
/// @p path (0: none): CAUSE is ENOSPC, EROFS or EACCES; with PREFIX only paths that start
/// with it fail (so that a test can let the rescue folder work).
int injected_write_fault(const std::string& path) {
  const char* f = std::getenv("GRAINLIFT_TEST_WRITE_FAULT");
  if (!f) return 0;
  const std::string s(f), cause = s.substr(0, s.find(':'));
  if (s.find(':') != std::string::npos && path.rfind(s.substr(s.find(':') + 1), 0) != 0)
    return 0;
  if (cause == "ENOSPC") return ENOSPC;
  if (cause == "EROFS") return EROFS;
  if (cause == "EACCES") return EACCES;
  return 0;
}

/// What to do about a write that failed with @p err.
const char* advice_for(int err) {
  switch (err) {
    case ENOSPC:
    case EDQUOT:
      return "free some space or choose another --out";
    case EROFS:
      return "the file system is read-only: choose another --out";
    case EACCES:
    case EPERM:
      return "no permission to write there: choose another --out";
    default:
      return "choose another --out";
  }
}

[[noreturn]] void fail_write(const std::string& final_path, const std::string& tmp, int err) {
  if (!tmp.empty()) std::remove(tmp.c_str());
  throw RunError(fmt::format("{}: cannot write the file: {} ({}); {}", final_path,
                             std::strerror(err), advice_for(err),
                             std::filesystem::exists(final_path)
                                 ? "the previous file is kept as it was"
                                 : "no file was left there"));
}

}  // namespace

void write_bytes_atomically(const std::string& final_path, const void* data, std::size_t size) {
  if (const int fault = injected_write_fault(final_path)) fail_write(final_path, "", fault);
  const std::string tmp = temporary_path_for(final_path);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail_write(final_path, "", errno);
  const char* p = static_cast<const char*>(data);
  std::size_t left = size;
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int err = n < 0 ? errno : ENOSPC;
      ::close(fd);
      fail_write(final_path, tmp, err);
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0 && errno != EINVAL) {
    const int err = errno;
    ::close(fd);
    fail_write(final_path, tmp, err);
  }
  if (::close(fd) != 0) fail_write(final_path, tmp, errno);
  commit_file(tmp, final_path);
}

void write_text_atomically(const std::string& final_path, const std::string& text) {
  write_bytes_atomically(final_path, text.data(), text.size());
}

void make_directories(const std::string& path) {
  std::error_code ec;
  std::filesystem::create_directories(path, ec);
  if (ec || !std::filesystem::is_directory(path))
    throw InputError(fmt::format("{}: cannot create the output folder: {}", path,
                                 ec ? ec.message() : "not a directory"));
}

}  // namespace grainlift
