#include "grainlift/shared/run/side_by_side.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace grainlift {

void side_by_side(std::size_t n, int workers, const std::function<void(std::size_t)>& run,
                  const std::function<void(std::size_t)>& report) {
  std::atomic<std::size_t> next{0};
  std::mutex m;  // guards ended, failed, reported and the reports
  std::vector<char> ended(n, 0);
  std::vector<std::exception_ptr> failed(n);
  std::size_t reported = 0;
  bool stopped = false;  // a run that threw: no report past it
  // one piece: run, then the reports it completes
  auto piece = [&](std::size_t k) {
    std::exception_ptr e;
    try {
      run(k);
    } catch (...) {
      e = std::current_exception();
    }
    const std::lock_guard<std::mutex> lock(m);
    ended[k] = 1;
    failed[k] = e;
    while (!stopped && reported < n && ended[reported]) {
      if (failed[reported]) {
        stopped = true;
        break;
      }
      try {
        report(reported);
      } catch (...) {
        failed[reported] = std::current_exception();
        stopped = true;
        break;
      }
      ++reported;
    }
  };
  const std::size_t threads =
      std::min<std::size_t>(n, static_cast<std::size_t>(std::max(1, workers)));
  // with other threads, this one starts with the last piece; the pieces before it are taken
  // in order by whichever thread is free
  const std::size_t pooled = threads > 1 ? n - 1 : n;
  auto work = [&] {
    for (std::size_t k; (k = next.fetch_add(1)) < pooled;) piece(k);
  };
  std::vector<std::thread> others;
  for (std::size_t t = 1; t < threads; ++t) others.emplace_back(work);
  if (pooled < n) piece(n - 1);
  work();
  for (auto& t : others) t.join();
  for (const auto& e : failed)
    if (e) std::rethrow_exception(e);
}

}  // namespace grainlift
