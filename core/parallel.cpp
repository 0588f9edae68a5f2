#include "core/parallel.h"

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>

namespace ssgi {

void ParallelFor(std::string_view name, size_t count, const std::function<void(size_t)>& body) {
  // simple_partitioner with grain 1: one task per item, so a slow tile never holds up a chunk of
  // cheap ones. The order items run in is free; each item's output is not.
  try {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1),
                      [&](const tbb::blocked_range<size_t>& range) {
                        for (size_t i = range.begin(); i != range.end(); ++i) body(i);
                      },
                      tbb::simple_partitioner());
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string(name) + ": " + e.what());
  }
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
