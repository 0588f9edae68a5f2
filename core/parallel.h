// The one doorway to oneTBB (docs/design.md §12: threading only in drivers, one place includes TBB).
// Work is split into fixed, index-addressed items, and each item writes only its own output, so
// results never depend on the thread count or on scheduling (docs/design.md §11).
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string_view>
#include <vector>

namespace ssgi {

// Runs body(i) for every i in [0, count), in parallel. `name` labels the region for profilers and
// error messages. Items must be independent: no item may read what another writes.
void ParallelFor(std::string_view name, size_t count, const std::function<void(size_t)>& body);

// The threads a ParallelFor may use now: ThreadLimit's, or all hardware threads.
size_t ParallelThreads();

// Runs body(item) for every item of every run, in parallel: run k front to back on one thread, which
// oneTBB is asked to keep from call to call (its static partitioner's fixed pattern), and a thread
// done with its run takes the items left in the others from their backs. For a pass of several
// regions whose runs read what the same run wrote in an earlier region or frame: that is then
// mostly in the same thread's caches, which matters where threads do not share one. Give each
// thread (ParallelThreads) a run of about equal work. Items must be independent, as for ParallelFor.
void ParallelForRuns(std::string_view name, const std::vector<std::vector<size_t>>& runs,
                     const std::function<void(size_t)>& body);

// Runs body(band, yBegin, yEnd) for the fixed bands of kRowsPerBand image rows covering [0, rows):
// the usual split of a full-screen pass. Bands depend only on `rows`, so a per-band partial result
// (a count) combined in band order is deterministic.
inline constexpr size_t kRowsPerBand = 16;
inline size_t RowBandCount(size_t rows) { return (rows + kRowsPerBand - 1) / kRowsPerBand; }
void ParallelForRowBands(std::string_view name, size_t rows,
                         const std::function<void(size_t band, size_t yBegin, size_t yEnd)>& body);

// Limits the threads every ParallelFor uses while the object lives; 0 means all hardware threads.
class ThreadLimit {
 public:
  explicit ThreadLimit(int threads);
  ~ThreadLimit();
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

int HardwareThreads();

}  // namespace ssgi
