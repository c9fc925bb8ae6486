// Faults of the machine at a write (issue 37): a full disk or a read-only folder ends in one
// sentence that names the file, the cause and what to do, leaves the previous file as it was
// and no temporary file beside it. The fault is injected with the test hook
// GRAINLIFT_TEST_WRITE_FAULT (shared/include/grainlift/shared/results/atomic_file.h), the
// same code path a real ENOSPC takes after write(2).
#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "grainlift/shared/errors.h"
#include "grainlift/shared/results/atomic_file.h"
#include "grainlift/shared/results/result_file.h"
#include "sample_result.h"

using namespace grainlift;
namespace fs = std::filesystem;

namespace {

fs::path scratch_dir(const std::string& name) {
  fs::path d = fs::temp_directory_path() /
               ("grainlift_faults_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// The message of the RunError that @p write throws under fault @p cause.
template <class F>
std::string message_under(const char* cause, F write) {
  ::setenv("GRAINLIFT_TEST_WRITE_FAULT", cause, 1);
  std::string what;
  try {
    write();
  } catch (const RunError& e) {
    what = e.what();
  }
  ::unsetenv("GRAINLIFT_TEST_WRITE_FAULT");
  return what;
}

}  // namespace

// A result file rewritten on a full disk: RunError naming the file, "No space left on
// device" and the way out; the previous file's bytes unchanged (exact), nothing else left in
// the folder.
TEST(WriteFaults, FullDiskKeepsThePreviousResultFile) {
  const fs::path dir = scratch_dir("h5");
  const std::string path = (dir / "dem.h5").string();
  const RunResult r = grainlift::test_support::sample_result_head();
  write_result(path, r);
  const std::string before = bytes_of(path);
  const std::string what = message_under("ENOSPC", [&] { write_result(path, r); });
  EXPECT_NE(what.find(path), std::string::npos) << what;
  EXPECT_NE(what.find("No space left on device"), std::string::npos) << what;
  EXPECT_NE(what.find("free some space or choose another --out"), std::string::npos) << what;
  EXPECT_NE(what.find("the previous file is kept as it was"), std::string::npos) << what;
  EXPECT_EQ(bytes_of(path), before);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
  fs::remove_all(dir);
}

// A text file (summary.json, XDMF, a checkpoint) in a read-only folder: the cause and the way
// out named; no file appears where there was none.
TEST(WriteFaults, ReadOnlyFolderLeavesNoFile) {
  const fs::path dir = scratch_dir("ro");
  const std::string path = (dir / "summary.json").string();
  const std::string what =
      message_under("EROFS", [&] { write_text_atomically(path, "{}\n"); });
  EXPECT_NE(what.find("Read-only file system"), std::string::npos) << what;
  EXPECT_NE(what.find("choose another --out"), std::string::npos) << what;
  EXPECT_NE(what.find("no file was left there"), std::string::npos) << what;
  EXPECT_FALSE(fs::exists(path));
  fs::remove_all(dir);
}

// The hook's prefix limits the fault to one folder: a write elsewhere succeeds (the rescue
// folder of a run whose --out is full).
TEST(WriteFaults, FaultLimitedToAFolder) {
  const fs::path full = scratch_dir("full"), other = scratch_dir("other");
  const std::string cause = "ENOSPC:" + full.string();
  ::setenv("GRAINLIFT_TEST_WRITE_FAULT", cause.c_str(), 1);
  EXPECT_THROW(write_text_atomically((full / "a.txt").string(), "x"), RunError);
  EXPECT_NO_THROW(write_text_atomically((other / "a.txt").string(), "x"));
  ::unsetenv("GRAINLIFT_TEST_WRITE_FAULT");
  EXPECT_EQ(bytes_of(other / "a.txt"), "x");
  fs::remove_all(full);
  fs::remove_all(other);
}
