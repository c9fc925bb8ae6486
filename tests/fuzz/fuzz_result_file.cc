// libFuzzer target of the result file reader (read_result, used by compare, report's summary
// and --resume's summary) and of what grainlift does next with a file it accepted: the
// derived quantities, a comparison with itself, the summary.json object.
//
// Expected behaviour: never crashes. Every file is either read or refused with InputError; a
// file read is one that compare and summary.json can use without reading out of bounds, and
// no declared size makes the reader allocate more than the file holds.
//
// The input is not an HDF5 file but a program that builds one with the HDF5 C API
// (result_ops.h), following or breaking docs/schema.md: names from the schema, members
// missing or extra, wrong ranks, shapes and types, empty and huge spaces, NaN and infinity.
#include <cstdint>
#include <string>

#include "fuzz_scratch.h"
#include "grainlift/shared/results/compare.h"
#include "grainlift/shared/results/derived_quantities.h"
#include "grainlift/shared/errors.h"
#include "grainlift/shared/results/result_file.h"
#include "grainlift/shared/run/run_driver.h"
#include "result_ops.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = grainlift::fuzz::scratch_path("result.h5");
  grainlift::fuzz::build_result_file(data, size, path);
  grainlift::RunResult r;
  try {
    r = grainlift::read_result(path);
  } catch (const grainlift::InputError&) {
    return 0;
  }
  (void)grainlift::derive(r);
  const grainlift::Comparison c = grainlift::compare_results(r, r);
  (void)grainlift::comparison_json(c);
  (void)grainlift::comparison_text(c);
  (void)grainlift::summary_object_json(r);
  return 0;
}
