// libFuzzer target of read_result over raw file bytes (seeds: files write_result wrote).
//
// Expected behaviour: every file is read or refused with InputError. Mutated bytes mostly
// exercise libhdf5's own parser of its format, not grainlift's code; findings inside libhdf5
// are documented in tests/fuzz/README.md and are not a test failure grainlift can fix, which is
// why this target is not run by the Fuzz.* tests (see the README).
#include <cstdint>
#include <string>

#include "fuzz_scratch.h"
#include "grainlift/shared/errors.h"
#include "grainlift/shared/results/result_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = grainlift::fuzz::scratch_path("raw.h5");
  grainlift::fuzz::write_file(path, std::string(reinterpret_cast<const char*>(data), size));
  try {
    (void)grainlift::read_result(path);
  } catch (const grainlift::InputError&) {
  }
  return 0;
}
