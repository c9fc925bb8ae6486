// libFuzzer target of the case reader (parse_case, with --set overrides) and of the rheology
// file reader a case may name (read_rheology_file).
//
// Expected behaviour: never crashes. Every input is either read or refused with InputError,
// whose message names the file and line; no other exception, no sanitizer report, no
// allocation out of proportion to the input.
//
// Input format:
//   - text that starts with "#%rheology\n" is written to a scratch file and read as a rheology
//     file (calibration output, continuum.rheology_file);
//   - otherwise the text up to a line "#%set" is the case file, and each line after it one
//     --set override ("section.key=value"). "#%set" is a TOML comment, so a case file with
//     overrides is still a case file.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "fuzz_scratch.h"
#include "grainlift/shared/case/case_loader.h"
#include "grainlift/shared/errors.h"
#include "grainlift/shared/rheology/rheology_file.h"

namespace {

void read_rheology(const std::string& text) {
  static const std::string path = grainlift::fuzz::scratch_path("rheology.toml");
  grainlift::fuzz::write_file(path, text);
  try {
    (void)grainlift::read_rheology_file(path);
  } catch (const grainlift::InputError&) {
  }
}

void read_case(const std::string& input) {
  const std::string marker = "#%set\n";
  std::string text = input;
  std::vector<std::string> overrides;
  const std::size_t at = input.find(marker);
  if (at != std::string::npos && (at == 0 || input[at - 1] == '\n')) {
    text = input.substr(0, at);
    std::size_t p = at + marker.size();
    while (p <= input.size()) {
      const std::size_t eol = std::min(input.find('\n', p), input.size());
      if (eol > p) overrides.push_back(input.substr(p, eol - p));
      p = eol + 1;
    }
  }
  try {
    // A name without a folder: a relative continuum.rheology_file is looked for in the
    // working directory (run_fuzzer.sh runs in a scratch folder).
    (void)grainlift::parse_case(text, "fuzz.toml", overrides);
  } catch (const grainlift::InputError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const std::string rheology = "#%rheology\n";
  if (input.compare(0, rheology.size(), rheology) == 0)
    read_rheology(input);
  else
    read_case(input);
  return 0;
}
