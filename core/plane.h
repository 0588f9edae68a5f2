// Planes: single-channel images with aligned, padded rows (Highway's hwy::Image, docs/design.md §12).
// Move-only. MakePlane initialises every byte, padding included, so no buffer ever holds
// uninitialised memory (docs/design.md §11).
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/parallel.h"
#include "hwy/contrib/image/image.h"

namespace ssgi {

template <class T>
using Plane = hwy::Image<T>;

// Asks the kernel to back a large buffer with transparent huge pages, so that the first touch of a
// new full-screen plane costs one fault per 2 MiB instead of one per 4 KiB. Only advice: no effect
// on contents, and none where the kernel declines it.
void AdviseHugePages(void* data, size_t bytes);

// Whether a frame's planes land on pages the process already has. glibc hands blocks above its mmap
// threshold back to the kernel on free, so a frame that allocates its planes afresh pays a page
// fault and a kernel zero-fill per 4 KiB: the cost of a one-frame CLI run. With retain = true, large
// freed blocks stay in the heap (mmap threshold at glibc's 32 MiB maximum, no trimming), so each new
// frame reuses memory already faulted in, as a renderer that keeps its buffers would, and frame
// times measure the passes: for the sweep, the benchmarks and the figures' Table 1. With retain =
// false every plane is a fresh mmap (threshold pinned at glibc's initial 128 KiB). Returns false
// where the allocator cannot be told (not glibc), for retain = true there only a loss of
// steadiness. No effect on output.
bool RetainFreedMemory(bool retain = true);

// Rows are filled in parallel bands: the fill is a new plane's first touch, and the page faults and
// kernel zeroing it triggers then run on every core.
template <class T>
Plane<T> MakePlane(size_t width, size_t height, T fill) {
  Plane<T> plane(width, height);
  AdviseHugePages(plane.bytes(), plane.bytes_per_row() * height);
  const size_t perRow = plane.bytes_per_row() / sizeof(T);
  ParallelForRowBands("plane.fill", height, [&](size_t, size_t yBegin, size_t yEnd) {
    for (size_t y = yBegin; y < yEnd; ++y) {
      T* row = plane.MutableRow(y);
      for (size_t x = 0; x < perRow; ++x) row[x] = fill;
    }
  });
  return plane;
}

// Three planes of one size: linear HDR RGB radiance and the like.
template <class T>
struct Plane3 {
  Plane<T> c[3];
};

template <class T>
Plane3<T> MakePlane3(size_t width, size_t height, T fill) {
  return Plane3<T>{{MakePlane<T>(width, height, fill), MakePlane<T>(width, height, fill),
                    MakePlane<T>(width, height, fill)}};
}

// Makes `planes` width x height, keeping their memory (and contents) when they already have that
// size: for a pass's output that its kernel overwrites pixel by pixel, so a caller that keeps its
// buffers from frame to frame pays for the allocation and the fill once.
template <class T>
void ReusePlane3(Plane3<T>& planes, size_t width, size_t height) {
  for (const Plane<T>& plane : planes.c)
    if (plane.xsize() != width || plane.ysize() != height) {
      planes = MakePlane3<T>(width, height, T(0));
      return;
    }
}

}  // namespace ssgi
