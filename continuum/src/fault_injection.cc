#include "fault_injection.h"

#include <cstdlib>
#include <new>
#include <stdexcept>

#include "grainlift/continuum/mpi_session.h"

namespace grainlift::continuum::internal {

void fail_here_if_requested(const std::string& where) {
  if (const char* fail_on = std::getenv("GRAINLIFT_TEST_FAIL_ON_RANK");
      fail_on && std::string(fail_on) == std::to_string(MpiSession::rank()))
    throw std::runtime_error("GRAINLIFT_TEST_FAIL_ON_RANK=" + std::string(fail_on) +
                             ": test failure " + where);
}

void bad_alloc_here_if_requested(int level) {
  if (const char* at = std::getenv("GRAINLIFT_TEST_BAD_ALLOC_AT_LEVEL");
      at && std::string(at) == std::to_string(level))
    throw std::bad_alloc();
}

double failure_wait_seconds(double usual) {
  const char* s = std::getenv("GRAINLIFT_TEST_FAILURE_WAIT_SECONDS");
  if (!s || !*s) return usual;
  char* end = nullptr;
  const double v = std::strtod(s, &end);
  return *end == '\0' && v > 0 && v <= usual ? v : usual;
}

}  // namespace grainlift::continuum::internal
