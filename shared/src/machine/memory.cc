#include "grainlift/shared/machine/memory.h"

#include <sys/resource.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace grainlift {

namespace {

/// The value of "Key:   N kB" in a /proc file, in bytes (< 0: not found).
double proc_kib(const std::string& file, const std::string& key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(key + ":", 0) != 0) continue;
    std::istringstream s(line.substr(key.size() + 1));
    double kib = -1;
    s >> kib;
    return kib >= 0 ? kib * 1024.0 : -1;
  }
  return -1;
}

/// One number in a file (< 0: absent, "max" or unreadable).
double file_number(const std::string& file) {
  std::ifstream in(file);
  std::string word;
  if (!(in >> word) || word == "max") return -1;
  char* end = nullptr;
  const double v = std::strtod(word.c_str(), &end);
  return end && *end == '\0' && v >= 0 ? v : -1;
}

/// This process's control group folder (cgroup v2: the line "0::/path"), "" when none.
std::string cgroup_folder() {
  std::ifstream in("/proc/self/cgroup");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("0::", 0) == 0) return "/sys/fs/cgroup" + line.substr(3);
  return {};
}

void tighten(MemoryRoom& room, double bytes, const char* limit) {
  if (bytes < 0) return;
  if (room.bytes < 0 || bytes < room.bytes) room = {bytes, limit};
}

double rlimit_room(int resource, const char* used_key) {
  rlimit rl{};
  if (getrlimit(resource, &rl) != 0 || rl.rlim_cur == RLIM_INFINITY) return -1;
  const double used = proc_kib("/proc/self/status", used_key);
  const double room = static_cast<double>(rl.rlim_cur) - (used > 0 ? used : 0);
  return room > 0 ? room : 0;
}

}  // namespace

MemoryRoom memory_room() {
  MemoryRoom room;
  if (const char* t = std::getenv("GRAINLIFT_TEST_MEMORY_MB"); t && *t) {
    tighten(room, std::atof(t) * 1024.0 * 1024.0, "test limit GRAINLIFT_TEST_MEMORY_MB");
    return room;
  }
  tighten(room, rlimit_room(RLIMIT_AS, "VmSize"), "ulimit -v, the address space");
  tighten(room, rlimit_room(RLIMIT_DATA, "VmData"), "ulimit -d, the data segment");
  if (const std::string cg = cgroup_folder(); !cg.empty()) {
    const double max = file_number(cg + "/memory.max"), cur = file_number(cg + "/memory.current");
    if (max >= 0 && cur >= 0) tighten(room, max > cur ? max - cur : 0, "the control group");
  }
  tighten(room, proc_kib("/proc/meminfo", "MemAvailable"), "the machine's available memory");
  return room;
}

std::string format_bytes(double bytes) {
  char buf[32];
  if (bytes >= 1e9)
    std::snprintf(buf, sizeof buf, "%.1f GB", bytes / 1e9);
  else if (bytes >= 1e7)
    std::snprintf(buf, sizeof buf, "%.0f MB", bytes / 1e6);
  else
    std::snprintf(buf, sizeof buf, "%.1f MB", bytes / 1e6);
  return buf;
}

std::string memory_shortfall(const std::string& what, double need_bytes, double margin) {
  const MemoryRoom room = memory_room();
  if (room.bytes < 0 || need_bytes * margin <= room.bytes) return {};
  return what + " needs about " + format_bytes(need_bytes) + " where " +
         format_bytes(room.bytes) + " are left (the limit: " + room.limit + ")";
}

}  // namespace grainlift
