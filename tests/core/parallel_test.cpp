// ParallelForRuns (core/parallel.h): every item of every run runs exactly once, whatever the thread
// count, the runs' lengths and their number against the threads', and a body's error names the region.
#include "core/parallel.h"

#include <catch2/catch.hpp>

#include <atomic>
#include <memory>
#include <stdexcept>
#include <vector>

namespace ssgi {
namespace {

TEST_CASE("parallel runs: each item of each run once, at 1, 2 and 3 threads", "[parallel]") {
  const std::vector<std::vector<size_t>> lengths = {{}, {0}, {1}, {5000, 3}, {3, 5000}, {0, 0, 7}, {1, 2, 3, 4, 5, 900}};
  for (const int threads : {1, 2, 3}) {
    const ThreadLimit limit(threads);
    CHECK(ParallelThreads() == size_t(threads));
    for (const std::vector<size_t>& runLengths : lengths) {
      // The items are the indices of a counter each, numbered across the runs.
      std::vector<std::vector<size_t>> runs;
      size_t items = 0;
      for (const size_t length : runLengths) {
        runs.emplace_back();
        for (size_t i = 0; i < length; ++i) runs.back().push_back(items++);
      }
      const auto counts = std::make_unique<std::atomic<int>[]>(items);
      for (size_t i = 0; i < items; ++i) counts[i] = 0;
      ParallelForRuns("test.runs", runs, [&](size_t item) {
        // Uneven work, so that threads finish their runs at different times and take from others.
        volatile size_t spin = 0;
        for (size_t k = 0; k < (item % 7) * 50; ++k) spin = spin + k;
        ++counts[item];
      });
      CAPTURE(threads, runLengths);
      size_t wrong = 0;
      for (size_t i = 0; i < items; ++i) wrong += counts[i] != 1;
      CHECK(wrong == 0);
    }
  }
}

TEST_CASE("parallel runs: an error in a body names the region", "[parallel]") {
  const ThreadLimit limit(2);
  const std::vector<std::vector<size_t>> runs = {{0, 1, 2}, {3, 4, 5}};
  CHECK_THROWS_WITH(ParallelForRuns("test.failing", runs,
                                    [](size_t item) {
                                      if (item == 4) throw std::runtime_error("item 4 failed");
                                    }),
                    "test.failing: item 4 failed");
}

}  // namespace
}  // namespace ssgi
