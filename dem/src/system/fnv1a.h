// FNV-1a 64, the engine's one byte hash: the packing cache's key (packing_hash) and the
// checksums of the packing cache's entries and of checkpoints.
#pragma once

#include <cstddef>
#include <cstdint>

namespace grainlift::dem::detail {

// Not FNV's published offset basis (14695981039346656037, which shared's fnv1a64_hex uses): a
// digit short. Kept, because the packing cache's keys and the checkpoints' checksums written so
// far are of it; the hash is as good with any nonzero basis.
constexpr std::uint64_t kFnvOffset = 1469598103934665603ull;

/// @p h (kFnvOffset to start) carried over the @p n bytes at @p data.
inline std::uint64_t fnv1a(const void* data, std::size_t n, std::uint64_t h = kFnvOffset) {
  const auto* b = static_cast<const unsigned char*>(data);
  for (std::size_t k = 0; k < n; ++k) {
    h ^= b[k];
    h *= 1099511628211ull;
  }
  return h;
}

}  // namespace grainlift::dem::detail
