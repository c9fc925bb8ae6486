// libFuzzer target of the DEM checkpoint decoder (decode_checkpoint, read by
// `grainlift run CASE --resume DIR`).
//
// Expected behaviour: never crashes. Every input is either decoded or refused with
// CheckpointError (the glue turns it into InputError); every length is checked against the
// bytes left before anything is allocated, so no input allocates more than its own size.
//
// The first byte picks how the rest becomes checkpoint bytes:
//   0  as they are (the magic, format and checksum checks meet mutated bytes);
//   1  magic + rest + FNV-1a 64 checksum of both (the format word comes from the input);
//   2  magic + format 2 + rest + checksum: every input reaches the payload parser.
// Without modes 1 and 2 almost no mutation would get past the checksum.
#include <cstdint>
#include <cstring>
#include <vector>

#include "checkpoint_bytes.h"
#include "grainlift/dem/system/checkpoint.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::vector<unsigned char> bytes =
      grainlift::fuzz::checkpoint_bytes(data[0] % 3, data + 1, size - 1);
  try {
    const grainlift::dem::RunCheckpoint c = grainlift::dem::decode_checkpoint(bytes);
    // what a decoded checkpoint promises its users (simulation.cc, the glue)
    const auto& s = c.system;
    if (s.ax.size() != s.grains.size() || s.pair_j.size() != s.pair_i.size() ||
        s.ic_sx.size() != s.ic_grain.size() || c.step < 0 || c.step > c.planned_steps ||
        (c.out.steady_start_index > c.out.samples.size() &&
         c.out.steady_start_index != static_cast<std::size_t>(-1)))
      __builtin_trap();
  } catch (const grainlift::dem::CheckpointError&) {
  }
  return 0;
}
