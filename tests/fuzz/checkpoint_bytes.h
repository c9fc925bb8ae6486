// The checkpoint fuzz target's input as checkpoint bytes (fuzz_checkpoint.cc), shared with the
// seed maker. The frame (magic, format word, FNV-1a 64 checksum) follows
// dem/src/system/checkpoint.cc.
#pragma once

#include <cstdint>
#include <cstring>
#include <vector>

namespace grainlift::fuzz {

inline constexpr char checkpoint_magic[8] = {'G', 'L', 'D', 'E', 'M', 'C', 'K', 'P'};

inline std::uint64_t checkpoint_fnv1a(const unsigned char* p, std::size_t n) {
  std::uint64_t h = 1469598103934665603ULL;
  for (std::size_t k = 0; k < n; ++k) {
    h ^= p[k];
    h *= 1099511628211ULL;
  }
  return h;
}

/// @brief Bytes to decode: @p mode 0 the payload as it is; 1 magic + payload + checksum;
/// 2 magic + format 3 + payload + checksum.
inline std::vector<unsigned char> checkpoint_bytes(int mode, const std::uint8_t* payload,
                                                   std::size_t size) {
  std::vector<unsigned char> b;
  if (mode == 0) return std::vector<unsigned char>(payload, payload + size);
  b.assign(checkpoint_magic, checkpoint_magic + sizeof checkpoint_magic);
  if (mode == 2) {
    const std::uint32_t format = 3;
    unsigned char f[4];
    std::memcpy(f, &format, 4);
    b.insert(b.end(), f, f + 4);
  }
  b.insert(b.end(), payload, payload + size);
  const std::uint64_t h = checkpoint_fnv1a(b.data(), b.size());
  unsigned char c[8];
  std::memcpy(c, &h, 8);
  b.insert(b.end(), c, c + 8);
  return b;
}

}  // namespace grainlift::fuzz
