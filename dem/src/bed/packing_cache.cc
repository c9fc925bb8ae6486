// The packing cache's files (packing_cache.h): a prepared bed written whole to a temporary
// file and renamed into place, with its format, its key and a checksum; read back only when
// all three hold. A damaged or foreign entry is removed (and the bed rebuilt by the caller).
#include "bed/packing_cache.h"
#include "system/fnv1a.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

namespace grainlift::dem::detail {

namespace {
/// Format 2: magic, key, grain count, area fraction, x, y, r, FNV-1a 64 of all before it.
constexpr char kMagic[8] = {'G', 'L', 'D', 'E', 'M', 'P', 'K', '2'};
constexpr char kOldMagic[8] = {'G', 'L', 'D', 'E', 'M', 'P', 'K', '1'};
constexpr std::size_t kHeader = 32;


template <class T>
T at(const std::vector<unsigned char>& b, std::size_t offset) {
  T v;
  std::memcpy(&v, b.data() + offset, sizeof v);
  return v;
}

/// Why the bytes @p b of an entry stored under key @p hash cannot be used ("" when they can).
std::string problem_of(const std::vector<unsigned char>& b, std::uint64_t hash) {
  if (b.size() >= 8 && std::memcmp(b.data(), kOldMagic, 8) == 0)
    return "of an older format (no checksum)";
  if (b.size() < kHeader + 8 || std::memcmp(b.data(), kMagic, 8) != 0)
    return "not a packing of this grainlift (foreign or truncated)";
  const auto n = at<std::int64_t>(b, 16);
  if (n < 0 || n > (1ll << 32) ||
      b.size() != kHeader + 3 * static_cast<std::size_t>(n) * sizeof(double) + 8)
    return "damaged (its length does not match its grain count)";
  if (fnv1a(b.data(), b.size() - 8) != at<std::uint64_t>(b, b.size() - 8))
    return "damaged (checksum mismatch)";
  if (at<std::uint64_t>(b, 8) != hash) return "of another bed (its key differs)";
  return "";
}
}  // namespace

CacheRead load_packing(const std::string& path, std::uint64_t hash, PackedBed& bed) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  const std::vector<unsigned char> b((std::istreambuf_iterator<char>(in)),
                                     std::istreambuf_iterator<char>());
  in.close();
  const std::string problem = problem_of(b, hash);
  if (!problem.empty()) {
    std::error_code ec;
    std::filesystem::remove(path, ec);
    return {false, "packing cache: " + path + " is " + problem + ": removed, the bed rebuilt"};
  }
  const auto n = static_cast<std::size_t>(at<std::int64_t>(b, 16));
  bed.area_fraction = at<double>(b, 24);
  std::size_t offset = kHeader;
  for (auto* v : {&bed.x, &bed.y, &bed.r}) {
    v->resize(n);
    std::memcpy(v->data(), b.data() + offset, n * sizeof(double));
    offset += n * sizeof(double);
  }
  bed.from_cache = true;
  return {true, ""};
}

std::string save_packing(const std::string& path, std::uint64_t hash, const PackedBed& bed) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(fs::path(path).parent_path(), ec);
  const std::int64_t n = static_cast<std::int64_t>(bed.r.size());
  std::vector<unsigned char> b(kHeader);
  std::memcpy(b.data(), kMagic, 8);
  std::memcpy(b.data() + 8, &hash, 8);
  std::memcpy(b.data() + 16, &n, 8);
  std::memcpy(b.data() + 24, &bed.area_fraction, 8);
  for (const auto* v : {&bed.x, &bed.y, &bed.r}) {
    const auto* p = reinterpret_cast<const unsigned char*>(v->data());
    b.insert(b.end(), p, p + v->size() * sizeof(double));
  }
  const std::uint64_t sum = fnv1a(b.data(), b.size());
  const auto* s = reinterpret_cast<const unsigned char*>(&sum);
  b.insert(b.end(), s, s + 8);
  std::random_device rd;
  const std::string tmp = path + ".tmp." + std::to_string(rd());
  auto not_cached = [&](const std::string& why) {
    fs::remove(tmp, ec);
    return "the prepared bed was not cached (" + path + ": " + why +
           "); the run goes on, and the next one prepares it again";
  };
  {
    errno = 0;
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) return not_cached(std::strerror(errno ? errno : EIO));
    out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
    out.close();  // a full disk may show only here: never rename a short file into place
    if (!out) return not_cached(std::strerror(errno ? errno : EIO));
  }
  fs::rename(tmp, path, ec);
  if (ec) return not_cached(ec.message());
  return {};
}

}  // namespace grainlift::dem::detail
