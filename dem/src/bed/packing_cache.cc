// The packing cache's files (packing_cache.h): a prepared bed written whole to a temporary
// file and renamed into place, read back only when its magic and key match.
#include "bed/packing_cache.h"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

namespace grainlift::dem::detail {

namespace {
constexpr char kMagic[8] = {'G', 'L', 'D', 'E', 'M', 'P', 'K', '1'};
}  // namespace

bool load_packing(const std::string& path, std::uint64_t hash, PackedBed& bed) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  char magic[8];
  std::uint64_t h = 0;
  std::int64_t n = 0;
  double phi = 0;
  in.read(magic, 8);
  in.read(reinterpret_cast<char*>(&h), sizeof h);
  in.read(reinterpret_cast<char*>(&n), sizeof n);
  in.read(reinterpret_cast<char*>(&phi), sizeof phi);
  if (!in || std::memcmp(magic, kMagic, 8) != 0 || h != hash || n < 0 || n > (1ll << 32)) {
    return false;
  }
  bed.x.resize(n);
  bed.y.resize(n);
  bed.r.resize(n);
  for (auto* v : {&bed.x, &bed.y, &bed.r}) {
    in.read(reinterpret_cast<char*>(v->data()), static_cast<std::streamsize>(n * sizeof(double)));
  }
  if (!in) return false;
  bed.area_fraction = phi;
  bed.from_cache = true;
  return true;
}

void save_packing(const std::string& path, std::uint64_t hash, const PackedBed& bed) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(fs::path(path).parent_path(), ec);
  std::random_device rd;
  const std::string tmp = path + ".tmp." + std::to_string(rd());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) return;  // the cache is an optimisation: a read-only directory is not an error
    const std::int64_t n = static_cast<std::int64_t>(bed.r.size());
    out.write(kMagic, 8);
    out.write(reinterpret_cast<const char*>(&hash), sizeof hash);
    out.write(reinterpret_cast<const char*>(&n), sizeof n);
    out.write(reinterpret_cast<const char*>(&bed.area_fraction), sizeof bed.area_fraction);
    for (const auto* v : {&bed.x, &bed.y, &bed.r}) {
      out.write(reinterpret_cast<const char*>(v->data()),
                static_cast<std::streamsize>(n * sizeof(double)));
    }
    if (!out) {
      out.close();
      fs::remove(tmp, ec);
      return;
    }
  }
  fs::rename(tmp, path, ec);
  if (ec) fs::remove(tmp, ec);
}

}  // namespace grainlift::dem::detail
