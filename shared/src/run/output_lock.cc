#include "grainlift/shared/run/output_lock.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <string>

#include "grainlift/shared/errors.h"

namespace grainlift {

namespace {

std::string read_all(int fd) {
  std::string s;
  char buf[256];
  ::lseek(fd, 0, SEEK_SET);
  for (ssize_t n; (n = ::read(fd, buf, sizeof buf)) > 0;) s.append(buf, static_cast<size_t>(n));
  while (!s.empty() && (s.back() == '\n' || s.back() == '\0')) s.pop_back();
  return s;
}

/// True when @p fd is still the file at @p path (not one unlinked by a writer that finished).
bool same_file(int fd, const std::string& path) {
  struct stat a {}, b {};
  return ::fstat(fd, &a) == 0 && ::stat(path.c_str(), &b) == 0 && a.st_dev == b.st_dev &&
         a.st_ino == b.st_ino;
}

}  // namespace

OutputLock::OutputLock(const std::string& dir) {
  const std::string path = dir + "/.grainlift.lock";
  for (int attempt = 0; attempt < 8; ++attempt) {
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) return;  // not writable: the result's own write says so
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      const std::string holder = read_all(fd);
      ::close(fd);
      if (err != EWOULDBLOCK) return;  // a file system without locks: nothing to hold
      throw RunError(fmt::format(
          "{}: another grainlift is writing its results there ({}); wait for it to end, or "
          "choose another --out",
          dir, holder.empty() ? "its process is starting" : holder));
    }
    if (!same_file(fd, path)) {  // the last writer removed it after we opened it: again
      ::close(fd);
      continue;
    }
    const auto now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    const std::string me = fmt::format("pid {}, since unix time {}", ::getpid(), now);
    if (::ftruncate(fd, 0) == 0) {
      const ssize_t written = ::pwrite(fd, me.data(), me.size(), 0);
      (void)written;  // the pid is only for the other's message: a failed write changes nothing
    }
    fd_ = fd;
    path_ = path;
    return;
  }
}

OutputLock::~OutputLock() {
  if (fd_ < 0) return;
  // removed while held (a process that opened it tries again); not when the folder was
  // removed and the file is another process's now
  if (same_file(fd_, path_)) ::unlink(path_.c_str());
  ::close(fd_);
}

}  // namespace grainlift
