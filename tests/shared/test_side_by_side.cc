// side_by_side (shared/run/side_by_side.h), which runs `calibrate`'s shear-cell points and
// creeping-layer seeds at once: every piece runs once, several at a time, the reports come in
// order however the runs end, and a failure stops the reports at it and is rethrown.
#include "grainlift/shared/run/side_by_side.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

using grainlift::side_by_side;

// Ten pieces on three threads, the early ones slower (as the slow low-I points are listed
// first): each runs once, at least two at the same time, the last on this thread (where the
// continuum must make its MPI calls), and the reports are 0, 1, ..., 9.
TEST(SideBySide, EachPieceOnceSeveralAtOnceReportsInOrder) {
  constexpr std::size_t n = 10;
  const auto self = std::this_thread::get_id();
  std::thread::id last_on;
  std::vector<std::atomic<int>> runs(n);
  std::atomic<int> now{0}, most{0};
  std::mutex m;
  std::vector<std::size_t> reports;
  side_by_side(
      n, 3,
      [&](std::size_t k) {
        const int at_once = ++now;
        int seen = most.load();
        while (at_once > seen && !most.compare_exchange_weak(seen, at_once)) continue;
        std::this_thread::sleep_for(std::chrono::milliseconds(5 * static_cast<int>(n - k)));
        if (k == n - 1) last_on = std::this_thread::get_id();
        ++runs[k];
        --now;
      },
      [&](std::size_t k) {
        const std::lock_guard<std::mutex> lock(m);
        reports.push_back(k);
      });
  for (std::size_t k = 0; k < n; ++k) EXPECT_EQ(runs[k], 1) << k;
  EXPECT_GE(most, 2);
  EXPECT_LE(most, 3);
  EXPECT_EQ(last_on, self);
  ASSERT_EQ(reports.size(), n);
  for (std::size_t k = 0; k < n; ++k) EXPECT_EQ(reports[k], k);
}

// Pieces 3 and 7 fail: every piece still runs (the others' work is not lost), the reports stop
// before 3, and the exception rethrown is piece 3's, the first in order, not the first to end.
TEST(SideBySide, FirstFailureInOrderIsRethrownAndStopsTheReports) {
  constexpr std::size_t n = 10;
  std::atomic<int> ran{0};
  std::vector<std::size_t> reports;
  try {
    side_by_side(
        n, 2,
        [&](std::size_t k) {
          ++ran;
          if (k == 3) {
            std::this_thread::sleep_for(std::chrono::milliseconds(30));
            throw std::runtime_error("piece 3");
          }
          if (k == 7) throw std::runtime_error("piece 7");
        },
        [&](std::size_t k) { reports.push_back(k); });
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "piece 3");
  }
  EXPECT_EQ(ran, static_cast<int>(n));
  EXPECT_EQ(reports, (std::vector<std::size_t>{0, 1, 2}));
}

// One worker or none asked for: the pieces run on this thread alone, in order.
TEST(SideBySide, OneWorkerRunsInOrderOnThisThread) {
  const auto self = std::this_thread::get_id();
  std::vector<std::size_t> order;
  for (int workers : {1, 0}) {
    order.clear();
    side_by_side(
        4, workers,
        [&](std::size_t k) {
          EXPECT_EQ(std::this_thread::get_id(), self);
          order.push_back(k);
        },
        [](std::size_t) {});
    EXPECT_EQ(order, (std::vector<std::size_t>{0, 1, 2, 3})) << workers;
  }
}
