#include "bench/memory_floor.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <set>
#include <utility>

#include <benchmark/benchmark.h>

#include "core/parallel.h"
#include "core/plane.h"

namespace ssgi {
namespace {

// Reads every byte of the source row and writes every byte of the destination row: the bytes both
// have are copied, the source's others folded into a word that fills the destination's others (so
// no read can be dropped by the compiler).
void TouchRow(const uint8_t* source, size_t sourceBytes, uint8_t* destination, size_t destinationBytes) {
  const size_t copied = std::min(sourceBytes, destinationBytes);
  std::memcpy(destination, source, copied);
  uint64_t folded = 0;
  for (size_t i = copied; i + sizeof(folded) <= sourceBytes; i += sizeof(folded)) {
    uint64_t word;
    std::memcpy(&word, source + i, sizeof(word));
    folded ^= word;
  }
  std::memset(destination + copied, int(folded & 0xFF), destinationBytes - copied);
}

void BM_MemoryFloor(benchmark::State& state) {
  const size_t readBytes = size_t(state.range(0));
  const size_t writeBytes = size_t(state.range(1));
  const size_t size = size_t(state.range(2));
  const ThreadLimit threads(int(state.range(3)));
  const Plane<uint8_t> source = MakePlane<uint8_t>(size * readBytes, size, uint8_t(1));
  Plane<uint8_t> destination = MakePlane<uint8_t>(size * writeBytes, size, uint8_t(0));
  for (auto _ : state) {
    ParallelForRowBands("memory_floor", size, [&](size_t, size_t yBegin, size_t yEnd) {
      for (size_t y = yBegin; y < yEnd; ++y)
        TouchRow(source.ConstRow(y), source.xsize(), destination.MutableRow(y), destination.xsize());
    });
    benchmark::ClobberMemory();
  }
  const int64_t pixels = int64_t(state.iterations()) * int64_t(size * size);
  state.SetItemsProcessed(pixels);
  state.SetBytesProcessed(pixels * int64_t(readBytes + writeBytes));
}

}  // namespace

void RegisterMemoryFloor(size_t readBytesPerPixel, size_t writeBytesPerPixel) {
  static std::set<std::pair<size_t, size_t>> registered;
  if (!registered.emplace(readBytesPerPixel, writeBytesPerPixel).second) return;
  benchmark::internal::Benchmark* floor = benchmark::RegisterBenchmark("BM_MemoryFloor", BM_MemoryFloor);
  floor->ArgNames({"read", "write", "size", "threads"});
  for (int64_t size : {1024, 2048}) {
    for (int64_t threads : {1, 2})
      floor->Args({int64_t(readBytesPerPixel), int64_t(writeBytesPerPixel), size, threads});
  }
  floor->Unit(benchmark::kMillisecond)->UseRealTime();
}

}  // namespace ssgi
