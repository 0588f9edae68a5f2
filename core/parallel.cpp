#include "core/parallel.h"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>

#include "core/check.h"

namespace ssgi {

namespace {

// body(i) for every i in [0, count) under `partitioner`, an error named after the region.
template <class Partitioner>
void ForEachIndex(std::string_view name, size_t count, const std::function<void(size_t)>& body,
                  const Partitioner& partitioner) {
  try {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1),
                      [&](const tbb::blocked_range<size_t>& range) {
                        for (size_t i = range.begin(); i != range.end(); ++i) body(i);
                      },
                      partitioner);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string(name) + ": " + e.what());
  }
}

}  // namespace

void ParallelFor(std::string_view name, size_t count, const std::function<void(size_t)>& body) {
  // simple_partitioner with grain 1: one task per item, so a slow tile never holds up a chunk of
  // cheap ones. The order items run in is free; each item's output is not.
  ForEachIndex(name, count, body, tbb::simple_partitioner());
}

size_t ParallelThreads() { return tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism); }

void ParallelForRuns(std::string_view name, const std::vector<std::vector<size_t>>& runs,
                     const std::function<void(size_t)>& body) {
  // Per run, the index of its next item from the front (low half) and one past its last from the
  // back (high half): the run's owner and the threads taking from it claim an item by one
  // compare-and-swap, so each item runs once.
  struct alignas(64) Ends {
    std::atomic<uint64_t> frontAndBack;
  };
  const auto ends = std::make_unique<Ends[]>(runs.size());
  for (size_t k = 0; k < runs.size(); ++k) {
    SSGI_CHECK(runs[k].size() <= 0xFFFFFFFFu);
    ends[k].frontAndBack = uint64_t(runs[k].size()) << 32;
  }
  const auto take = [&](size_t k, bool fromFront) -> std::optional<size_t> {
    uint64_t current = ends[k].frontAndBack.load();
    for (;;) {
      const uint64_t front = current & 0xFFFFFFFFu, back = current >> 32;
      if (front >= back) return std::nullopt;
      const uint64_t next = fromFront ? current + 1 : current - (uint64_t(1) << 32);
      if (ends[k].frontAndBack.compare_exchange_weak(current, next)) return fromFront ? front : back - 1;
    }
  };
  ForEachIndex(
      name, runs.size(),
      [&](size_t part) {
        while (const std::optional<size_t> i = take(part, true)) body(runs[part][*i]);
        for (size_t step = 1; step < runs.size(); ++step) {
          const size_t other = (part + step) % runs.size();
          while (const std::optional<size_t> i = take(other, false)) body(runs[other][*i]);
        }
      },
      tbb::static_partitioner());
}

void ParallelForRowBands(std::string_view name, size_t rows,
                         const std::function<void(size_t band, size_t yBegin, size_t yEnd)>& body) {
  ParallelFor(name, RowBandCount(rows), [&](size_t band) {
    body(band, band * kRowsPerBand, std::min(rows, (band + 1) * kRowsPerBand));
  });
}

struct ThreadLimit::Impl {
  std::optional<tbb::global_control> control;
};

ThreadLimit::ThreadLimit(int threads) : impl_(std::make_unique<Impl>()) {
  if (threads > 0) impl_->control.emplace(tbb::global_control::max_allowed_parallelism, size_t(threads));
}

ThreadLimit::~ThreadLimit() = default;

int HardwareThreads() { return tbb::info::default_concurrency(); }

}  // namespace ssgi
